"""Chapters 5 and 6 (homographies, stitching): names, verdicts and definitions a reader checks.

Static checks on the stored notebooks:

* the protocol's deviations from the paper are shown once, in the claims section;
* chapter 5's "What reproduces" prints no verdict beside numbers from other data (the real-scene
  claim is judged on chapter 6's panorama sets, not on homogr), and takes the claims' titles from
  the claims' own list;
* chapter 5 says nothing about the threads the page ran on;
* the outlier sweep's break (glued in the text) is the one its printed table shows under the
  definition the text gives: the lowest ratio at which fewer than half of the seeds succeed;
  a break that rests on exactly half of the seeds at a lower ratio is said to sit on the edge;
* a ratio or share the prose cites beside a table agrees with the value the table prints
  (within 5 %: "about 2000 times" beside 1610, or "at most 0.1 %" beside 1.3e-03, do not).
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

BOOK = Path(__file__).resolve().parent.parent / "book" / "chapters"
CH5, CH6 = BOOK / "05_homographies.ipynb", BOOK / "05b_stitching.ipynb"
DEVIATIONS = re.compile(r"\|\s*the paper( says)?\s*\|\s*here\s*\|\s*why\s*\|")


def _text(value) -> str:
    return "".join(value) if isinstance(value, list) else str(value)


def _load(path: Path) -> dict:
    return json.loads(path.read_text(encoding="utf-8"))


def _outputs(nb: dict):
    """(cell index, text) of every text output, glued values included."""
    for i, cell in enumerate(nb["cells"]):
        for o in cell.get("outputs", []):
            if o["output_type"] == "stream":
                yield i, _text(o["text"])
            for key, value in o.get("data", {}).items():
                if key.endswith("text/plain") or key.endswith("text/markdown"):
                    yield i, _text(value)


def _glued(nb: dict) -> dict:
    out = {}
    for cell in nb["cells"]:
        for o in cell.get("outputs", []):
            name = o.get("metadata", {}).get("scrapbook", {}).get("name")
            if name:
                out[name] = _text(o["data"].get("application/papermill.record/text/plain", ""))
    return out


def deviation_tables(nb: dict) -> tuple[int, int]:
    """Deviation tables shown (in the claims section, elsewhere on the page)."""
    inside = outside = 0
    for i, cell in enumerate(nb["cells"]):
        source = _text(cell["source"])
        shown = [source] if cell["cell_type"] == "markdown" else [
            text for j, text in _outputs(nb) if j == i]
        if cell["cell_type"] == "code" and "DEVIATIONS" in source and "Markdown(" in source:
            shown.append("| the paper | here | why |")  # a table built from the list
        n = sum(len(DEVIATIONS.findall(s)) for s in shown)
        if "chapter_claims(" in source:
            inside += n
        else:
            outside += n
    return inside, outside


@pytest.mark.parametrize("path", [CH5, CH6], ids=["ch5", "ch6"])
def test_deviations_shown_once(path):
    inside, outside = deviation_tables(_load(path))
    assert inside >= 1 and outside == 0, (inside, outside)


def _reproduces_rows(nb: dict) -> list[str]:
    cell = next(_text(c["source"]) for c in nb["cells"] if c["cell_type"] == "markdown"
                and _text(c["source"]).startswith("## What reproduces"))
    return [line for line in cell.splitlines() if line.startswith("| {glue")]


def test_no_verdict_beside_other_data():
    rows = _reproduces_rows(_load(CH5))
    real = [r for r in rows if "vpg_real_sre" in r.split("|")[1]]
    assert len(real) == 1 and "verdict_" not in real[0], real
    assert all("{glue:text}`title_" in r.split("|")[1] for r in rows), rows


def test_no_thread_count_claimed():
    nb = _load(CH5)
    text = "\n".join(_text(c["source"]) for c in nb["cells"] if c["cell_type"] == "markdown")
    assert not re.search(r"OpenBLAS\s+thread", text)


def _sweep_table(nb: dict) -> tuple[list[int], dict]:
    cell = next(c for c in nb["cells"] if "SWEEP = {" in _text(c["source"]))
    text = "".join(_text(o["text"]) for o in cell["outputs"] if o["output_type"] == "stream")
    lines = text.strip().splitlines()
    ratios = [int(x.rstrip("%")) for x in re.findall(r"\d+%", lines[0])]
    rates = {}
    for line in lines[1:]:
        rates[re.split(r"\s{2,}", line.strip())[0]] = [
            float(v) for v in re.findall(r"(?<![\d.])\d\.\d(?![\d.])", line)]
    return ratios, rates


def test_the_break_is_the_defined_one():
    nb = _load(CH5)
    ratios, rates = _sweep_table(nb)
    clap = rates["CLAP (paper)"]
    first = next((r for r, v in zip(ratios, clap, strict=True) if v < 0.5), None)
    glued = _glued(nb).get("sweep_clap_break", "")
    assert glued.strip("'\"") == (f"{first} %" if first is not None else "no ratio tried"), (
        glued, ratios, clap)


def _printed(nb: dict, marker: str) -> list[str]:
    """The printed lines of the one code cell whose text output contains ``marker``."""
    texts = [t for _, t in _outputs(nb) if marker in t]
    assert len(texts) == 1, (marker, len(texts))
    return texts[0].splitlines()


def _number(glued: dict, name: str) -> float:
    return float(glued[name].strip("'\""))


#: (glued name, the table's header, its row, which number of the row, scale): the prose's value
#: beside a table's
PROSE_BESIDE_TABLE = [
    ("pixel_vs_linear", "/ lie_linear", "exact Lie, pixel frame", -1, 1),
    ("rel_max_pct", "median relative difference", "median relative difference", -1, 100),
    ("cand_time_x", "/ 100 candidates", "800 ", -1, 1),
    ("r_h_clap", "homogr [ms]", "CLAP (paper) ", 1, 1),  # its homogr "/ OpenCV RANSAC"
    ("r_e_clap", "homogr [ms]", "CLAP (paper) ", 3, 1),  # its EVD "/ OpenCV RANSAC"
]
NUMBER = re.compile(r"(?<![\w.])\d+(?:\.\d+)?(?:e[-+]?\d+)?")


def rounding_defects(nb: dict, tol: float = 0.05) -> list[str]:
    """Prose values (glued) more than ``tol`` away from the value the table beside prints
    (``rel_max_pct`` is a percentage of a printed fraction: 1.3e-03 is 0.13 %)."""
    glued, defects = _glued(nb), []
    for name, header, row, k, scale in PROSE_BESIDE_TABLE:
        line = next(line for line in _printed(nb, header) if line.lstrip().startswith(row))
        printed = scale * float(NUMBER.findall(line.lstrip()[len(row):])[k])
        prose = _number(glued, name)
        if abs(prose - printed) > tol * abs(printed):
            defects.append(f"{name}: the prose says {prose:g}, the table {printed:g}")
    return defects


def test_prose_rounding_agrees_with_the_tables():
    assert rounding_defects(_load(CH5)) == []


def edge_defects(nb: dict) -> list[str]:
    """Breaks of the sweep that rest on exactly half of the seeds at a lower ratio, unsaid.

    At a ratio below a method's break where exactly half of the seeds succeed, the break sits
    on the edge of its definition (one seed fewer, and it would be there): the glued sentence
    ``sweep_edge``, cited beside the definition, must name the method, the ratio and say so."""
    ratios, rates = _sweep_table(nb)
    said = _glued(nb).get("sweep_edge", "")
    cited = any("{glue:text}`sweep_edge`" in _text(c["source"]) for c in nb["cells"]
                if c["cell_type"] == "markdown")
    defects = []
    for method, rate in rates.items():
        broke = next((i for i, v in enumerate(rate) if v < 0.5), len(rate))
        for r, v in zip(ratios[:broke], rate[:broke], strict=True):
            if v == 0.5 and not (cited and f"At {r} % {method} succeeds" in said
                                 and "exactly half" in said):
                defects.append(f"{method}: exactly half of the seeds at {r} %, not said")
    return defects


def test_a_break_on_the_edge_is_said():
    assert edge_defects(_load(CH5)) == []


def test_the_checks_catch_each_defect():
    table = {"output_type": "display_data",
             "data": {"text/markdown": "| the paper | here | why |\n|---|---|---|"}}
    twice = {"cells": [{"cell_type": "code", "source": "x", "outputs": [table]},
                       {"cell_type": "code", "source": "chapter_claims(y)", "outputs": [table]}]}
    assert deviation_tables(twice) == (1, 1)
    # the prose's rounding: one figure of 1404 ("about 1000") and of 0.13 % ("0.1 %") disagree
    nb = _load(CH5)
    assert rounding_defects(nb) == []
    for name, old in (("pixel_vs_linear", "1000"), ("rel_max_pct", "0.1")):
        for cell in nb["cells"]:
            for o in cell.get("outputs", []):
                if o.get("metadata", {}).get("scrapbook", {}).get("name") == name:
                    o["data"]["application/papermill.record/text/plain"] = old
    assert [d.split(":")[0] for d in rounding_defects(nb)] == ["pixel_vs_linear", "rel_max_pct"]
    # a break on exactly half of the seeds (CLAP (paper) at 70 %), unsaid and then said
    table = ("method               50%   70%   80%\n"
             "CLAP (paper)         0.9   0.5   0.1\n"
             "OpenCV RANSAC        1.0   1.0   0.6\n")
    sweep = {"cell_type": "code", "source": "SWEEP = {",
             "outputs": [{"output_type": "stream", "text": table}]}
    said = {"output_type": "display_data", "metadata": {"scrapbook": {"name": "sweep_edge"}},
            "data": {"application/papermill.record/text/plain":
                     "'At 70 % CLAP (paper) succeeds in 5 of 10 seeds: exactly half, ...'"}}
    text = {"cell_type": "markdown", "source": "It breaks at 80 %."}
    assert edge_defects({"cells": [sweep, text]}) == [
        "CLAP (paper): exactly half of the seeds at 70 %, not said"]
    cited = {"cell_type": "markdown", "source": "It breaks at 80 %. {glue:text}`sweep_edge`"}
    glue_cell = {"cell_type": "code", "source": "", "outputs": [said]}
    assert edge_defects({"cells": [sweep, glue_cell, cited]}) == []
