"""The front page and the decision guide: the numbers the guide quotes read as in the chapters
they come from, no number typed into either page's prose, and each page says once which data
stands in for the paper's.

The checks read the pages' sources and the chapters' saved outputs (no execution).
"""

from __future__ import annotations

import json
import re
from pathlib import Path

BOOK = Path(__file__).resolve().parents[1] / "book"
#: A glue citation from another document: ``{glue:text}`chapters/NB::key:format```.
CROSS = re.compile(r"\{glue:text\}`chapters/([\w.]+)::(\w+):([^`]*)`")
#: A glue citation in a chapter: ``{glue:text}`key``` or ``{glue:text}`key:format```.
LOCAL = r"\{{glue:text\}}`{key}(?::([^`]*))?`"


def _glued(notebook: str) -> dict:
    """``{key: text}`` of what a chapter's saved outputs glue."""
    nb = json.loads((BOOK / "chapters" / notebook).read_text())
    out = {}
    for cell in nb["cells"]:
        for o in cell.get("outputs", []):
            name = o.get("metadata", {}).get("scrapbook", {}).get("name")
            if name:
                out[name] = "".join(o["data"].get("application/papermill.record/text/plain",
                                                  ""))
    return out


def _prose(notebook: str) -> str:
    nb = json.loads((BOOK / "chapters" / notebook).read_text())
    return "\n".join("".join(c["source"]) for c in nb["cells"] if c["cell_type"] == "markdown")


def _shown(text: str, fmt: str | None) -> str:
    """A glued value as a citation with format ``fmt`` prints it."""
    if not fmt or fmt == "s":
        return text.strip("'\"")
    return format(float(text), fmt)


def test_the_guide_quotes_each_number_as_its_chapter_does():
    """Same value at the same precision: a number the chapter cites as ``:.2f`` and the guide
    as ``:s`` (or the reverse) prints differently when it ends in a zero."""
    guide = (BOOK / "choosing.md").read_text()
    cited = CROSS.findall(guide)
    assert cited
    for notebook, key, fmt in cited:
        glued = _glued(notebook)
        assert key in glued, (notebook, key)
        for chapter_fmt in re.findall(LOCAL.format(key=re.escape(key)), _prose(notebook)):
            assert _shown(glued[key], fmt) == _shown(glued[key], chapter_fmt or None), (
                notebook, key, fmt, chapter_fmt)


def _typed_numbers(markdown: str) -> list[str]:
    """Numbers typed into prose: not in a glue citation, a code span, a link, a term or a
    name (S01-S12, 2D, 3D, MAGSAC++, chapter numbers)."""
    text = re.sub(r"```.*?```", "", markdown, flags=re.S)
    text = re.sub(r"\{[\w:]+\}`[^`]*`", "", text)  # glue, term, doc
    text = re.sub(r"`[^`]*`", "", text)
    text = re.sub(r"\]\([^)]*\)", "]", text)  # link targets
    text = re.sub(r"^---.*?^---", "", text, flags=re.S | re.M)  # front matter
    text = re.sub(r"\bS\d\d-S\d\d\b|\b[23]D\b|\b[Cc]hapters? \d(?:(?:, | and )\d)*\b|180 degree"
                  r"|\[\d+\]|RoboCup 2024|\(2025\)|^#.*$", "", text, flags=re.M)
    return re.findall(r"(?<![\w.])\d+(?:\.\d+)?(?![\w])", text)


def test_no_number_is_typed_into_the_guide_or_the_front_page():
    for page in ("choosing.md", "intro.md"):
        assert not _typed_numbers((BOOK / page).read_text()), (page, _typed_numbers(
            (BOOK / page).read_text()))


def test_each_page_says_once_which_data_stands_in_for_the_paper_s():
    """VPG S13-S36 is judged on real panoramas only (chapter 6); VPG S01-S12 on synthetic
    sets and homogr (chapter 5): the front page and the decision guide say so once each."""
    for page in ("intro.md", "choosing.md"):
        text = " ".join((BOOK / page).read_text().split())
        real = [m.start() for m in re.finditer(r"S13-S36", text)]
        assert len(real) == 1, (page, "S13-S36 named once")
        assert re.search(r"S13-S36[^.;]*real panoramas?[^.;]*only", text, flags=re.I), page
        assert re.search(r"S01-S12[^;]*synthetic[^;]*homogr", text), page
