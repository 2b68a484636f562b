"""Chapters 1-4 as a newcomer reads them: one name per algorithm, and the line fit's timed
distance stated where `fit_line` first appears.

The checks read the stored notebooks (no execution). Each was tried once on the text it guards
against (the test at the end keeps small copies of those defects).
"""

from __future__ import annotations

import json
import re
from pathlib import Path

CHAPTERS = Path(__file__).resolve().parent.parent / "book" / "chapters"

#: The page's machinery named in its text.
#: A range of glued numbers followed by "% of them": a share of a share, read oddly.
RANGE_OF_THEM = re.compile(r"\{glue:text\}`[^`]+` to \{glue:text\}`[^`]+` % of them")
LIBRARY_NAME = re.compile(r"the library's CLAP|CLAP \(the library's\)")


def _text(value) -> str:
    return "".join(value) if isinstance(value, list) else str(value)


def _notebook(stem: str) -> dict:
    return json.loads((CHAPTERS / f"{stem}.ipynb").read_text(encoding="utf-8"))


def markdown_cells(notebook: dict) -> list[str]:
    return [_text(c["source"]) for c in notebook["cells"] if c["cell_type"] == "markdown"]


def shown_outputs(notebook: dict) -> list[str]:
    """The text of the outputs a reader sees (cells not removed), tables and prints."""
    texts = []
    for cell in notebook["cells"]:
        if cell["cell_type"] != "code" or "remove-cell" in cell["metadata"].get("tags", []):
            continue
        for out in cell.get("outputs", []):
            texts.append(_text(out.get("text", "")))
            data = out.get("data", {})
            texts += [_text(data.get(k, "")) for k in ("text/markdown", "text/plain")]
    return texts


def library_name_outside(notebook: dict, allowed: str) -> list[str]:
    """Text shown with "the library's CLAP" except the cell citing ``allowed``."""
    texts = [t for t in markdown_cells(notebook) if allowed not in t] + shown_outputs(notebook)
    return [t[:80] for t in texts if LIBRARY_NAME.search(t)]


def first_fit_line_cell(notebook: dict) -> str:
    return next(t for t in markdown_cells(notebook) if "fit_line" in t)


def test_line_fitting_says_which_distance_fit_line_and_the_chapter_use_at_first_mention():
    first = first_fit_line_cell(_notebook("02_line_fitting"))
    assert "c2_for_data_metric_words" in first and "c2_fit_line_metric_words" in first


def test_localization_2d_uses_one_name_and_says_why():
    nb = _notebook("03_localization_2d")
    assert any("c3_same_words" in t for t in markdown_cells(nb))
    assert not library_name_outside(nb, "c3_same_words"), library_name_outside(
        nb, "c3_same_words")
    assert not any(RANGE_OF_THEM.search(t) for t in markdown_cells(nb))


def test_localization_3d_names_each_clap_and_says_how_they_differ():
    nb = _notebook("04_localization_3d")
    text = markdown_cells(nb)
    assert any("c4_same_words" in t for t in text)
    assert any("c4_pc_vs_paper" in t for t in text)
    # "the library's CLAP" only from the point-cloud section on (another function)
    start = next(i for i, t in enumerate(text) if t.startswith("## Point clouds"))
    early = [t[:80] for t in text[:start] if LIBRARY_NAME.search(t)
             and "c4_same_words" not in t]
    assert not early, early


def test_the_checks_catch_each_defect():
    def page(*markdown, outputs=()):
        cells = [{"cell_type": "markdown", "source": m, "metadata": {}} for m in markdown]
        cells.append({"cell_type": "code", "source": "", "metadata": {},
                      "outputs": [{"output_type": "stream", "text": o} for o in outputs]})
        return {"cells": cells}

    assert RANGE_OF_THEM.search("lost, {glue:text}`c3_a` to {glue:text}`c3_b` % of them within")
    old_2d = page("* **CLAP + EKF** (the library's CLAP inside a filter)",
                  "CLAP (paper) and the library's CLAP are {glue:md}`c3_same_words`")
    assert library_name_outside(old_2d, "c3_same_words")
    assert not library_name_outside(page("CLAP (paper) + EKF"), "c3_same_words")
    old_2 = page("{py:func}`clap_unified.fit_line`, which is fit in a LineSpace.")
    assert "c2_fit_line_metric_words" not in first_fit_line_cell(old_2)


def _cites(text: str, name: str) -> bool:
    return f"{{glue:text}}`{name}" in text  # a format spec may follow the name


def test_localization_3d_mirror_distance_order_and_bandwidths_are_said():
    nb = _notebook("04_localization_3d")
    text = markdown_cells(nb)
    prose = "".join(text)
    assert "depends only on the order of the candidates" not in prose
    assert _cites(prose, "c4_far_first")  # why the order favours the mirror image
    field = next(t for t in text if t.startswith("## The field"))
    assert _cites(field, "c4_mirror_lo") and _cites(field, "c4_mirror_hi")
    caption = next(c["metadata"]["mystnb"]["figure"]["caption"] for c in nb["cells"]
                   if c["metadata"].get("mystnb", {}).get("figure", {}).get("name")
                   == "fig-3d-cdf-global")
    assert _cites(caption, "c4_exp_mirror_lo") and not _cites(caption, "c4_mirror_m")
    assert _cites(prose, "c4_wide_words")  # the rows at another bandwidth, said


def test_localization_2d_explains_the_rise_up_to_the_best_rate():
    prose = "".join(markdown_cells(_notebook("03_localization_2d")))
    assert _cites(prose, "c3_same_verdict") and _cites(prose, "c3_same_n")
