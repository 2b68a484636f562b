"""Chapters 5 and 6 (homographies, stitching): the checks of their own (issue 28).

``tests/test_chapter_pages.py`` holds every chapter to the book's rules (short cells, narrow
outputs, one output per cell, names, worked solutions); these two chapters show the
homography experiments' alternatives and pixel errors, and are also held to

* no variant key of the homography experiments (``trim_in_cluster``) in the text or an output
  (the claims blocks, checked with their generator, aside): words instead;
* no large number in exponent notation in an output (``1.7e+02 px``).
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

BOOK = Path(__file__).resolve().parent.parent / "book" / "chapters"
CHAPTERS = [BOOK / "05_homographies.ipynb", BOOK / "05b_stitching.ipynb"]
EXPONENT = re.compile(r"\d\.?\d*e\+\d\d")  # 1.7e+02: a pixel count in exponent form
#: the homography distances a reader passes as ``metric=`` (``HomographyInFrame``): API names
METRICS = {"lie", "lie_linear", "frobenius"}


def variant_keys() -> set[str]:
    """The alternatives' keys of the homography experiments that are not names of the API (a
    protocol, a distance)."""
    from clap_unified.imaging import PROTOCOLS
    from clap_unified.reproduce.exp_homography import VARIANTS

    return {v.key for v in VARIANTS} - set(PROTOCOLS) - METRICS


def _text(value) -> str:
    return "".join(value) if isinstance(value, list) else str(value)


def _shown(cell) -> str:
    """The text outputs of a code cell (a figure's and a glued value's aside)."""
    parts = []
    for o in cell.get("outputs", []):
        data = o.get("data", {})
        if o["output_type"] == "stream":
            parts.append(_text(o["text"]))
        elif "image/png" not in data and not o.get("metadata", {}).get("scrapbook"):
            parts += [_text(data[k]) for k in ("text/markdown", "text/plain") if k in data][:1]
    return "\n".join(parts)


def defects(notebook: dict) -> list[str]:
    """Variant keys and exponents that one of these chapters shows its reader."""
    found = []
    keys = re.compile(r"\b(" + "|".join(sorted(variant_keys())) + r")\b")
    for index, cell in enumerate(notebook["cells"]):
        source = _text(cell["source"])
        if cell["cell_type"] == "markdown":
            found += [f"cell {index}: variant key {m.group(0)!r}" for m in keys.finditer(source)]
            continue
        tags = set(cell.get("metadata", {}).get("tags", []))
        if "remove-cell" in tags:
            continue
        shown = _shown(cell)
        if "chapter_claims(" not in source:  # the claims' generator is checked apart
            found += [f"cell {index}: variant key {m.group(0)!r} in an output"
                      for m in keys.finditer(shown)]
        found += [f"cell {index}: exponent {m.group(0)!r} in an output"
                  for m in EXPONENT.finditer(shown)]
    return found


@pytest.mark.parametrize("path", CHAPTERS, ids=[p.stem for p in CHAPTERS])
def test_chapter_shows_no_key_and_no_exponent(path):
    problems = defects(json.loads(path.read_text(encoding="utf-8")))
    assert not problems, f"{path.name}:\n" + "\n".join(problems)


def _code(source, text="", tags=()):
    outputs = [{"output_type": "stream", "name": "stdout", "text": text}] if text else []
    return {"cell_type": "code", "source": source, "outputs": outputs,
            "metadata": {"tags": list(tags)}}


def test_the_checks_catch_each_defect():
    assert "trim_in_cluster" in variant_keys()
    bad = {"cells": [
        {"cell_type": "markdown", "source": "the variant `trim_in_cluster`"},
        _code("print(v)", "validation SRE 1.7e+02 px\n"),
        _code("print(v)", "trim_in_cluster  sensitivity  17\n"),
    ]}
    assert [d.split(":")[0] for d in defects(bad)] == ["cell 0", "cell 1", "cell 2"], (
        defects(bad))
    good = {"cells": [
        {"cell_type": "markdown", "source": "the centre trimmed within its cluster"},
        _code("print(v)", "validation SRE 170 px with metric lie_linear\n"),
        _code("show(chapter_claims(x))", "trim_in_cluster\n"),
        _code("x = 1", "trim_in_cluster 1e+05\n", ["remove-cell"]),
    ]}
    assert defects(good) == []
