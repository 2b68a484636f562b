"""The book's ``glue``: a number is glued for the prose only when a page of the book cites it.

The chapters compute their numbers in loops (one per method, per ratio, per data set); the
prose cites a few of them. ``glue`` here is myst-nb's, skipping the names that no page cites
(``{glue:text}`name``` or ``{glue:md}`name``` in a chapter's text, a figure's caption or a page
of the book),
so that a chapter's stored outputs hold only the numbers a reader sees.
``tests/test_chapter_pages.py`` fails on a glued name that no page cites.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

from myst_nb import glue as _myst_glue

BOOK = Path(__file__).resolve().parent.parent

#: ``{glue}`name```, ``{glue:text}`name:.2f```, ``{glue:md}`chapters/x.ipynb::name```.
CITATION = re.compile(r"\{glue(?::\w*)?\}`([^`]+)`")


def cited_names(text: str) -> set[str]:
    """The glued names cited in one page's text (markdown)."""
    return {m.group(1).split("::")[-1].split(":")[0].strip() for m in CITATION.finditer(text)}


def book_citations(book: Path = BOOK) -> frozenset[str]:
    """Every glued name cited by a page of the book (chapters' text and markdown pages)."""
    names: set[str] = set()
    for path in sorted(book.rglob("*.md")):
        if "_build" not in path.parts:
            names |= cited_names(path.read_text(encoding="utf-8"))
    for path in sorted((book / "chapters").glob("*.ipynb")):
        for cell in json.loads(path.read_text(encoding="utf-8"))["cells"]:
            # a figure's caption lives in its code cell's metadata (``mystnb: figure: caption``)
            names |= cited_names(json.dumps(cell.get("metadata", {})))
            if cell["cell_type"] == "markdown":
                source = cell["source"]
                names |= cited_names("".join(source) if isinstance(source, list) else source)
    return frozenset(names)


CITED = book_citations()


def glue(name: str, value, display: bool = True) -> None:
    """myst-nb's ``glue``, for the names a page cites (a displayed value always)."""
    if display or name in CITED:
        _myst_glue(name, value, display=display)


def keeper(prefix: str = ""):
    """A ``keep(name, value, digits=None)`` that glues numbers under ``prefix``.

    The chapters glue many numbers for their prose; each is rounded as the chapter's tables
    print it (``digits`` decimals, or an integer when ``digits`` is None), without a ``-0.0``,
    and glued without display under ``prefix + name``.

    Examples
    --------
    >>> keep = keeper("c3_")
    >>> callable(keep)
    True
    """

    def keep(name: str, value, digits: int | None = None) -> None:
        if digits is None:
            value = int(round(float(value)))
        else:
            value = round(float(value), digits) + 0.0  # no -0.0
        glue(f"{prefix}{name}", value, display=False)

    return keep


def about(ratio: float):
    """A ratio of two times measured in one run, to the one significant figure it supports.

    Times taken on a shared machine vary by tens of percent from run to run (a ratio of 66 in
    one run of a page was 120 in another), so a page quotes such a ratio to one figure: an
    ``int`` from 1 up, a ``float`` below.

    Examples
    --------
    >>> about(118.0), about(66.0), about(1.4), about(0.034)
    (100, 70, 1, 0.03)
    """
    value = float(f"{float(ratio):.1g}")
    return int(value) if value >= 1 else value


def as_long(ratio: float, than: str) -> str:
    """A time ratio in words: "about as long as" only where the ratio is 1 to two figures
    (0.95 to 1.05); from 1.05 up to 10 to two figures ("about 1.3 times", since one figure
    would call 1.26 "as long as"); elsewhere to :func:`about`'s one figure.

    Examples
    --------
    >>> as_long(1.02, "RANSAC"), as_long(1.26, "RANSAC")
    ('about as long as RANSAC', 'about 1.3 times as long as RANSAC')
    >>> as_long(0.62, "RANSAC")
    'about 0.6 times as long as RANSAC'
    >>> as_long(118.0, "OpenCV")
    'about 100 times as long as OpenCV'
    """
    ratio = float(ratio)
    if round(ratio, 1) == 1.0:
        return f"about as long as {than}"
    figure = f"{float(f'{ratio:.2g}'):g}" if 1 <= ratio < 10 else str(about(ratio))
    return f"about {figure} times as long as {than}"
