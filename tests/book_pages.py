"""Readers of a chapter's stored notebook shared by the chapter tests: what it glues and the
Markdown tables it shows."""

from __future__ import annotations

import re


def _text(value) -> str:
    return "".join(value) if isinstance(value, list) else str(value)


def glued_values(notebook: dict) -> dict[str, str]:
    """``{name: plain text}`` of every value a stored notebook (parsed JSON) glues."""
    values = {}
    for cell in notebook["cells"]:
        for o in cell.get("outputs", []):
            name = o.get("metadata", {}).get("scrapbook", {}).get("name")
            if name:
                values[name] = _text(o["data"].get("application/papermill.record/text/plain",
                                                   ""))
    return values


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
