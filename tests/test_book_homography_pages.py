"""Chapters 5 and 6 (homographies, stitching) read as textbook pages (issue 28).

Static checks on the stored notebooks, stricter than ``tests/test_chapter_pages.py`` for these
two chapters:

* a visible code cell holds at most :data:`MAX_VISIBLE_LINES` lines;
* a folded cell (``hide-input``: code a reader may unfold) does no glue bookkeeping; that
  belongs in removed cells (``remove-cell``, ``remove-input``);
* no stored output prints a large number in exponent notation (``1.7e+02 px``);
* the markdown does not talk about how the page was produced;
* every exercise has a solution cell whose printed output answers it in a sentence.
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


def _text(value) -> str:
    return "".join(value) if isinstance(value, list) else str(value)


def defects(notebook: dict) -> list[str]:
    """What keeps one of these chapters from reading as a textbook page."""
    found, answered = [], set()
    for index, cell in enumerate(notebook["cells"]):
        source = _text(cell["source"])
        if cell["cell_type"] == "markdown":
            found += [f"cell {index}: {m.group(0)!r}" for m in SELF_TALK.finditer(source)]
            continue
        tags = set(cell.get("metadata", {}).get("tags", []))
        if not tags & HIDDEN and len(source.splitlines()) > MAX_VISIBLE_LINES:
            found.append(f"cell {index}: visible code cell of {len(source.splitlines())} lines")
        if "hide-input" in tags and BOOKKEEPING.search(source):
            found.append(f"cell {index}: glue bookkeeping in a folded cell")
        if "remove-cell" in tags:
            continue
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
    good = {"cells": [
        exercises,
        _code("# 1. the first\nprint(x)", ["hide-cell"], "[1, 2]\nIt holds: 2 of 3.\n"),
        _code("# 2. the second\nprint(x)", ["hide-cell"], "Ordering helps here.\n"),
        _code("glue('x', 1, display=False)", ["remove-cell"]),
    ]}
    assert defects(good) == []
