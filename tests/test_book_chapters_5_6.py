"""Chapters 5 and 6 (homographies, stitching): names, verdicts and definitions a reader checks.

Static checks on the stored notebooks:

* the protocol's deviations from the paper are shown once, in the claims section;
* chapter 5's "What reproduces" prints no verdict beside numbers from other data (the real-scene
  claim is judged on chapter 6's panorama sets, not on homogr), and takes the claims' titles from
  the claims' own list;
* chapter 5 says nothing about the threads the page ran on;
* the outlier sweep's break (glued in the text) is the one its printed table shows under the
  definition the text gives: the lowest ratio at which fewer than half of the seeds succeed.
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


def test_the_checks_catch_each_defect():
    table = {"output_type": "display_data",
             "data": {"text/markdown": "| the paper | here | why |\n|---|---|---|"}}
    twice = {"cells": [{"cell_type": "code", "source": "x", "outputs": [table]},
                       {"cell_type": "code", "source": "chapter_claims(y)", "outputs": [table]}]}
    assert deviation_tables(twice) == (1, 1)
