"""The API reference pages of the book cover every public module of the package."""

from __future__ import annotations

import pkgutil
import re
from pathlib import Path

import clap_unified

PAGES = Path(__file__).resolve().parents[1] / "book" / "reference" / "api"


def _public_modules() -> set[str]:
    names = {"clap_unified"}
    for info in pkgutil.walk_packages(clap_unified.__path__, "clap_unified."):
        if not any(part.startswith("_") for part in info.name.split(".")):
            names.add(info.name)
    return names


def test_every_public_module_has_a_section():
    documented = set()
    for page in PAGES.glob("*.md"):
        documented |= set(re.findall(r"\.\. automodule:: (\S+)", page.read_text()))
    missing = sorted(_public_modules() - documented)
    assert not missing, f"modules missing from book/reference/api/*.md: {missing}"


def test_every_api_page_is_in_the_table_of_contents():
    toc = (PAGES.parents[1] / "_toc.yml").read_text()
    for page in PAGES.glob("*.md"):
        assert f"reference/api/{page.stem}" in toc, page.name
