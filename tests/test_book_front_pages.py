"""The front page and the decision guide: the numbers the guide quotes read as in the chapters
they come from, no number typed into either page's prose, and each page says once which data
stands in for the paper's.

The checks read the pages' sources and the chapters' saved outputs (no execution).
"""

from __future__ import annotations

import json
import re
from pathlib import Path

from book_pages import glued_values

BOOK = Path(__file__).resolve().parents[1] / "book"
#: A glue citation from another document: ``{glue:text}`chapters/NB::key:format```.
CROSS = re.compile(r"\{glue:text\}`chapters/([\w.]+)::(\w+):([^`]*)`")
#: A glue citation in a chapter: ``{glue:text}`key``` or ``{glue:text}`key:format```.
LOCAL = r"\{{glue:text\}}`{key}(?::([^`]*))?`"


def _glued(notebook: str) -> dict:
    """``{key: text}`` of what a chapter's saved outputs glue."""
    return glued_values(json.loads((BOOK / "chapters" / notebook).read_text()))
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


#: A chapter number or a list of them in prose: "chapter 4", "chapters 1, 2 and 9".
LIBRARY_LABEL = "CLAP (the library's)"


def _chapter_order() -> list[str]:
    """The chapter notebooks in the order (and numbering) of the table of contents."""
    toc = (BOOK / "_toc.yml").read_text(encoding="utf-8")
    return re.findall(r"^\s*- file: chapters/(\S+)\s*$", toc, flags=re.MULTILINE)


def chapters_labelling_library_clap() -> set[int]:
    """Chapters whose code names a method "CLAP (the library's)" (tables, legends): the
    chapters that run the library's own CLAP."""
    found = set()
    for number, stem in enumerate(_chapter_order(), start=1):
        nb = json.loads((BOOK / "chapters" / f"{stem}.ipynb").read_text(encoding="utf-8"))
        if any(LIBRARY_LABEL in "".join(c["source"]) for c in nb["cells"]
               if c["cell_type"] == "code"):
            found.add(number)
    return found


def clap_rows(markdown: str) -> dict[str, set[int]]:
    """The rows of the front page's table "Which CLAP is which": ``{first cell: chapters}``."""
    section = markdown.split("(which-clap)=", 1)[1].split("\n## ", 2)[1]
    rows = {}
    for line in section.splitlines():
        line = re.sub(r"\{term\}`([^`<]*?)(?: <[^>]*>)?`", r"\1", line)  # a term as its name
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if line.startswith("| CLAP") and len(cells) >= 3:
            rows[cells[0]] = {int(n) for n in re.findall(r"\d+", cells[2])}
    return rows


def clap_table(markdown: str) -> dict[str, set[int]]:
    """The table by name: ``{name: chapters}``, a name that has several rows (one per problem)
    with the union of their chapters."""
    table = {}
    for first, chapters in clap_rows(markdown).items():
        name = re.match(r"CLAP \([^)]*\)(?: \+ [\w-]+(?: [\w-]+)*)?", first).group(0)
        table.setdefault(name, set()).update(chapters)
    return table


#: What each of the library's rows runs, as a chapter's code calls it: a chapter the row names
#: must call it; where the call is the row's alone (``only``), a chapter that calls it must be
#: named.
LIBRARY_CALLS = {
    "on lines and curves": (r"fit_line\(|LineSpace|CircleSpace|EllipseSpace", r"fit_line\("),
    "on point clouds": (r"align_correspondences\(", r"align_correspondences\("),
    "for homographies": (r"estimate_homography\(", None),
    "for several structures": (r"\bsegment(?:_matches)?\(", r"\bsegment(?:_matches)?\("),
}


def chapters_calling(pattern: str) -> set[int]:
    found = set()
    for number, stem in enumerate(_chapter_order(), start=1):
        nb = json.loads((BOOK / "chapters" / f"{stem}.ipynb").read_text(encoding="utf-8"))
        code = "\n".join("".join(c["source"]) for c in nb["cells"] if c["cell_type"] == "code")
        if re.search(pattern, code):
            found.add(number)
    return found


def library_row_defects(rows: dict[str, set[int]]) -> list[str]:
    """A library row naming a chapter that does not run it, or missing one that does."""
    defects = []
    for problem, (calls, only) in LIBRARY_CALLS.items():
        listed = rows.get(f"CLAP (the library's), {problem}")
        if listed is None:
            defects.append(f"no row for the library's CLAP {problem}")
            continue
        defects += [f"{problem}: chapter {n} does not call it"
                    for n in sorted(listed - chapters_calling(calls))]
        if only:
            defects += [f"{problem}: chapter {n} runs it, not named"
                        for n in sorted(chapters_calling(only) - listed)]
    return defects


#: Names a table gives CLAP that are not configurations: a claims block's row of variants.
NOT_CONFIGURATIONS = {"CLAP (this row)", "CLAP (that row)"}


def clap_names_in_chapters() -> set[str]:
    """Every "CLAP (...)" name the chapters' tables and code labels use, with its qualifier in
    brackets (the configuration), not what follows it ("+ polish", "ordered")."""
    names = set()
    for stem in _chapter_order():
        text = (BOOK / "chapters" / f"{stem}.ipynb").read_text(encoding="utf-8")
        # a table cell of a saved output, or a string of the code (a label, a legend)
        names |= set(re.findall(r'(?:\| |\\")(CLAP \([^()|\\]*\))', text))
    return names


def test_front_page_names_every_chapter_that_runs_the_library_s_clap():
    """The front page said only chapters 7 and 8 measure CLAP (the library's), while chapters
    1, 2, 4 (point clouds) and 9 run it too; then it named one configuration where the book
    runs four (the thirteenth read)."""
    markdown = (BOOK / "intro.md").read_text(encoding="utf-8")
    table = clap_table(markdown)
    assert table.get("CLAP (the library's)") == chapters_labelling_library_clap(), table
    assert not library_row_defects(clap_rows(markdown)), library_row_defects(clap_rows(markdown))


def test_the_front_page_lists_every_configuration_the_chapters_name():
    """Each "CLAP (...)" name of a chapter is a row of the front page's table."""
    table = clap_table((BOOK / "intro.md").read_text(encoding="utf-8"))
    bases = {re.match(r"CLAP \([^)]*\)", name).group(0) for name in table}
    unlisted = clap_names_in_chapters() - bases - NOT_CONFIGURATIONS
    assert not unlisted, unlisted
    assert "CLAP (paper) + in-cluster trim" in table
    library_rows = [line for line in (BOOK / "intro.md").read_text().splitlines()
                    if re.match(r"\| (?:\{term\}`)?CLAP \(the library's\)", line)]
    assert len(library_rows) == 4  # lines, point clouds, homographies, several structures


def toc_part_of(file: str) -> dict:
    import yaml

    toc = yaml.safe_load((BOOK / "_toc.yml").read_text(encoding="utf-8"))
    return next(p for p in toc["parts"]
                if any(c.get("file") == file for c in p.get("chapters", [])))


def test_the_decision_guide_is_not_numbered_as_a_chapter():
    """The guide sat in a numbered part after chapter 9, so its headings read "10.1 The
    short answer", as if it were a tenth chapter."""
    assert not toc_part_of("choosing").get("numbered", False)
    assert toc_part_of("chapters/07_your_data").get("numbered", False)


def test_the_front_page_checks_catch_the_old_text():
    old = ("(which-clap)=\n## Which CLAP is which\n\n| name | what runs | chapters | answer |\n"
           "|---|---|---|---|\n| CLAP (the library's), on lines | `clap` | chapters 1, 2 and 9 "
           "| density |\n| CLAP (the library's), on point clouds | x | chapter 4 | density |\n"
           "| CLAP (the library's), for homographies | x | chapters 8 and 9 | data |\n"
           "| CLAP (the library's), for several structures | x | chapters 7 and 9 | data |\n")
    assert clap_table(old) == {"CLAP (the library's)": {1, 2, 4, 7, 8, 9}}
    defects = library_row_defects(clap_rows(old))
    assert "no row for the library's CLAP on lines and curves" in defects
    old = old.replace("on lines |", "on lines and curves |")
    assert library_row_defects(clap_rows(old)) == [
        "on lines and curves: chapter 8 runs it, not named",
        "on point clouds: chapter 8 runs it, not named",
        "for several structures: chapter 9 does not call it"]
    assert chapters_labelling_library_clap() >= {1, 2, 4, 7, 8, 9}


def test_the_front_page_says_what_clap_is_and_maps_the_book_before_the_claims():
    """The front page asked a newcomer to parse the claims table and its alternatives and
    controls before "How to read this book" (the chapter map)."""
    text = (BOOK / "intro.md").read_text(encoding="utf-8")
    headings = re.findall(r"^## (.+)$", text, flags=re.MULTILINE)
    assert headings.index("How to read this book") < headings.index(
        "What the paper claims, and what was measured"), headings
    read = text.index("## How to read this book")
    assert text.index("{term}`CLAP`") < read  # what CLAP is, first
    # the claims' machinery (the table, alternatives, controls) comes after the chapter map
    for word in ("claims_markdown(", "{term}`two-proportion test`", "Controls are"):
        assert text.index(word) > read, word


def test_the_guide_rows_on_tracking_and_match_quality_agree_with_their_numbers():
    """The tracking row chose "either method" beside RANSAC 53 against CLAP (paper) 39 of 60
    frames; the match-quality row set CLAP with the ratio against a peer without it, unsaid."""
    guide = (BOOK / "choosing.md").read_text()
    track = next(line for line in guide.splitlines() if line.startswith("| a prior: tracking"))
    assert "either method with the prior's gate" not in track
    assert "c4_track_choose" in track
    quality = next(line for line in guide.splitlines()
                   if line.startswith("| matches with a quality"))
    assert "only CLAP had the ordering" in quality
    assert "evd_kept_ransaco" in quality and "PROSAC" in quality

def reproducibility_defects(intro: str, chapter_prose: dict[str, str]) -> list[str]:
    """The front page's promise of what changes from build to build must leave room for
    what a chapter warns of: a chapter that says its numbers can differ on another machine is
    named, and linked, in the front page's "How to read this book"."""
    read = intro.split("## How to read this book", 1)[-1].split("\n## ", 1)[0]
    promise = next((p for p in read.split("\n\n") if "wall-clock" in p), "")
    defects = []
    for nb, prose in chapter_prose.items():
        if "On another machine" in prose and (
                "another machine" not in promise or f"chapters/{nb}" not in promise):
            defects.append(nb)
    return defects


def test_the_front_page_says_what_can_change_on_another_machine():
    chapters = {p.name: _prose(p.name) for p in sorted((BOOK / "chapters").glob("*.ipynb"))}
    intro = (BOOK / "intro.md").read_text(encoding="utf-8")
    assert "05c_many_answers.ipynb" in [k for k, v in chapters.items()
                                        if "On another machine" in v]
    assert reproducibility_defects(intro, chapters) == []
    old = intro.split("## How to read this book")[0] + (
        "## How to read this book\n\nEvery number is produced by seeded computation when the "
        "book is built;\nonly wall-clock times change from build to build.\n")
    assert reproducibility_defects(old, chapters) == ["05c_many_answers.ipynb"]


def test_the_glossary_defines_the_terms_a_newcomer_met_undefined():
    """ICP (chapter 4), MoCap (the front page's claims, chapter 4) and spatial coherence
    (claim 9's protocol, chapter 7) were used without a definition anywhere."""
    glossary = (BOOK / "glossary.md").read_text(encoding="utf-8")
    terms = set(re.findall(r"^(\S[^\n]*)\n  \S", glossary, flags=re.M))
    assert {"ICP", "MoCap", "spatial coherence"} <= terms
    ch4, ch7 = _prose("04_localization_3d.ipynb"), _prose("05c_many_answers.ipynb")
    assert "{term}`ICP`" in ch4 and "{term}`MoCap`" in ch4
    assert "{term}`spatial coherence`" in ch7


def _guide_row(guide: str, starts: str) -> list[str]:
    """The cells of the short answer's row that starts with ``starts``."""
    line = next(x for x in guide.splitlines() if x.startswith("| " + starts))
    return [c.strip() for c in line.strip()[1:-1].split(" | ")]


def _claims_section(guide: str) -> str:
    return " ".join(guide.split("## What the paper's claims came to")[1].split("\n## ")[0]
                    .split())


def unsaid_claims(section: str, titles: list[str]) -> list[str]:
    """The claims the guide's section on the paper's claims does not name: a title is quoted
    whole, or, where its words hold a number (which the guide may not type), its prefix ("3D")
    is quoted."""
    unsaid = []
    for title in titles:
        prefix, words = title.split(": ", 1)
        named = f'"{prefix}"' in section if re.search(r"\d", words) else f'"{title}"' in section
        if not named:
            unsaid.append(title)
    return unsaid


def test_the_guide_names_every_claim_and_its_table_of_verdicts():
    """The section covered only 2D, 3D and homographies, and pointed to "the table above",
    where the only table a reader could take for it was the short answer."""
    from clap_unified.reproduce.claims import CLAIM_TITLES

    section = _claims_section((BOOK / "choosing.md").read_text(encoding="utf-8"))
    assert unsaid_claims(section, list(CLAIM_TITLES.values())) == []
    assert "verdicts_markdown(run.claims)" in section  # the verdicts, computed
    assert "every claim of the paper its verdict in one place" in section
    assert "in the table above" not in section  # the table is named: "table of verdicts"
    assert "table of verdicts" in section


def test_the_unsaid_claims_check_catches_the_old_section():
    old = ('* **2D localization**: level (the claim\'s own experiment, whose verdict is in the '
           'table above). * **Homographies**: fails more often.')
    titles = ["3D: CLAP beats RANSAC above 50 % outliers", "Real panoramas: similar accuracy",
              "2D: robust against outliers"]
    assert unsaid_claims(old, titles) == titles
    assert unsaid_claims('the two rows that start with "3D"; the row "2D: robust against '
                         'outliers"', titles) == ["Real panoramas: similar accuracy"]


def test_the_guide_s_homography_choice_follows_chapter_8_s_numbers():
    """The row chose "OpenCV MAGSAC++ or PoseLib" beside numbers that put MAGSAC++ below the
    library's CLAP and OpenCV RANSAC on the hard synthetic pairs: the choice is now the best
    peer chapter 8 computes, and the evidence names the peers the library's CLAP is ahead of."""
    _, choose, evidence = _guide_row((BOOK / "choosing.md").read_text(encoding="utf-8"),
                                     "one {term}`homography`")
    assert "c6_guide_choose" in choose and "MAGSAC" not in choose
    assert "c6_below_words" in evidence


def test_the_guide_s_3d_rows_say_which_experiment_each_number_is_from():
    """53 and 39 of 60 (tracking, each method gated around its own previous estimate) and
    0.89 and 0.76 (a front end's guess) read as one comparison; CLAP (paper)'s misses were
    said to be frames without a pose while 2 of 21 were coarse poses."""
    guide = (BOOK / "choosing.md").read_text(encoding="utf-8")
    _, _, track = _guide_row(guide, "a prior: tracking")
    assert "own previous estimate" in track
    for name in ("c4_track_clap_local_none", "c4_track_clap_local_coarse",
                 "c4_track_clap_local_wrong"):
        assert f"::{name}:" in track, name
    assert "never a wrong one" not in track
    _, _, few = _guide_row(guide, "few correct candidates")
    assert "front end's guess" in few and "::c4_guess_m:" in few and "::c4_n_frames:" in few


def test_the_guide_s_choice_for_several_structures_is_computed():
    """The row chose "CLAP through segment" beside evidence that its lead over T-Linkage and
    sequential RANSAC is within the spread over seeds."""
    _, choose, _ = _guide_row((BOOK / "choosing.md").read_text(encoding="utf-8"),
                              "several structures")
    assert choose == "{glue:text}`chapters/05c_many_answers.ipynb::mm_guide_choose:s`"


def test_the_guide_s_design_row_has_a_measurement():
    """The row "cheap to compare but expensive to score" had only a description under "what
    the measurements say"."""
    _, _, evidence = _guide_row((BOOK / "choosing.md").read_text(encoding="utf-8"),
                                "candidates that are cheap to compare")
    assert CROSS.search(evidence), evidence


def landmark_clap_defects(intro: str) -> list[str]:
    """The front page's sentence on which CLAP the landmark chapters run: chapters 3 and 4 run
    one configuration (the library's localization defaults are the paper's settings), named
    CLAP (paper), so the page may not promise a comparison of the two."""
    text = " ".join(intro.split())
    sentence = next((s for s in re.split(r"(?<=\.) ", text) if s.startswith("For landmarks")),
                    "")
    if not sentence:
        return ["no sentence on the landmark chapters' CLAP"]
    defects = []
    if re.search(r"\bcompare", sentence):
        defects.append("promises a comparison of the paper's settings with the defaults")
    if "CLAP (paper)" not in sentence:
        defects.append("does not name the CLAP they run")
    return defects


def test_the_front_page_says_the_landmark_chapters_run_one_clap():
    assert landmark_clap_defects((BOOK / "intro.md").read_text(encoding="utf-8")) == []
    old = ("on your own data. For landmarks, chapters 3 and 4 compare the paper's settings with "
           "the library's localization defaults and say which CLAP they run. The chapters")
    assert landmark_clap_defects(old) == [
        "promises a comparison of the paper's settings with the defaults",
        "does not name the CLAP they run"]


def test_the_glossary_defines_the_terms_its_entries_and_chapter_5_use():
    """"first-order distance" (in the entry CLAP (densest-cluster reading)) and "SL(3)"
    (chapter 5's "In the library" box) had no entry."""
    from test_chapter_pages import _glossary_terms

    terms = _glossary_terms()
    assert "first-order distance" in terms and "SL(3)" in terms
    glossary = (BOOK / "glossary.md").read_text(encoding="utf-8")
    assert "{term}`first-order distance`" in glossary


def test_the_glossary_defines_the_terms_the_twelfth_read_met_undefined():
    """MAD and Weiszfeld iterations (chapter 1's robust centres), the Tanimoto distance
    (T-Linkage) and P-NAPSAC (Progressive-X's published protocol, chapter 7)."""
    glossary = (BOOK / "glossary.md").read_text(encoding="utf-8")
    terms = set(re.findall(r"^(\S[^\n]*)\n  \S", glossary, flags=re.M))
    assert {"MAD", "Weiszfeld iterations", "Tanimoto distance", "P-NAPSAC"} <= terms
    assert "{term}`Tanimoto distance`" in glossary.split("\nT-Linkage\n")[1].split("\n\n")[0]

# --- the twelfth read: the guide's "why" paragraph, the glossary's polish and paired test ----

def _entry(glossary: str, term: str) -> str:
    """A glossary entry's text, its indented lines below the term."""
    return " ".join(glossary.split(f"\n{term}\n", 1)[1].split("\n\n", 1)[0].split())


def guide_glossary_twelfth_defects(guide: str, glossary: str) -> list[str]:
    """The guide read "chapters 4 and 5 (homographies)" and "their nearest neighbours" (the
    library's CLAP ranks by the k-th, k = 2); the glossary put the polish's zero weight at the
    threshold (the library's homography CLAP puts it at PROTOCOLS["clap"]["polish"] times it)
    and ended "paired test" with a sentence the reader could not parse."""
    from clap_unified.imaging import PROTOCOLS

    defects = []
    if "chapters 4 and 5 ([homographies]" in guide:
        defects.append("'chapters 4 and 5 (homographies)': chapter 4 is about poses")
    if "distance to their nearest neighbours" in guide:
        defects.append("the guide's 'nearest neighbours' where CLAP ranks by the k-th")
    polish = _entry(glossary, "polish")
    if f"polish={PROTOCOLS['clap']['polish']}" not in polish:
        defects.append("the polish entry omits the library's CLAP's wider polish")
    if "would call noise when the frames, not the method, vary" in _entry(glossary,
                                                                          "paired test"):
        defects.append("the paired test's last sentence is hard to parse")
    return defects


def test_the_guide_and_glossary_answer_the_twelfth_read():
    defects = guide_glossary_twelfth_defects((BOOK / "choosing.md").read_text(encoding="utf-8"),
                                             (BOOK / "glossary.md").read_text(encoding="utf-8"))
    assert not defects, defects


def test_the_guide_and_glossary_twelfth_checks_catch_the_old_text():
    guide = ("why chapters 4 and 5 ([homographies](chapters/05_homographies.ipynb)) compare; "
             "it ranks candidates by the distance to their nearest neighbours and")
    glossary = ("\npaired test\n  the rule's margin. It sees a change that a two-proportion test"
                "\n  on the same shares would call noise when the frames, not the method, vary."
                "\n\npolish\n  weights fall smoothly to zero at the inlier threshold.\n\n")
    assert len(guide_glossary_twelfth_defects(guide, glossary)) == 4
