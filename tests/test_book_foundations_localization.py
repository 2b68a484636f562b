"""Chapters 1-4 read as textbook pages: no talk of how the page was made, worked exercises.

The checks read the stored notebooks (no execution): every exercise of a chapter has a worked
solution cell (``# Exercise k``) with an output, and no text speaks of the machine that built the
book, of the book's tests by name, or of the regression test.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

CHAPTERS = Path(__file__).resolve().parent.parent / "book" / "chapters"
PAGES = ["01_one_abstraction", "02_line_fitting", "03_localization_2d", "04_localization_3d"]

#: How the page was produced, not the subject: the build machine, the book's own tests.
SELF_TALK = re.compile(r"machine that built|when this page was built|regression test|"
                       r"`test_\w+`|glued for the prose", flags=re.IGNORECASE)
EXERCISE_ITEM = re.compile(r"^(\d+)\. ", flags=re.MULTILINE)
SOLUTION = re.compile(r"# Exercise (\d+)\b")


def _text(value) -> str:
    return "".join(value) if isinstance(value, list) else str(value)


def _notebook(stem: str) -> dict:
    return json.loads((CHAPTERS / f"{stem}.ipynb").read_text(encoding="utf-8"))


def self_talk(notebook: dict) -> list[str]:
    """The phrases of a notebook's text and captions that speak of how the page was made."""
    found = []
    for cell in notebook["cells"]:
        texts = [json.dumps(cell.get("metadata", {}).get("mystnb", {}))]
        if cell["cell_type"] == "markdown":
            texts.append(_text(cell["source"]))
        found += [m.group(0) for t in texts for m in SELF_TALK.finditer(t)]
    return found


def exercises_and_solutions(notebook: dict) -> tuple[list[int], dict[int, int]]:
    """The numbered exercises, and for each solution cell the number of its outputs."""
    exercises, solutions = [], {}
    for cell in notebook["cells"]:
        source = _text(cell["source"])
        if cell["cell_type"] == "markdown" and "## Exercises" in source:
            listed = source.split("## Exercises", 1)[1].split("```{admonition} Hints")[0]
            exercises = [int(k) for k in EXERCISE_ITEM.findall(listed)]
        match = SOLUTION.match(source)
        if cell["cell_type"] == "code" and match:
            solutions[int(match.group(1))] = len(cell.get("outputs", []))
    return exercises, solutions


@pytest.mark.parametrize("stem", PAGES)
def test_no_talk_of_how_the_page_was_made(stem):
    assert not self_talk(_notebook(stem)), self_talk(_notebook(stem))


@pytest.mark.parametrize("stem", PAGES)
def test_every_exercise_has_a_worked_solution_with_output(stem):
    exercises, solutions = exercises_and_solutions(_notebook(stem))
    assert exercises, f"{stem}: no exercises found"
    assert sorted(solutions) == exercises, (exercises, solutions)
    assert all(n > 0 for n in solutions.values()), solutions


def test_the_checks_catch_each_defect():
    def cell(kind, source):
        return {"cell_type": kind, "source": source, "metadata": {}, "outputs": []}

    page = {"cells": [cell("markdown", "On the machine that built this page it took 2 ms."),
                      cell("markdown", "The test `test_one_frame` records it.")]}
    assert self_talk(page) == ["machine that built", "`test_one_frame`"]
    assert self_talk({"cells": [cell("markdown", "The goals are identical.")]}) == []
    page = {"cells": [cell("markdown", "## Exercises\n\n1. One.\n2. Two.\n"),
                      cell("code", "# Exercise 1: one\nprint(1)")]}
    exercises, solutions = exercises_and_solutions(page)
    assert exercises == [1, 2] and solutions == {1: 0}
