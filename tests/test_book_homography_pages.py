"""Chapters 5 and 6 (homographies, stitching) read as textbook pages (issue 28).

Static checks on the stored notebooks, stricter than ``tests/test_chapter_pages.py`` for these
two chapters:

* a visible code cell holds at most :data:`MAX_VISIBLE_LINES` lines;
* a folded cell (``hide-input``: code a reader may unfold) does no glue bookkeeping; that
  belongs in removed cells (``remove-cell``, ``remove-input``);
* no stored output prints a large number in exponent notation (``1.7e+02 px``);
* the markdown does not talk about how the page was produced;
* every exercise has a solution cell whose printed output answers it in a sentence;
* no printed line is wider than :data:`MAX_OUTPUT_WIDTH` characters, and a folded cell holds at
  most :data:`MAX_FOLDED_LINES` lines;
* a cell shows one text output (a print, or one displayed table), not a print, then a table,
  then a print;
* the reader sees no variant key (``trim_in_cluster``): words instead, and no pointer to the
  repository (``bench/``, the README);
* a printed or displayed number next to "CLAP" says which CLAP.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

BOOK = Path(__file__).resolve().parent.parent / "book" / "chapters"
CHAPTERS = [BOOK / "05_homographies.ipynb", BOOK / "05b_stitching.ipynb"]
MAX_VISIBLE_LINES = 20
HIDDEN = {"remove-input", "remove-cell", "hide-input", "hide-cell"}
BOOKKEEPING = re.compile(r"^\s*(glue|keep)\(", flags=re.MULTILINE)
EXPONENT = re.compile(r"\d\.?\d*e\+\d\d")  # 1.7e+02: a pixel count in exponent form
SELF_TALK = re.compile(r"machine that built|crippled|glued for|every build|make book|make test",
                       flags=re.IGNORECASE)
SOLUTION = re.compile(r"^# (\d)\. ")
MAX_OUTPUT_WIDTH = 88
MAX_FOLDED_LINES = 40
REPOSITORY = re.compile(r"bench/|\bREADME\b|ARCHITECTURE|earlier version", flags=re.IGNORECASE)
#: "CLAP" before a number with no bracket saying which CLAP (the claims blocks' generator has
#: its own check, :data:`clap_unified.reproduce.claims.BARE_CLAP`)
BARE_CLAP = re.compile(r"\bCLAP\b(?!\s*\()(?=[\s:]*\d)")


#: the homography distances a reader passes as ``metric=`` (``HomographyInFrame``): API names
METRICS = {"lie", "lie_linear", "frobenius"}


def variant_keys() -> set[str]:
    """The alternatives' keys of the homography experiments that are not names of the API (a
    protocol, a distance)."""
    from clap_unified.imaging import PROTOCOLS
    from clap_unified.reproduce.exp_homography import VARIANTS

    return {v.key for v in VARIANTS} - set(PROTOCOLS) - METRICS


def _text_blocks(outputs) -> list[tuple[str, str]]:
    """(kind, text) of the text outputs, consecutive prints of one stream joined."""
    blocks = []
    for o in outputs:
        if o["output_type"] == "stream":
            kind, text = "stream:" + o.get("name", ""), _text(o["text"])
        elif "image/png" in o.get("data", {}) or o.get("metadata", {}).get("scrapbook"):
            continue
        elif "text/markdown" in o.get("data", {}):
            kind, text = "markdown", _text(o["data"]["text/markdown"])
        elif "text/plain" in o.get("data", {}):
            kind, text = "plain", _text(o["data"]["text/plain"])
        else:
            continue
        if blocks and blocks[-1][0] == kind and kind.startswith("stream"):
            blocks[-1] = (kind, blocks[-1][1] + text)
        else:
            blocks.append((kind, text))
    return blocks


def _text(value) -> str:
    return "".join(value) if isinstance(value, list) else str(value)


def defects(notebook: dict) -> list[str]:
    """What keeps one of these chapters from reading as a textbook page."""
    found, answered = [], set()
    keys = re.compile(r"\b(" + "|".join(sorted(variant_keys())) + r")\b")
    for index, cell in enumerate(notebook["cells"]):
        source = _text(cell["source"])
        if cell["cell_type"] == "markdown":
            found += [f"cell {index}: {m.group(0)!r}" for m in SELF_TALK.finditer(source)]
            found += [f"cell {index}: {m.group(0)!r}" for m in REPOSITORY.finditer(source)]
            found += [f"cell {index}: variant key {m.group(0)!r}" for m in keys.finditer(source)]
            continue
        tags = set(cell.get("metadata", {}).get("tags", []))
        if not tags & HIDDEN and len(source.splitlines()) > MAX_VISIBLE_LINES:
            found.append(f"cell {index}: visible code cell of {len(source.splitlines())} lines")
        if "hide-input" in tags and BOOKKEEPING.search(source):
            found.append(f"cell {index}: glue bookkeeping in a folded cell")
        if "hide-input" in tags and len(source.splitlines()) > MAX_FOLDED_LINES:
            found.append(f"cell {index}: folded cell of {len(source.splitlines())} lines")
        if "remove-cell" in tags:
            continue
        blocks = _text_blocks(cell.get("outputs", []))
        if len(blocks) > 1:
            found.append(f"cell {index}: {len(blocks)} text outputs "
                         f"({', '.join(k for k, _ in blocks)})")
        claims_block = "chapter_claims(" in source  # the claims' generator is checked apart
        for kind, shown in blocks:
            if kind.startswith("stream"):
                found += [f"cell {index}: an output line of {len(line)} characters"
                          for line in shown.splitlines() if len(line) > MAX_OUTPUT_WIDTH]
            if not claims_block:
                found += [f"cell {index}: variant key {m.group(0)!r} in an output"
                          for m in keys.finditer(shown)]
                found += [f"cell {index}: a bare CLAP before a number: "
                          f"{shown[max(0, m.start() - 20):m.end() + 20]!r}"
                          for m in BARE_CLAP.finditer(shown)]
        text = "".join(_text(o.get("text", "")) for o in cell.get("outputs", []))
        found += [f"cell {index}: exponent {m.group(0)!r} in an output"
                  for m in EXPONENT.finditer(text)]
        solution = SOLUTION.match(source)
        if solution and re.search(r"[a-z][^\n]*[.!?]\s*$", text.strip(), flags=re.MULTILINE):
            answered.add(int(solution.group(1)))
    exercises = {int(n) for cell in notebook["cells"] if cell["cell_type"] == "markdown"
                 and "## Exercises" in _text(cell["source"])
                 for n in re.findall(r"^(\d)\. ", _text(cell["source"]).split("## Exercises")[1]
                                     .split("```")[0], flags=re.MULTILINE)}
    found += [f"exercise {n}: no solution printing a sentence"
              for n in sorted(exercises - answered)]
    return found


@pytest.mark.parametrize("path", CHAPTERS, ids=[p.stem for p in CHAPTERS])
def test_chapter_reads_as_a_textbook_page(path):
    problems = defects(json.loads(path.read_text(encoding="utf-8")))
    assert not problems, f"{path.name}:\n" + "\n".join(problems)


def _code(source, tags=(), text=""):
    outputs = [{"output_type": "stream", "name": "stdout", "text": text}] if text else []
    return {"cell_type": "code", "source": source, "outputs": outputs,
            "metadata": {"tags": list(tags)}}


def test_the_checks_catch_each_defect():
    exercises = {"cell_type": "markdown", "source": "## Exercises\n\n1. Do this.\n2. And that.\n"}
    bad = {"cells": [
        {"cell_type": "markdown", "source": "timed on the machine that built this book"},
        _code("\n".join(f"x{i} = {i}" for i in range(MAX_VISIBLE_LINES + 1))),
        _code("glue('x', 1, display=False)", ["hide-input"]),
        _code("print(v)", text="validation SRE 1.7e+02 px\n"),
        exercises,
        _code("# 1. the first\nprint(x)", ["hide-cell"], "[1, 2, 3]\n"),
    ]}
    assert len(defects(bad)) == 6, defects(bad)
    stream = {"output_type": "stream", "name": "stdout", "text": "x\n"}
    table = {"output_type": "display_data", "data": {"text/markdown": "| a |"}}
    worse = {"cells": [
        {"cell_type": "markdown", "source": "as `bench/bench_x.py` measures"},
        {"cell_type": "markdown", "source": "the variant `trim_in_cluster`"},
        _code("\n".join(f"x{i} = {i}" for i in range(MAX_FOLDED_LINES + 1)), ["hide-input"]),
        _code("print(x)", text="y" * (MAX_OUTPUT_WIDTH + 1) + "\n"),
        {**_code("f()"), "outputs": [stream, table, stream]},
        _code("print(v)", text="polish_both  sensitivity  17\n"),
        _code("print(v)", text="CLAP 0.53 px, RANSAC 0.70 px\n"),
    ]}
    assert [d.split(":")[0] for d in defects(worse)] == [f"cell {i}" for i in range(7)], (
        defects(worse))
    assert defects({"cells": [
        _code("print(v)", text="CLAP (paper) 0.53 px; the protocol clap_densest\n"),
        {**_code("f()"), "outputs": [stream, stream]},
        _code("show(chapter_claims(x))", text="CLAP closer on 1\n")]}) == []
    good = {"cells": [
        exercises,
        _code("# 1. the first\nprint(x)", ["hide-cell"], "[1, 2]\nIt holds: 2 of 3.\n"),
        _code("# 2. the second\nprint(x)", ["hide-cell"], "Ordering helps here.\n"),
        _code("glue('x', 1, display=False)", ["remove-cell"]),
    ]}
    assert defects(good) == []
