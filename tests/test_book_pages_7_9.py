"""Chapters 7-9 read as textbook pages: what ``test_chapter_pages`` checks, and more.

* a folded-but-viewable cell (``hide-input``) holds code a reader may unfold (a table, a
  figure), never the ``glue``/``keep`` bookkeeping, which goes to ``remove-cell`` cells;
* a cell prints one block of output, not several (a loop prints its lines at once);
* every exercise has a worked solution: a folded cell (``hide-cell``) opening with the
  exercise's number, executed (it has output), whose output ends on a sentence;
* no words about how the page was made (the machine that built it, what "we tried"), no
  pointer to the repository's scripts (``bench/...``), which a reader of the book has not;
* one name per algorithm: never "default CLAP" or "CLAP (library default)" (the library's is
  "CLAP (the library's)"), never a synthetic pair's code name ("r=0.08 decoy=0.04") shown;
* no printed line wider than 88 characters (a cell whose output is folded by ``hide-output``,
  the library's own source, is exempt).
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

CHAPTERS = Path(__file__).resolve().parent.parent / "book" / "chapters"
PAGES = ("05c_many_answers", "06_performance", "07_your_data")
BOOKKEEPING = re.compile(r"^\s*(glue|keep)\(", flags=re.MULTILINE)
SELF_TALK = re.compile(r"\bwe tried\b|\bmachine that built\b|\bglued for\b|\bcrippled\b|"
                       r"\ban earlier version\b|\bthis book was built\b", flags=re.IGNORECASE)
EXERCISE = re.compile(r"^(\d+)\. ", flags=re.MULTILINE)
REPOSITORY = re.compile(r"\bbench/\w+\.py|\(see the README\)|ARCHITECTURE\.md")
NAMING = re.compile(r"\bdefault CLAP\b|CLAP \(library default\)|\br=0\.\d+ decoy=0")
WIDTH = 88


def _text(value) -> str:
    return "".join(value) if isinstance(value, list) else str(value)


def _tags(cell) -> set[str]:
    return set(cell.get("metadata", {}).get("tags", []))


def _stdout(cell) -> str:
    return "".join(_text(o["text"]) for o in cell.get("outputs", [])
                   if o["output_type"] == "stream" and o.get("name") == "stdout")


def _shown(cell) -> str:
    """What a code cell shows: its printed text, its Markdown and plain-text results."""
    parts = [_stdout(cell)]
    for o in cell.get("outputs", []):
        data = o.get("data", {})
        parts += [_text(data[k]) for k in ("text/markdown", "text/plain") if k in data]
    return "\n".join(parts)


def page_defects(notebook: dict) -> list[str]:
    """What keeps one of these chapters (parsed JSON) from reading as a textbook page."""
    defects = []
    cells = notebook["cells"]
    for index, cell in enumerate(cells):
        where = f"cell {index}"
        if cell["cell_type"] == "markdown":
            text = _text(cell["source"])
            defects += [f"{where}: {m.group(0)!r}" for m in SELF_TALK.finditer(text)]
            defects += [f"{where}: {m.group(0)!r}" for m in REPOSITORY.finditer(text)]
            defects += [f"{where}: name {m.group(0)!r}" for m in NAMING.finditer(text)]
            continue
        tags = _tags(cell)
        shown = _shown(cell)
        defects += [f"{where}: output {m.group(0)!r}" for m in REPOSITORY.finditer(shown)]
        defects += [f"{where}: name {m.group(0)!r}" for m in NAMING.finditer(shown)]
        if "hide-output" not in tags:
            wide = [line for line in _stdout(cell).splitlines() if len(line) > WIDTH]
            defects += [f"{where}: a printed line of {len(line)} characters" for line in wide]
        if "hide-input" in tags and BOOKKEEPING.search(_text(cell["source"])):
            defects.append(f"{where}: glue bookkeeping in a folded, viewable cell")
        streams = [o for o in cell.get("outputs", []) if o["output_type"] == "stream"
                   and o.get("name") == "stdout"]
        if len(streams) > 1:
            defects.append(f"{where}: {len(streams)} blocks of output")
    exercises = [k for k, c in enumerate(cells) if c["cell_type"] == "markdown"
                 and "## Exercises" in _text(c["source"])]
    for start in exercises:
        text = _text(cells[start]["source"]).split("## Exercises", 1)[1]
        numbers = EXERCISE.findall(text.split("```", 1)[0])  # the questions, not the hints
        solutions: dict[str, list[int]] = {}
        number = None
        for index in range(start + 1, len(cells)):
            cell = cells[index]
            if cell["cell_type"] == "code" and "hide-cell" in _tags(cell):
                match = re.match(r"#\s*(\d+)\.", _text(cell["source"]))
                number = match.group(1) if match else number  # a solution's later cells
                if number is not None:
                    solutions.setdefault(number, []).append(index)
        for number in numbers:
            if number not in solutions:
                defects.append(f"exercise {number}: no worked solution (a hide-cell "
                               f"'# {number}.')")
                continue
            printed = [_stdout(cells[k]).strip() for k in solutions[number]]
            if not any(printed):
                defects.append(f"exercise {number}: its solution prints nothing")
            elif not any(p.endswith(".") for p in printed):
                last = [p for p in printed if p][-1].splitlines()[-1]
                defects.append(f"exercise {number}: its solution's output ends without a "
                               f"sentence: {last[:60]!r}")
    return defects


@pytest.mark.parametrize("stem", PAGES)
def test_chapter_reads_as_a_page(stem):
    notebook = json.loads((CHAPTERS / f"{stem}.ipynb").read_text(encoding="utf-8"))
    defects = page_defects(notebook)
    assert not defects, f"{stem}:\n" + "\n".join(defects)


def _cell(kind, source, tags=(), outputs=()):
    cell = {"cell_type": kind, "source": source, "metadata": {"tags": list(tags)}}
    if kind == "code":
        cell["outputs"] = [{"output_type": "stream", "name": "stdout", "text": t}
                           for t in outputs]
    return cell


def test_the_checks_catch_each_defect():
    notebook = {"cells": [
        _cell("markdown", "Across the kernels we tried, nothing moved."),
        _cell("code", "x = 1\nkeep('x', x)", tags=["hide-input"]),
        _cell("code", "print(1)\nprint(2)", outputs=["1\n", "2\n"]),
        _cell("markdown", "## Exercises\n\n1. One?\n2. Two?\n3. Three?"),
        _cell("code", "# 1. one\nprint('one')", tags=["hide-cell"], outputs=["one\n"]),
        _cell("code", "# 2. two", tags=["hide-cell"]),
        _cell("markdown", "As `python bench/bench_budget.py` shows, the default CLAP wins."),
        _cell("code", "print(name)", outputs=["synthetic r=0.08 decoy=0.04 #1\n"]),
        _cell("code", "print(wide)", outputs=["x" * 89 + "\n"]),
        _cell("code", "print(source)", tags=["hide-output"], outputs=["x" * 89 + "\n"]),
    ]}
    defects = page_defects(notebook)
    assert [d.split(":")[0] for d in defects] == [
        "cell 0", "cell 1", "cell 2", "cell 6", "cell 6", "cell 7", "cell 8",
        "exercise 1", "exercise 2", "exercise 3"], defects
    assert "bench/bench_budget.py" in defects[3] and "default CLAP" in defects[4]
    assert "r=0.08 decoy=0" in defects[5] and "89 characters" in defects[6]
    defects = [d for d in defects if not d.startswith("cell 6")
               and not d.startswith("cell 7") and not d.startswith("cell 8")]
    assert "we tried" in defects[0]
    assert "bookkeeping" in defects[1]
    assert "2 blocks" in defects[2]
    assert "without a sentence" in defects[3]
    assert "prints nothing" in defects[4]
    assert "no worked solution" in defects[5]
    notebook["cells"][4]["outputs"][0]["text"] = "one: the hint holds.\n"
    assert "exercise 1" not in " ".join(page_defects(notebook))
