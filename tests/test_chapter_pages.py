"""Every chapter of the book reads as a textbook page (issue 28).

The checks are static: they read each ``book/chapters/*.ipynb`` with its stored outputs (the
ones nbval compares and the book shows). :func:`page_defects` holds every chapter to the same
rules and fails on

* a visible code cell (not tagged ``remove-input``, ``remove-cell``, ``hide-input`` or
  ``hide-cell``) longer than :data:`MAX_VISIBLE_LINES` lines: teaching code is short; a folded
  cell (code a reader may unfold: how a figure is drawn) longer than :data:`MAX_FOLDED_LINES`;
* ``glue(...)``/``keep(...)`` bookkeeping in a cell a reader sees or may unfold: it belongs in
  removed cells (``remove-cell``, ``remove-input``);
* a stored output line (a stream, or a ``text/plain`` result) wider than
  :data:`MAX_OUTPUT_WIDTH` characters: it would scroll out of the text column (an output
  folded under ``hide-output``, such as a printed source file, may scroll);
* a cell that shows more than one text output (a print, then a table, then a print);
* ``stderr`` output containing ``Warning``: warnings are fixed at their cause;
* a ``text/plain`` result with no richer form beside it that is a bare object repr
  (``Text(...)``, ``<matplotlib...>``, ``<Figure ...>``): a plotting cell's last value
  leaking onto the page;
* in the text, captions and outputs: a bare "CLAP" beside a number (the book measures more than
  one CLAP: "CLAP (paper)", "CLAP (the library's)"), another name for the library's CLAP, a
  synthetic pair's code name, a pointer to the repository's files (a reader has the book, not
  the bench scripts, README or ARCHITECTURE.md), words about how the page was made;
* an exercise without a worked solution: a folded cell opening with ``# N.`` (or
  ``# Exercise N:``) whose output ends on a sentence, computed.

The chapters' own checks (the homography chapters' variant keys) live beside their
experiments' tests. Further checks read the whole book: every number a chapter glues is cited
by some page, and a citation from another document has a format.
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
#: Tags under which a code cell's source is folded: shown to a reader who unfolds it.
FOLDED = {"hide-input", "hide-cell"}
MAX_VISIBLE_LINES = 20
MAX_FOLDED_LINES = 45
MAX_OUTPUT_WIDTH = 88
#: Folded code is set smaller by the stylesheet, to show lines of this many characters whole.
MAX_FOLDED_WIDTH = 100
BARE_REPR = re.compile(r"\s*(Text\(|<matplotlib|<Figure)")
BOOKKEEPING = re.compile(r"^\s*(glue|keep)\(", flags=re.MULTILINE)
CITATION = re.compile(r"\{glue(?::\w*)?\}`([^`]+)`")
#: A bare "CLAP" beside a number: before a glued value or a digit, or right after one
#: ("5.0 % for CLAP,"), where the book measures more than one CLAP ("the library's CLAP"
#: is a name).
BARE_CLAP_NUMBER = re.compile(r"(?<!library's\s)\bCLAP(?!\s*\()[\s:]*(?:\{glue|\d)|"
                              r"[\d`][^|.;`]{0,12} for CLAP\b(?!\s*\()")
#: Other names for the library's CLAP ("CLAP (the library's)"), and a synthetic pair's code name.
OTHER_NAME = re.compile(r"\bdefault CLAP\b|CLAP \(library default\)|\br=0\.\d+ decoy=0")
#: Other names for the peers, whose book names are "OpenCV RANSAC", "OpenCV MAGSAC++",
#: "scikit-image RANSAC", "OpenCV point-set Hough" and "RANSAC (library) + polish": anywhere,
#: the possessive and bracketed forms; in an output (a table, a legend's print), also the code
#: identifiers, which the prose may quote once to say what is called.
PEER_OTHER_NAME = re.compile(r"OpenCV's (?:RANSAC|MAGSAC\+\+)|MAGSAC\+\+ \(OpenCV\)|"
                             r"scikit-image's `?ransac|\bskimage ransac\b")
PEER_IDENTIFIER = re.compile(r"cv2\.RANSAC|cv2\.USAC_MAGSAC|cv2\.HoughLinesPointSet|"
                             r"(?<!OpenCV )MAGSAC\+\+|(?<!\) )RANSAC \+ polish")
REPOSITORY_FILES = re.compile(r"\bbench/|\bbench_\w+\.py|ARCHITECTURE\.md|\bREADME\b")
#: Words about how the page was made rather than about its subject.
SELF_TALK = re.compile(r"machine that built|\bcrippled\b|\bglued for\b|\bevery build\b|"
                       r"\bmake book\b|\bmake test\b|\bwe tried\b|\ban earlier version\b|"
                       r"\bthis book was built\b|when this page was built|regression test|"
                       r"`test_\w+`|book's\s+`?glue|the\s+glue\b", flags=re.IGNORECASE)
#: The first line of a worked solution: ``# 2. ...`` or ``# Exercise 2: ...``.
SOLUTION = re.compile(r"#\s*(?:Exercise\s+)?(\d+)[.:]")
EXERCISE = re.compile(r"^(\d+)\. ", flags=re.MULTILINE)


def _text(value) -> str:
    return "".join(value) if isinstance(value, list) else str(value)


def _tags(cell) -> set[str]:
    return set(cell.get("metadata", {}).get("tags", []))


def text_outputs(outputs) -> list[tuple[str, str]]:
    """(kind, text) of the text outputs a reader sees, consecutive prints of a stream joined
    (a figure and a glued value are not text outputs)."""
    blocks = []
    for o in outputs:
        if o["output_type"] == "stream":
            kind, text = "stream:" + o.get("name", ""), _text(o["text"])
        elif "image/png" in o.get("data", {}) or o.get("metadata", {}).get("scrapbook"):
            continue
        elif "text/markdown" in o.get("data", {}):
            kind, text = "markdown", _text(o["data"]["text/markdown"])
        elif "text/html" in o.get("data", {}):
            kind, text = "html", _text(o["data"].get("text/plain", ""))
        elif "text/plain" in o.get("data", {}):
            kind, text = "plain", _text(o["data"]["text/plain"])
        else:
            continue
        if blocks and blocks[-1][0] == kind and kind.startswith("stream"):
            blocks[-1] = (kind, blocks[-1][1] + text)
        else:
            blocks.append((kind, text))
    return blocks


def _cell_defects(where: str, cell: dict) -> list[str]:
    defects = []
    source, tags = _text(cell["source"]), _tags(cell)
    n_lines = len(source.splitlines())
    if not tags & HIDDEN and n_lines > MAX_VISIBLE_LINES:
        defects.append(f"{where}: visible code cell of {n_lines} lines "
                       f"(at most {MAX_VISIBLE_LINES})")
    # the stylesheet fits 88 characters of visible code and 100 of folded code to the column
    width = (MAX_OUTPUT_WIDTH if not tags & HIDDEN
             else MAX_FOLDED_WIDTH if tags & FOLDED else None)
    if width:
        kind = "folded" if tags & FOLDED else "visible"
        defects += [f"{where}: a {kind} code line of {len(line)} characters (at most "
                    f"{width}): {line.strip()[:50]!r}..."
                    for line in source.splitlines() if len(line) > width]
    if tags & FOLDED and n_lines > MAX_FOLDED_LINES:
        defects.append(f"{where}: folded code cell of {n_lines} lines "
                       f"(at most {MAX_FOLDED_LINES})")
    if (not tags & HIDDEN or tags & FOLDED) and BOOKKEEPING.search(source):
        defects.append(f"{where}: glue bookkeeping in a cell a reader sees or may unfold")
    for output in cell.get("outputs", []):
        if output["output_type"] == "stream":
            text = _text(output["text"])
            if output.get("name") == "stderr" and "Warning" in text:
                defects.append(f"{where}: a warning on stderr: {text.strip()[:80]!r}")
        elif "text/plain" in output.get("data", {}):
            text = _text(output["data"]["text/plain"])
            if set(output["data"]) == {"text/plain"} and BARE_REPR.match(text):
                defects.append(f"{where}: a bare object repr: {text.strip()[:60]!r}")
            if len(output["data"]) > 1:
                continue  # a figure's or a table's plain form is not what the page shows
        else:
            continue
        for line in text.splitlines() if "hide-output" not in tags else ():  # folded: scrolls
            if len(line) > MAX_OUTPUT_WIDTH:
                defects.append(f"{where}: an output line of {len(line)} characters "
                               f"(at most {MAX_OUTPUT_WIDTH}): {line[:60]!r}...")
    if "remove-cell" in tags:
        return defects
    blocks = text_outputs(cell.get("outputs", []))
    if len(blocks) > 1:
        defects.append(f"{where}: {len(blocks)} text outputs "
                       f"({', '.join(kind for kind, _ in blocks)})")
    if "chapter_claims(" not in source:  # the claims' generator has its own checks
        shown = "\n".join(t for _, t in blocks)
        defects += _words_defects(where + " output", shown)
        defects += [f"{where} output: a peer's code name: {m.group(0)!r}"
                    for m in PEER_IDENTIFIER.finditer(shown)]
    return defects


def _words_defects(where: str, text: str) -> list[str]:
    """Naming, repository pointers and self-talk in a text a reader sees."""
    return ([f"{where}: bare CLAP beside a number: {m!r}"
             for m in BARE_CLAP_NUMBER.findall(text)]
            + [f"{where}: another name: {m.group(0)!r}" for m in OTHER_NAME.finditer(text)]
            + [f"{where}: another name: {m.group(0)!r}" for m in PEER_OTHER_NAME.finditer(text)]
            + [f"{where}: names a repository file: {m.group(0)!r}"
               for m in REPOSITORY_FILES.finditer(text)]
            + [f"{where}: says how the page was made: {m.group(0)!r}"
               for m in SELF_TALK.finditer(text)])


def _solution_output(cell: dict) -> str:
    return "".join(t for _, t in text_outputs(cell.get("outputs", []))).strip()


def exercise_defects(cells: list[dict]) -> list[str]:
    """The exercises without a worked solution whose output ends on a sentence."""
    defects = []
    for start, cell in enumerate(cells):
        if cell["cell_type"] != "markdown" or "## Exercises" not in _text(cell["source"]):
            continue
        questions = _text(cell["source"]).split("## Exercises", 1)[1].split("```", 1)[0]
        solutions: dict[str, list[str]] = {}
        number = None
        for later in cells[start + 1:]:
            if later["cell_type"] != "code" or not _tags(later) & FOLDED:
                continue
            match = SOLUTION.match(_text(later["source"]))
            number = match.group(1) if match else number  # a solution's later cells
            if number is not None:
                solutions.setdefault(number, []).append(_solution_output(later))
        for number in EXERCISE.findall(questions):
            printed = [p for p in solutions.get(number, []) if p]
            if number not in solutions:
                defects.append(f"exercise {number}: no worked solution (a folded cell "
                               f"'# {number}.')")
            elif not printed:
                defects.append(f"exercise {number}: its solution shows nothing")
            elif not re.search(r"[.!?]$", printed[-1]):
                defects.append(f"exercise {number}: its solution's output ends without a "
                               f"sentence: {printed[-1].splitlines()[-1][:60]!r}")
    return defects


#: A markdown line that MyST reads as a comment and drops from the page: a sentence wrapped
#: so that its next line starts with "%" ("up to 80\n% outliers") loses its end.
COMMENT_LINE = re.compile(r"^[ \t]*%", flags=re.MULTILINE)


def comment_defects(where: str, markdown: str) -> list[str]:
    """Lines of ``markdown`` that MyST drops as comments."""
    return [f"{where}: a line starts with '%', which MyST drops as a comment: "
            f"{line.strip()[:60]!r}" for line in markdown.splitlines()
            if COMMENT_LINE.match(line)]


def page_defects(notebook: dict) -> list[str]:
    """What keeps one notebook (parsed JSON) from reading as a textbook page."""
    defects = []
    for index, cell in enumerate(notebook["cells"]):
        where = f"cell {index}"
        if cell["cell_type"] == "markdown":
            defects += _words_defects(where, _text(cell["source"]))
            defects += comment_defects(where, _text(cell["source"]))
        elif cell["cell_type"] == "code":
            caption = json.dumps(cell.get("metadata", {}).get("mystnb", {}))
            defects += _words_defects(where + " caption", caption)
            defects += _cell_defects(where, cell)
            for output in cell.get("outputs", []):
                defects += comment_defects(where + " output",
                                           _text(output.get("data", {}).get("text/markdown", "")))
    return defects + exercise_defects(notebook["cells"])


def _param(path: Path):
    return pytest.param(path, id=path.stem)


def test_a_line_myst_drops_as_a_comment_is_a_defect():
    dropped = _markdown("all strategies are accurate up to 80\n% outliers.")
    assert any("'%'" in d for d in page_defects({"cells": [dropped]}))
    table = _cell("show()", [{"output_type": "display_data",
                              "data": {"text/markdown": "a share of 6.4\n% of them"}}])
    assert any("'%'" in d for d in page_defects({"cells": [table]}))
    kept = _markdown("all strategies are accurate up to 80 %\noutliers.")
    assert not comment_defects("x", kept["source"])


@pytest.mark.parametrize("page", sorted(p.name for p in BOOK.parent.glob("*.md")))
def test_no_line_of_a_markdown_page_is_dropped_as_a_comment(page):
    assert not comment_defects(page, (BOOK.parent / page).read_text(encoding="utf-8"))


def test_the_chapters_are_found():
    assert len(CHAPTERS) >= 9, CHAPTERS


@pytest.mark.parametrize("path", [_param(p) for p in CHAPTERS])
def test_chapter_reads_as_a_page(path):
    defects = page_defects(json.loads(path.read_text(encoding="utf-8")))
    assert not defects, f"{path.name}:\n" + "\n".join(defects)


def _cell(source, outputs=(), tags=()):
    return {"cell_type": "code", "source": source, "outputs": list(outputs),
            "metadata": {"tags": list(tags)}}


def _stream(text, name="stdout"):
    return {"output_type": "stream", "name": name, "text": text}


def test_the_checks_catch_each_defect():
    long_source = "\n".join(f"x{i} = {i}" for i in range(MAX_VISIBLE_LINES + 1))
    longer = "\n".join(f"x{i} = {i}" for i in range(MAX_FOLDED_LINES + 1))
    wide = _stream("x" * (MAX_OUTPUT_WIDTH + 1) + "\n")
    warning = _stream("UserWarning: The figure layout has changed to tight\n", "stderr")
    bare = {"output_type": "execute_result",
            "data": {"text/plain": "Text(0.5, 1.0, 'title')"}}
    figure = {"output_type": "display_data",
              "data": {"text/plain": "<Figure size 640x480 with 1 Axes>",
                       "image/png": "..."}}
    table = {"output_type": "display_data", "data": {"text/markdown": "| a |"}}
    cells = [_cell(long_source), _cell("print()", [wide]), _cell("f()", [warning]),
             _cell("ax.set_title('t')", [bare]), _cell("plt.show()", [figure]),
             _cell(long_source, tags=["hide-input"]),
             _cell(long_source, tags=["remove-cell"]),
             {"cell_type": "markdown", "source": "y" * 200, "metadata": {}},
             _cell('plt.show()\nkeep("n_lines", 4)'),
             _cell('keep("n_lines", 4)', tags=["remove-cell"]),
             _cell("print(source)", [wide], tags=["hide-output"]),  # folded: may scroll
             _cell(longer, tags=["hide-input"]),
             _cell("x = 1\nkeep('x', x)", tags=["hide-input"]),
             _cell("f()", [_stream("x\n"), table, _stream("y\n")]),
             _cell("print(1)\nprint(2)", [_stream("1\n"), _stream("2\n")]),  # one block
             _markdown("at 80 % CLAP {glue:text}`c4_x` of the frames; see "
                       "`bench/bench_lines.py` and ARCHITECTURE.md"),
             _markdown("Across the kernels we tried, the default CLAP wins."),
             _cell("print(v)", [_stream("CLAP 0.53 px, RANSAC 0.70 px\n")]),
             _cell("print(name)", [_stream("synthetic r=0.08 decoy=0.04 #1\n")]),
             _cell("show(chapter_claims(x))", [_stream("CLAP closer on 1\n")])]
    defects = page_defects({"cells": cells})
    assert [d.split(":")[0] for d in defects] == [
        "cell 0", "cell 1", "cell 2", "cell 3", "cell 8", "cell 11", "cell 12", "cell 13",
        "cell 15", "cell 15", "cell 15", "cell 15", "cell 16", "cell 16", "cell 17 output",
        "cell 18 output"], defects
    assert f"visible code cell of {MAX_VISIBLE_LINES + 1} lines" in defects[0]
    assert f"{MAX_OUTPUT_WIDTH + 1} characters" in defects[1]
    assert "warning" in defects[2]
    assert "bare object repr" in defects[3]
    assert "bookkeeping" in defects[4] and "bookkeeping" in defects[6]
    assert f"folded code cell of {MAX_FOLDED_LINES + 1} lines" in defects[5]
    assert "3 text outputs" in defects[7]
    assert "bare CLAP" in defects[8] and "bench/" in defects[9]
    assert "bench_lines.py" in defects[10] and "ARCHITECTURE" in defects[11]
    assert "default CLAP" in defects[12] and "we tried" in defects[13]
    assert "bare CLAP" in defects[14] and "r=0.08 decoy=0" in defects[15]
    fine = {"cells": [_markdown("CLAP (paper) {glue:text}`x`; the library's bench"),
                      _cell("print()", [_stream("x" * MAX_OUTPUT_WIDTH)]),
                      _cell("print(v)", [_stream("CLAP (paper) 0.53 px; clap_densest\n")]),
                      _markdown("the library's CLAP\n{glue:text}`x` and the library's CLAP: 2")]}
    assert page_defects(fine) == []


def test_a_visible_code_line_wider_than_the_column_is_a_defect():
    wide = "x = " + "1 + " * 25 + "1"
    assert "visible code line of 105 characters" in " ".join(page_defects({"cells": [
        _cell(wide)]}))
    # folded code is set smaller: up to 100 characters are shown whole, a wider line is cut
    assert page_defects({"cells": [_cell(wide[:MAX_FOLDED_WIDTH], tags=["hide-input"])]}) == []
    assert "folded code line of 105 characters" in " ".join(page_defects({"cells": [
        _cell(wide, tags=["hide-cell"])]}))
    assert page_defects({"cells": [_cell(wide, tags=["remove-cell"])]}) == []  # not on the page


def test_a_peer_goes_by_its_book_name():
    cells = [_markdown("OpenCV's RANSAC and scikit-image's `ransac`; calls `cv2.RANSAC`"),
             _cell("print(t)", [_stream("| skimage ransac | 9.28 |\n| cv2.RANSAC | 1 |\n")]),
             _cell("print(t)", [_stream("MAGSAC++ 0.4, RANSAC + polish 0.3\n")]),
             _cell("show(chapter_claims(x))", [_stream("cv2.RANSAC\n")])]
    assert [d.split(": ", 1)[1] for d in page_defects({"cells": cells})] == [
        "another name: \"OpenCV's RANSAC\"", "another name: \"scikit-image's `ransac\"",
        "another name: 'skimage ransac'", "a peer's code name: 'cv2.RANSAC'",
        "a peer's code name: 'MAGSAC++'", "a peer's code name: 'RANSAC + polish'"]
    fine = [_markdown("OpenCV RANSAC (`cv2.findHomography` with `cv2.RANSAC`)"),
            _cell("print(t)", [_stream("OpenCV MAGSAC++ 0.4, RANSAC (library) + polish 0.3\n"
                                       "| scikit-image RANSAC | 9.28 |\n")])]
    assert page_defects({"cells": fine}) == []


def test_talk_of_how_the_page_was_made_is_caught():
    said = ["timed on the machine that built this book", "as `test_claims` checks",
            "the regression test compares", "and the book's `glue`", "the glue keeps it",
            "measured when this page was built"]
    for text in said:
        assert "how the page was made" in " ".join(page_defects({"cells": [_markdown(text)]}))
    assert page_defects({"cells": [_markdown("glued values; a test of two proportions")]}) == []


def test_every_exercise_needs_a_worked_solution_ending_in_a_sentence():
    questions = _markdown("## Exercises\n\n1. One?\n2. Two?\n3. Three?\n4. Four?\n"
                          "```{tip}\n5. not a question\n```")
    cells = [questions,
             _cell("# 1. one\nprint('one')", [_stream("one\n")], ["hide-cell"]),
             _cell("# Exercise 2: two", [], ["hide-input"]),
             _cell("# 3. three\nprint('x')", [_stream("x = 1\n")], ["hide-cell"]),
             _cell("print('It holds.')", [_stream("It holds.\n")], ["hide-cell"])]
    assert exercise_defects(cells) == [
        "exercise 1: its solution's output ends without a sentence: 'one'",
        "exercise 2: its solution shows nothing",
        "exercise 4: no worked solution (a folded cell '# 4.')"]
    cells[1]["outputs"] = [_stream("one: the hint holds.\n")]
    cells[2]["outputs"] = [{"output_type": "display_data",
                            "data": {"text/markdown": "| a |\n\nThe table says so."}}]
    cells.append(_cell("# 4. four\nprint('Four.')", [_stream("Four.\n")], ["hide-input"]))
    assert exercise_defects(cells) == []


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
FRONT_SELF_TALK = re.compile(r"\bREADME\b|\bbench/|\bthe project\b|\d\s*ms\b",
                             flags=re.IGNORECASE)


def test_the_front_pages_talk_about_the_subject():
    for name in FRONT_PAGES:
        text = (BOOK.parent / name).read_text(encoding="utf-8")
        prose = re.sub(r"```.*?```", "", text, flags=re.DOTALL)
        assert not FRONT_SELF_TALK.findall(prose), (name, FRONT_SELF_TALK.findall(prose))
        glued_ms = re.findall(r"\{glue(?::\w*)?\}`[^`]*`\s*ms\b", prose)
        assert not glued_ms, (name, glued_ms)


def figure_defects(notebook: dict) -> list[str]:
    """Figures a reader sees without a caption or alt text (the book's -W build fails on them:
    this finds them before a build does)."""
    defects = []
    for i, cell in enumerate(notebook["cells"]):
        if cell["cell_type"] != "code" or _tags(cell) & {"remove-cell", "remove-output"}:
            continue
        if not any("image/png" in o.get("data", {}) for o in cell.get("outputs", [])):
            continue
        meta = cell.get("metadata", {}).get("mystnb", {})
        if not meta.get("figure", {}).get("caption"):
            defects.append(f"cell {i}: a figure without a caption")
        if not meta.get("image", {}).get("alt"):
            defects.append(f"cell {i}: a figure without alt text")
    return defects


@pytest.mark.parametrize("path", [_param(p) for p in CHAPTERS])
def test_every_figure_has_a_caption_and_alt_text(path):
    assert figure_defects(json.loads(path.read_text())) == []


def test_a_figure_without_a_caption_is_a_defect():
    figure = {"output_type": "display_data", "data": {"image/png": "..."}}
    bare = _cell("plt.show()", [figure])
    told = {**_cell("plt.show()", [figure]),
            "metadata": {"mystnb": {"figure": {"caption": "c"}, "image": {"alt": "a"}}}}
    hidden = _cell("plt.show()", [figure], tags=["remove-output"])
    assert figure_defects({"cells": [bare, told, hidden]}) == [
        "cell 0: a figure without a caption", "cell 0: a figure without alt text"]


def _names(source: str) -> tuple[set[str], set[str]]:
    """The names a cell defines at its top level and the names it reads."""
    import ast

    tree = ast.parse(source)
    defined = set()
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            defined.add(node.name)
        elif isinstance(node, (ast.Import, ast.ImportFrom)):
            defined |= {(a.asname or a.name).split(".")[0] for a in node.names}
        elif isinstance(node, (ast.Assign, ast.AnnAssign, ast.AugAssign, ast.For, ast.With)):
            targets = (node.targets if isinstance(node, ast.Assign) else
                       [node.target] if hasattr(node, "target") else
                       [i.optional_vars for i in node.items if i.optional_vars])
            defined |= {n.id for t in targets for n in ast.walk(t) if isinstance(n, ast.Name)}
    read = {n.id for n in ast.walk(tree) if isinstance(n, ast.Name)
            and isinstance(n.ctx, ast.Load)}
    return defined, read


def how_to_read_defects(notebook: dict) -> list[str]:
    """A chapter whose visible code reads names that only hidden cells define (folded on the
    page, or left out of it and shown in the notebook) says so near its top ("How to read the
    code", naming some of them); each name it gives is one of them."""
    folded_defs, visible_defs, visible_reads = set(), set(), set()
    for cell in notebook["cells"]:
        if cell["cell_type"] != "code":
            continue
        defined, read = _names(_text(cell["source"]))
        if _tags(cell) & HIDDEN:
            folded_defs |= defined
        else:
            visible_defs |= defined
            visible_reads |= read
    borrowed = (folded_defs - visible_defs) & visible_reads
    if not borrowed:
        return []
    intro = "\n\n".join(_text(c["source"]) for c in notebook["cells"][:4]
                         if c["cell_type"] == "markdown")
    if "**How to read the code.**" not in intro:
        some = ", ".join(sorted(borrowed)[:5])
        return [f"visible code reads names only folded cells define ({some}...) and the "
                "chapter does not say so"]
    said = re.findall(r"`(\w+)`", intro.split("**How to read the code.**", 1)[1].split("\n\n")[0])
    if not said:
        return ["'How to read the code' names none of them"]
    return [f"'How to read the code' names {n}, which visible code does not borrow from a "
            "folded cell" for n in said if n not in borrowed]


@pytest.mark.parametrize("path", [_param(p) for p in CHAPTERS])
def test_a_chapter_says_where_its_visible_code_s_names_come_from(path):
    assert not how_to_read_defects(json.loads(path.read_text(encoding="utf-8")))


def test_the_how_to_read_check_catches_an_unsaid_or_wrong_name():
    folded = _cell("N = 3\ndef helper():\n    pass", tags=["hide-input"])
    visible = _cell("helper()\nprint(N)")
    assert how_to_read_defects({"cells": [folded, visible]})
    said = _markdown("**What it assumes.** x\n\n**How to read the code.** (`N`, `helper`)")
    assert not how_to_read_defects({"cells": [said, folded, visible]})
    wrong = _markdown("**How to read the code.** (`M`)")
    assert how_to_read_defects({"cells": [wrong, folded, visible]})
