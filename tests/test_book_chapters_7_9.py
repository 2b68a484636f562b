"""Chapters 7-9 as a newcomer checks them against their own tables.

* a table column of numbers holds numbers or a dash, never words ("found", "19 sequences",
  "see (1)"): the words go to a note under the table;
* a count the prose states is made on the values the table beside it prints (rounded first,
  then counted): chapter 7's "below 3 %" against its table of errors per sequence;
* chapter 8 says which distance and budget the timed line fit uses, from ``fit_line``'s own
  defaults, and figure 8.3 is measured on several seeds.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

CHAPTERS = Path(__file__).resolve().parent.parent / "book" / "chapters"
PAGES = ("05c_many_answers", "06_performance", "07_your_data")
NUMBER = re.compile(r"^[+-]?\d+(\.\d+)?( / [+-]?\d+(\.\d+)?)?$")
CLAIMS_TEXT = re.compile(r"chapter_claims\(|verdict_lines\(")  # the experiments' own words


def _text(value) -> str:
    return "".join(value) if isinstance(value, list) else str(value)


def _load(stem: str) -> dict:
    return json.loads((CHAPTERS / f"{stem}.ipynb").read_text(encoding="utf-8"))


def _outputs(cell) -> list[str]:
    """A code cell's printed text and its Markdown results."""
    shown = []
    for o in cell.get("outputs", []):
        if o["output_type"] == "stream":
            shown.append(_text(o["text"]))
        shown += [_text(o["data"][k]) for k in ("text/markdown",) if k in o.get("data", {})]
    return shown


def markdown_tables(text: str) -> list[list[list[str]]]:
    """The Markdown tables in ``text``: rows of stripped cells, the header first."""
    tables, current = [], []
    for line in text.splitlines() + [""]:
        if line.startswith("|") and line.rstrip().endswith("|"):
            cells = [c.strip() for c in line.strip()[1:-1].split("|")]
            if not all(re.fullmatch(r":?-+:?", c) for c in cells):
                current.append(cells)
        elif current:
            tables.append(current)
            current = []
    return tables


def word_cells(table: list[list[str]]) -> list[str]:
    """Cells holding words in a column whose other cells are numbers (or dashes)."""
    header, rows = table[0], table[1:]
    bad = []
    for k, name in enumerate(header):
        column = [r[k] for r in rows if k < len(r)]
        numeric = [c for c in column if NUMBER.match(c)]
        if len(numeric) * 2 < len(column):  # a column of words (names, yes/no)
            continue
        bad += [f"{name!r}: {c!r}" for c in column if c != "-" and not NUMBER.match(c)]
    return bad


@pytest.mark.parametrize("stem", PAGES)
def test_numeric_columns_hold_numbers_or_a_dash(stem):
    bad = [cell for c in _load(stem)["cells"] if c["cell_type"] == "code"
           for out in _outputs(c) for table in markdown_tables(out) for cell in word_cells(table)]
    assert not bad, f"{stem}: words in a column of numbers: {bad}"


def test_word_cells_catch_words_among_numbers():
    table = markdown_tables("| method | mean | found |\n|---|---|---|\n| a | 5.0 | 2.4 |\n"
                            "| b | 5.1 | 2.5 |\n| c | 7.0 | 3.0 |\n"
                            "| Progressive-X | 6.6 | found |\n| d | - | 19 sequences |\n")[0]
    assert word_cells(table) == ["'found': 'found'", "'found': '19 sequences'"]
    assert word_cells([["set", "as many"], ["homogr", "no"], ["EVD", "yes"]]) == []


def _glued(notebook: dict) -> dict[str, str]:
    values = {}
    for cell in notebook["cells"]:
        for o in cell.get("outputs", []):
            name = o.get("metadata", {}).get("scrapbook", {}).get("name")
            if name:
                plain = o["data"].get("application/papermill.record/text/plain")
                values[name] = plain
    return values


def test_chapter7_count_below_3_is_made_on_the_printed_table():
    nb = _load("05c_many_answers")
    per_sequence = next(t for c in nb["cells"] if c["cell_type"] == "code"
                        for out in _outputs(c) for t in markdown_tables(out)
                        if t[0][0] == "sequence")
    column = per_sequence[0].index("CLAP (the library's)")
    printed = [float(row[column]) for row in per_sequence[1:]]
    assert int(_glued(nb)["mm_n_below_3"]) == sum(v < 3 for v in printed)
    prose = "".join(_text(c["source"]) for c in nb["cells"] if c["cell_type"] == "markdown")
    assert "below 3 % on {glue:text}`mm_n_below_3`" in prose


def test_chapter8_says_what_the_timed_line_fit_uses():
    nb = _load("06_performance")
    glued = _glued(nb)
    prose = "".join(_text(c["source"]) for c in nb["cells"] if c["cell_type"] == "markdown")
    for name in ("c6_line_metric", "c6_space_metric", "c6_line_budget"):
        assert f"{{glue:text}}`{name}`" in prose, name
    assert glued["c6_line_metric"] != glued["c6_space_metric"]  # the two timed distances
    assert int(glued["c6_scale_seeds"]) > 1  # figure 8.3: medians over several seeds


def _prose(notebook: dict) -> str:
    return "".join(_text(c["source"]) for c in notebook["cells"] if c["cell_type"] == "markdown")


def _cites(text: str, name: str) -> bool:
    return f"{{glue:text}}`{name}`" in text


def rounding_decides(table: list[list[str]]) -> list[str]:
    """Rows of chapter 8's table beside the best peer whose printed value equals its threshold
    but whose verdict does not say that it lies within rounding of it."""
    header, bad = table[0], []
    for row in table[1:]:
        for value, verdict, limit in (("error / best peer", "within 1.1x", 1.1),
                                      ("time / OpenCV RANSAC", "as fast", 1.0)):
            if (float(row[header.index(value)]) == limit
                    and "within rounding" not in row[header.index(verdict)]):
                bad.append(f"{row[0]}, {row[1]}: {value} {row[header.index(value)]}")
    return bad


def test_chapter8_parity_with_the_peers_is_computed_and_owns_its_help():
    prose = _prose(_load("06_performance"))
    assert "it alone stays below" not in prose
    for name in ("c6_below_words", "c6_budget_factor", "c6_ab_polish_homogr",
                 "c6_ab_default_homogr", "c6_ab_polish_synthetic", "c6_ab_default_synthetic"):
        assert _cites(prose, name), name


def test_chapter8_beside_the_best_peer_is_judged_unrounded():
    nb = _load("06_performance")
    beside = next(t for c in nb["cells"] if c["cell_type"] == "code" for out in _outputs(c)
                  for t in markdown_tables(out) if "as fast" in t[0])
    assert not rounding_decides(beside), rounding_decides(beside)


def test_chapter8_says_what_its_list_of_clusters_holds_and_each_3d_budget():
    nb = _load("06_performance")
    texts = [_text(c["source"]) for c in nb["cells"] if c["cell_type"] == "markdown"]
    assert "What clustering gives that consensus alone does not" not in "".join(texts)
    assert sum(_cites(t, "c6_list_words") for t in texts) >= 2  # section 8.4 and the verdict
    o3d = next(t for t in texts if _cites(t, "c6_o3d_ratio") and "Open3D" in t
               and not t.lstrip().startswith("## Verdict"))
    assert _cites(o3d, "c6_o3d_iter") and _cites(o3d, "c6_clap3d_n")


def test_chapter7_says_what_the_papers_reading_changes_and_counts_every_seed():
    nb = _load("05c_many_answers")
    prose = _prose(nb)
    assert "which has none of the parts" not in prose
    assert "changes all of them at once" not in prose
    assert _cites(prose, "mm_paper_changed") and _cites(prose, "mm_paper_kept_words")
    diagnosis = next(t for c in nb["cells"] if c["cell_type"] == "code"
                     for out in _outputs(c) for t in markdown_tables(out)
                     if t[0][-1].startswith("seeds:"))
    totals = {sum(int(v) for v in row[-1].split(" / ")) for row in diagnosis[1:]}
    assert len(totals) == 1, f"seeds unaccounted for: {totals}"


def test_the_chapter8_checks_catch_the_old_tables():
    old = markdown_tables(
        "| set | method | right / best peer | as many | error / best peer | within 1.1x | "
        "time / OpenCV RANSAC | as fast |\n|---|---|---|---|---|---|---|---|\n"
        "| EVD | CLAP | 11.7 / 14.0 | no | 1.32 | no | 1.0 | yes |\n"
        "| synthetic | CLAP | 8.3 / 12.0 | no | 1.10 | no | 0.8 | yes |\n")[0]
    assert len(rounding_decides(old)) == 2
    new = [row[:] for row in old]
    new[1][7], new[2][5] = "no (1.034, within rounding)", "no (1.1040, within rounding)"
    assert not rounding_decides(new)
