"""Every chapter of the book reads as a textbook page (issue 28).

The check is static: it reads each ``book/chapters/*.ipynb`` with its stored outputs (the
ones nbval compares and the book shows) and fails on

* a visible code cell (not tagged ``remove-input``, ``remove-cell`` or ``hide-input``)
  longer than :data:`MAX_VISIBLE_LINES` lines: teaching code is short;
* a stored output line (a stream, or a ``text/plain`` result) wider than
  :data:`MAX_OUTPUT_WIDTH` characters: it would scroll out of the text column (an output
  folded under ``hide-output``, such as a printed source file, may scroll);
* ``stderr`` output containing ``Warning``: warnings are fixed at their cause;
* a ``text/plain`` result with no richer form beside it that is a bare object repr
  (``Text(...)``, ``<matplotlib...>``, ``<Figure ...>``): a plotting cell's last value
  leaking onto the page;
* a visible code cell that glues numbers for the prose (``glue(...)`` or the chapters'
  ``keep(...)``): bookkeeping belongs in hidden cells.

A last check reads the whole book: every number a chapter glues is cited by some page
(``{glue:text}`name```), so the stored outputs hold no number nobody reads.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

BOOK = Path(__file__).resolve().parent.parent / "book" / "chapters"
CHAPTERS = sorted(BOOK.glob("*.ipynb"))

#: Tags under which a code cell's source is not shown as it stands (removed or folded).
HIDDEN = {"remove-input", "remove-cell", "hide-input", "hide-cell"}
MAX_VISIBLE_LINES = 20
MAX_OUTPUT_WIDTH = 88
BARE_REPR = re.compile(r"\s*(Text\(|<matplotlib|<Figure)")
BOOKKEEPING = re.compile(r"^\s*(glue|keep)\(", flags=re.MULTILINE)
CITATION = re.compile(r"\{glue(?::\w*)?\}`([^`]+)`")

def _text(value) -> str:
    return "".join(value) if isinstance(value, list) else str(value)


def page_defects(notebook: dict) -> list[str]:
    """What keeps one notebook (parsed JSON) from reading as a textbook page."""
    defects = []
    for index, cell in enumerate(notebook["cells"]):
        if cell["cell_type"] != "code":
            continue
        where = f"cell {index}"
        tags = set(cell.get("metadata", {}).get("tags", []))
        n_lines = len(_text(cell["source"]).splitlines())
        if not tags & HIDDEN and n_lines > MAX_VISIBLE_LINES:
            defects.append(f"{where}: visible code cell of {n_lines} lines "
                           f"(at most {MAX_VISIBLE_LINES})")
        if not tags & HIDDEN and BOOKKEEPING.search(_text(cell["source"])):
            defects.append(f"{where}: glue bookkeeping in a visible code cell")
        for output in cell.get("outputs", []):
            texts = []
            if output["output_type"] == "stream":
                text = _text(output["text"])
                texts.append(text)
                if output.get("name") == "stderr" and "Warning" in text:
                    defects.append(f"{where}: a warning on stderr: {text.strip()[:80]!r}")
            elif "text/plain" in output.get("data", {}):
                text = _text(output["data"]["text/plain"])
                texts.append(text)
                richer = set(output["data"]) - {"text/plain"}
                if not richer and BARE_REPR.match(text):
                    defects.append(f"{where}: a bare object repr: {text.strip()[:60]!r}")
            for text in texts if "hide-output" not in tags else ():  # folded: scrolls
                for line in text.splitlines():
                    if len(line) > MAX_OUTPUT_WIDTH:
                        defects.append(f"{where}: an output line of {len(line)} characters "
                                       f"(at most {MAX_OUTPUT_WIDTH}): {line[:60]!r}...")
    return defects


def _param(path: Path):
    return pytest.param(path, id=path.stem)


def test_the_chapters_are_found():
    assert len(CHAPTERS) >= 9, CHAPTERS


@pytest.mark.parametrize("path", [_param(p) for p in CHAPTERS])
def test_chapter_reads_as_a_page(path):
    defects = page_defects(json.loads(path.read_text(encoding="utf-8")))
    assert not defects, f"{path.name}:\n" + "\n".join(defects)


def _cell(source, outputs=(), tags=()):
    return {"cell_type": "code", "source": source, "outputs": list(outputs),
            "metadata": {"tags": list(tags)}}


def test_the_checks_catch_each_defect():
    long_source = "\n".join(f"x{i} = {i}" for i in range(MAX_VISIBLE_LINES + 1))
    wide = {"output_type": "stream", "name": "stdout",
            "text": "x" * (MAX_OUTPUT_WIDTH + 1) + "\n"}
    warning = {"output_type": "stream", "name": "stderr",
               "text": "UserWarning: The figure layout has changed to tight\n"}
    bare = {"output_type": "execute_result",
            "data": {"text/plain": "Text(0.5, 1.0, 'title')"}}
    figure = {"output_type": "display_data",
              "data": {"text/plain": "<Figure size 640x480 with 1 Axes>",
                       "image/png": "..."}}
    cells = [_cell(long_source), _cell("print()", [wide]), _cell("f()", [warning]),
             _cell("ax.set_title('t')", [bare]), _cell("plt.show()", [figure]),
             _cell(long_source, tags=["hide-input"]),
             _cell(long_source, tags=["remove-cell"]),
             {"cell_type": "markdown", "source": "y" * 200, "metadata": {}},
             _cell('plt.show()\nkeep("n_lines", 4)'),
             _cell('keep("n_lines", 4)', tags=["remove-cell"]),
             _cell("print(source)", [wide], tags=["hide-output"])]  # folded: may scroll
    defects = page_defects({"cells": cells})
    assert [d.split(":")[0] for d in defects] == ["cell 0", "cell 1", "cell 2", "cell 3",
                                                  "cell 8"]
    assert f"visible code cell of {MAX_VISIBLE_LINES + 1} lines" in defects[0]
    assert f"{MAX_OUTPUT_WIDTH + 1} characters" in defects[1]
    assert "warning" in defects[2]
    assert "bare object repr" in defects[3]
    assert "bookkeeping" in defects[4]


def _markdown(source: str) -> dict:
    return {"cell_type": "markdown", "source": source, "metadata": {}}


def _glued(name: str) -> dict:
    return {"output_type": "display_data", "metadata": {"scrapbook": {"name": name}},
            "data": {"text/plain": "1"}}


def uncited_glue(notebooks: dict[str, dict], pages: list[str]) -> list[str]:
    """The glued names (in the notebooks' stored outputs) that no page cites."""
    cited = set()
    texts = list(pages) + [_text(c["source"]) for nb in notebooks.values()
                           for c in nb["cells"] if c["cell_type"] == "markdown"]
    # a figure's caption (``mystnb: figure: caption``) cites from its cell's metadata
    texts += [json.dumps(c.get("metadata", {})) for nb in notebooks.values()
              for c in nb["cells"]]
    for text in texts:
        cited |= {m.group(1).split("::")[-1].split(":")[0].strip()
                  for m in CITATION.finditer(text)}
    uncited = []
    for name, nb in notebooks.items():
        for cell in nb["cells"]:
            for output in cell.get("outputs", []):
                glued = output.get("metadata", {}).get("scrapbook", {}).get("name")
                if glued and glued not in cited:
                    uncited.append(f"{name}: {glued}")
    return uncited


def test_every_glued_number_is_cited_by_a_page():
    notebooks = {p.name: json.loads(p.read_text(encoding="utf-8")) for p in CHAPTERS}
    pages = [p.read_text(encoding="utf-8") for p in BOOK.parent.rglob("*.md")
             if "_build" not in p.parts]
    uncited = uncited_glue(notebooks, pages)
    assert not uncited, f"{len(uncited)} glued numbers no page cites: {uncited[:20]}"


def test_an_uncited_glued_number_fails():
    nb = {"cells": [_markdown("the {glue:text}`a` and {glue:text}`ch.ipynb::b:.2f`"),
                    _cell("keep()", [_glued("a"), _glued("b"), _glued("c")])]}
    assert uncited_glue({"ch.ipynb": nb}, []) == ["ch.ipynb: c"]
    assert uncited_glue({"ch.ipynb": nb}, ["{glue:md}`c`"]) == []
    figure = _cell("plt.show()")
    figure["metadata"]["mystnb"] = {"figure": {"caption": "error {glue:text}`c:.2f` px"}}
    nb["cells"].append(figure)
    assert uncited_glue({"ch.ipynb": nb}, []) == []


#: ``{glue:text}`path::key``` with no format: myst-nb splits the key at its last colon, so
#: the key becomes ``path:`` and the page shows nothing (``path::key:g`` is read as meant);
#: ``{glue:md}`` reads no other document at all.
UNFORMATTED_CROSS_CITATION = re.compile(r"\{glue:text\}`[^`:]+::[^`:]+`|\{glue:md\}`[^`]*::[^`]*`")


def test_a_citation_from_another_document_has_a_format():
    pages = {p.name: p.read_text(encoding="utf-8") for p in BOOK.parent.rglob("*.md")
             if "_build" not in p.parts}
    bad = {name: UNFORMATTED_CROSS_CITATION.findall(text) for name, text in pages.items()}
    assert not {k: v for k, v in bad.items() if v}, bad
    assert UNFORMATTED_CROSS_CITATION.findall(
        "{glue:text}`ch.ipynb::x` {glue:text}`ch.ipynb::y:g` {glue:text}`z` {glue:md}`w`"
        " {glue:md}`ch.ipynb::v:myst`") == ["{glue:text}`ch.ipynb::x`",
                                             "{glue:md}`ch.ipynb::v:myst`"]


def _toc_chapters() -> list[str]:
    """The chapter notebooks in the order of the book's table of contents."""
    toc = (BOOK.parent / "_toc.yml").read_text(encoding="utf-8")
    return re.findall(r"^\s*- file: chapters/(\S+)\s*$", toc, flags=re.MULTILINE)


def test_readme_numbers_the_chapters_as_the_book_does():
    readme = (BOOK.parent.parent / "README.md").read_text(encoding="utf-8")
    rows = re.findall(r"^\s*\| (\d+) \| (.+?) \| `(\S+)\.ipynb` \|\s*$", readme,
                      flags=re.MULTILINE)
    order = _toc_chapters()
    assert len(order) == len(CHAPTERS), (order, CHAPTERS)
    assert [(int(n), stem) for n, _, stem in rows] == list(enumerate(order, start=1))
    for _, title, stem in rows:
        first = json.loads((BOOK / f"{stem}.ipynb").read_text(encoding="utf-8"))["cells"][0]
        heading = _text(first["source"]).splitlines()[0].removeprefix("# ").strip()
        assert title.startswith(heading.split(":")[0]), (title, heading)


#: Words about the project's own work rather than the reader's subject (the football goal of
#: the RoboCup field is the subject, and stays).
PROJECT_TALK = re.compile(
    r"\bhonest\w*|\bwork items?\b|\bwe aim\b|\bTODO\b|\bgoals? (?:the library|of the "
    r"(?:library|project|multi-model work))|\bthe library set\b|\bagainst its goals\b|"
    r"\b(?:library|project)'s (?:work )?(?:goals?|targets?)\b", flags=re.IGNORECASE)


def project_talk(texts) -> list[str]:
    """The phrases of ``texts`` that speak of the project's work, not of the subject."""
    return [m.group(0) for t in texts for m in PROJECT_TALK.finditer(t)]


def test_no_page_speaks_of_the_project_s_goals():
    texts = [_text(c["source"]) for p in CHAPTERS
             for c in json.loads(p.read_text(encoding="utf-8"))["cells"]]
    texts += [p.read_text(encoding="utf-8") for p in BOOK.parent.glob("*.md")]
    assert not project_talk(texts), project_talk(texts)


def test_project_talk_is_caught_and_the_football_goal_is_not():
    assert project_talk(["So the honest reading is this", "The goals the library set its",
                         "the goals of the multi-model work"]) == [
        "honest", "goals the library", "goals of the multi-model work"]
    assert project_talk(["x towards the opponent goal", "the goals are identical",
                         "one goal's crossbars"]) == []


#: Anecdotes of the project's own runs, where a page should state a measurement (glued) or
#: nothing: "took more than three minutes on the machine that built this book".
BUILD_ANECDOTE = re.compile(
    r"machine that built|\bwe tried\b|\bcrippled\b|took (?:more than|over|about) [^.]{0,40}"
    r"(?:minutes?|hours?|seconds?)", flags=re.IGNORECASE)
#: A bare "CLAP" beside a number: before a glued value or a digit, or right after one
#: ("5.0 % for CLAP,"), where the book measures more than one CLAP.
BARE_CLAP_NUMBER = re.compile(r"\bCLAP(?!\s*\()[\s:]*(?:\{glue|\d)|[\d`][^|.;`]{0,12} for "
                              r"CLAP\b(?!\s*\()")
FRONT_PAGES = ("intro.md", "choosing.md")


def test_the_front_pages_tell_no_anecdotes_and_name_each_clap():
    for name in FRONT_PAGES:
        text = (BOOK.parent / name).read_text(encoding="utf-8")
        assert not BUILD_ANECDOTE.findall(text), (name, BUILD_ANECDOTE.findall(text))
        assert not BARE_CLAP_NUMBER.findall(text), (name, BARE_CLAP_NUMBER.findall(text))


def test_anecdotes_and_bare_claps_are_caught():
    assert BUILD_ANECDOTE.findall("the run took more than three minutes on the machine that "
                                  "built this book") == ["took more than three minutes",
                                                         "machine that built"]
    assert not BUILD_ANECDOTE.search("the median time per estimate, measured when the book "
                                     "was built")
    assert BARE_CLAP_NUMBER.search("for RANSAC and {glue:text}`x` for CLAP; CLAP gives")
    assert BARE_CLAP_NUMBER.search("at 80 %: CLAP {glue:text}`c4`")
    assert not BARE_CLAP_NUMBER.search("{glue:text}`x` for CLAP (paper); CLAP (paper) "
                                       "{glue:text}`y`")


#: The chapters whose pages meet the narrower rules of the second read (issue 28): output
#: lines of at most :data:`NARROW_OUTPUT` characters, no bare "CLAP" beside a number in the
#: text or a caption, and no pointer to the repository's files (a reader has the book, not
#: the repository's bench scripts, README or ARCHITECTURE.md).
NARROW_CHAPTERS = ("01_one_abstraction", "02_line_fitting", "03_localization_2d",
                   "04_localization_3d")
NARROW_OUTPUT = 88
REPOSITORY_FILES = re.compile(r"\bbench/|\bbench_\w+\.py|ARCHITECTURE\.md|\bREADME\b")


def narrow_defects(notebook: dict) -> list[str]:
    """Where one notebook breaks the narrower rules of :data:`NARROW_CHAPTERS`."""
    defects = []
    for index, cell in enumerate(notebook["cells"]):
        where = f"cell {index}"
        if cell["cell_type"] == "markdown":
            text = _text(cell["source"])
        else:
            text = json.dumps(cell.get("metadata", {}).get("mystnb", {}))  # the caption
        defects += [f"{where}: bare CLAP beside a number: {m!r}"
                    for m in BARE_CLAP_NUMBER.findall(text)]
        defects += [f"{where}: names a repository file: {m!r}"
                    for m in REPOSITORY_FILES.findall(text)]
        for output in cell.get("outputs", []):
            if output["output_type"] == "stream":
                lines = _text(output["text"]).splitlines()
            elif "text/plain" in output.get("data", {}) and len(output["data"]) == 1:
                lines = _text(output["data"]["text/plain"]).splitlines()
            else:
                continue
            defects += [f"{where}: an output line of {len(line)} characters: {line[:50]!r}"
                        for line in lines if len(line) > NARROW_OUTPUT]
    return defects


@pytest.mark.parametrize("stem", NARROW_CHAPTERS)
def test_first_chapters_are_narrow_and_name_each_clap(stem):
    notebook = json.loads((BOOK / f"{stem}.ipynb").read_text(encoding="utf-8"))
    defects = narrow_defects(notebook)
    assert not defects, f"{stem}:\n" + "\n".join(defects)


def test_narrow_defects_are_caught():
    wide = {"output_type": "stream", "name": "stdout", "text": "x" * 89 + "\n"}
    nb = {"cells": [_markdown("at 80 % CLAP {glue:text}`c4_x` of the frames; see "
                              "`bench/bench_lines.py` and ARCHITECTURE.md"),
                    _cell("print()", [wide])]}
    defects = narrow_defects(nb)
    assert [d.split(": ")[1] for d in defects] == [
        "bare CLAP beside a number", "names a repository file", "names a repository file",
        "names a repository file", "an output line of 89 characters"], defects
    fine = {"cells": [_markdown("CLAP (paper) {glue:text}`x`; the library's bench"),
                      _cell("print()", [{**wide, "text": "x" * 88}])]}
    assert narrow_defects(fine) == []

#: A role of the glossary: {term}`text <target>` or {term}`target`.
TERM_ROLE = re.compile(r"\{term\}`(?:[^`<]*<([^`>]+)>|([^`]+))`")


def _glossary_terms() -> list[str]:
    """The glossary's terms, each name of an entry (``sensitivity, control``: two names)."""
    text = (BOOK.parent / "glossary.md").read_text(encoding="utf-8")
    body = text.split("```{glossary}")[1].split("```")[0]
    return [line for line in body.splitlines() if line and not line.startswith(" ")]


def _unlinked_first_uses(text: str, terms: list[str]) -> list[str]:
    """The glossary terms whose first use in ``text``'s prose comes before any link to them.

    Code cells and blocks, inline code, glue roles, link targets and headings are not prose;
    a term inside a role is replaced by a marker of its entry, so that "CLAP" is not found
    inside a linked "CLAP (paper)".
    """
    prose = re.sub(r"```.*?```", "", text, flags=re.DOTALL)
    prose = re.sub(r"^#.*$", "", prose, flags=re.MULTILINE)
    prose = re.sub(r"\{glue(?::\w*)?\}`[^`]*`", "", prose)
    prose = re.sub(r"\]\([^)]*\)", "]", prose)
    links = {}

    def mark(m):
        entry = m.group(1) or m.group(2)
        links.setdefault(entry, m.start())
        return "\x00" * len(m.group(0))

    prose = TERM_ROLE.sub(mark, prose)
    prose = re.sub(r"`[^`]*`", lambda m: " " * len(m.group(0)), prose)  # positions kept
    missing = []
    for entry in terms:
        for name in (n.strip() for n in entry.split(",")):
            use = re.search(r"(?<![\w-])" + re.escape(name) + r"(?:s|es)?(?![\w-])", prose)
            if use and links.get(entry, len(prose)) > use.start():
                missing.append(name)
    return missing


def test_the_front_pages_link_every_glossary_term_at_its_first_use():
    terms = _glossary_terms()
    assert "Wilson interval" in terms and "sensitivity, control" in terms
    for name in FRONT_PAGES:
        text = (BOOK.parent / name).read_text(encoding="utf-8")
        assert not _unlinked_first_uses(text, terms), (name, _unlinked_first_uses(text, terms))
        for m in TERM_ROLE.finditer(text):  # every role names an entry
            assert (m.group(1) or m.group(2)) in terms, m.group(0)


def test_an_unlinked_first_use_is_caught():
    terms = ["Lie distance", "CLAP", "CLAP (paper)", "sensitivity, control"]
    assert _unlinked_first_uses("the Lie distance, then {term}`Lie distance`", terms) == [
        "Lie distance"]
    assert _unlinked_first_uses("{term}`CLAP (paper)` and `CLAP` in code", terms) == []
    assert _unlinked_first_uses("`a` `b` {term}`CLAP` then CLAP", terms) == []
    assert _unlinked_first_uses("two controls, then {term}`control <sensitivity, control>`",
                                terms) == ["control"]


#: The decision guide and the front page speak to the reader about the subject: no pointers to
#: the repository's files (a reader of the book has no README or bench folder), no "the
#: project", and no typed wall-clock time (a time is glued, or a ratio measured in one run).
SELF_TALK = re.compile(r"\bREADME\b|\bbench/|\bthe project\b|\d\s*ms\b", flags=re.IGNORECASE)


def test_the_front_pages_talk_about_the_subject():
    for name in FRONT_PAGES:
        text = (BOOK.parent / name).read_text(encoding="utf-8")
        prose = re.sub(r"```.*?```", "", text, flags=re.DOTALL)
        assert not SELF_TALK.findall(prose), (name, SELF_TALK.findall(prose))
        glued_ms = re.findall(r"\{glue(?::\w*)?\}`[^`]*`\s*ms\b", prose)
        assert not glued_ms, (name, glued_ms)
