"""The built book, as a reader's browser shows it (headless Chromium through selenium).

Run after ``make book`` (``make test`` builds the book first). Skipped, with the reason, when
the book is not built or when no Chromium and chromedriver are installed.

Each chapter page is loaded once from a local HTTP server; one script collects what the
tests check: that MathJax (served by the book itself, no network) typeset every formula and
no raw TeX delimiters are left in the visible text, that every figure's image loaded and has
alt text, a number and a caption, that figures are drawn at most as wide as the text column
that ``tests/test_book_figures.py`` assumes when it checks the legend text of every figure for
its size on the page, and that the reference pages exist and are linked.
"""

from __future__ import annotations

import functools
import html
import http.server
import re
import shutil
import threading
from pathlib import Path

import pytest

BOOK = Path(__file__).resolve().parents[1] / "book" / "_build" / "html"
CHAPTERS = sorted(p.name for p in (BOOK / "chapters").glob("*.html"))
BROWSERS = ("chromium", "chromium-browser", "google-chrome")
COMMANDS = ("fit", "localize2d", "localize3d", "stitch", "reproduce", "segment")

pytestmark = [
    pytest.mark.skipif(not (BOOK / "index.html").is_file(),
                       reason=f"the book is not built ({BOOK} is missing; run make book)"),
    pytest.mark.skipif(shutil.which("chromedriver") is None
                       or not any(shutil.which(b) for b in BROWSERS),
                       reason="no headless browser: install chromium and chromium-driver"),
]

#: Runs in the page once MathJax has finished; returns what the tests check.
FACTS_JS = """
const done = arguments[arguments.length - 1];
const collect = () => {
  const maths = [...document.querySelectorAll('.math')];
  const visible = document.querySelector('main') ? document.querySelector('main').innerText
                                                 : document.body.innerText;
  const images = [...document.querySelectorAll('.cell_output img')].map(img => {
    const fig = img.closest('figure');
    const cap = fig ? fig.querySelector('figcaption') : null;
    return {src: img.getAttribute('src'), complete: img.complete,
            width: img.naturalWidth, alt: img.getAttribute('alt') || '',
            // the width the page draws it at (0 in a folded cell)
            rendered: img.getBoundingClientRect().width,
            // textContent, not innerText: a figure in a folded cell (an exercise's
            // solution) has its number and caption in the page, hidden until unfolded
            number: cap && cap.querySelector('.caption-number')
                    ? cap.querySelector('.caption-number').textContent.trim() : '',
            caption: cap ? cap.textContent.trim() : ''};
  });
  // code, printed output and tables a reader sees (not folded: a folded cell, opened on
  // purpose, may scroll) that scroll sideways: a part of them is cut off at the column's edge
  const longest = el => Math.max(...el.textContent.split('\\n').map(l => l.length));
  const shown = el => el.getBoundingClientRect().width > 0
    && !el.closest('.tag_hide-input, .tag_hide-cell, .tag_hide-output');
  const cutoff = [
    ...[...document.querySelectorAll('.cell_input pre, .cell_output pre, main div.highlight pre')]
      .filter(p => shown(p) && p.scrollWidth > p.clientWidth + 1)
      .map(p => (p.closest('.cell_output') ? 'output' : 'code') + ' line of '
                + longest(p) + ' characters: ' + p.textContent.trim().slice(0, 50)),
    ...[...document.querySelectorAll('main table')].filter(shown).filter(t => {
      let p = t.parentElement;
      while (p && p.tagName !== 'MAIN' && p.scrollWidth <= p.clientWidth + 1) p = p.parentElement;
      return p && p.tagName !== 'MAIN';
    }).map(t => 'table ' + Math.round(t.getBoundingClientRect().width) + ' px wide: '
                + t.textContent.trim().slice(0, 50))];
  // folded code, unfolded as a reader would: shown whole too (the stylesheet sets it smaller)
  document.querySelectorAll('.tag_hide-input details, .tag_hide-cell details')
    .forEach(d => { d.open = true; });
  cutoff.push(...[...document.querySelectorAll(
      '.tag_hide-input .cell_input pre, .tag_hide-cell .cell_input pre')]
    .filter(p => p.getBoundingClientRect().width > 0 && p.scrollWidth > p.clientWidth + 1)
    .map(p => 'folded code line of ' + longest(p) + ' characters: '
              + p.textContent.trim().slice(0, 50)));
  const scripts = [...document.querySelectorAll('script[src]')].map(s => s.src);
  const links = [...document.querySelectorAll('a[href]')].map(a => a.href);
  done({mathjax: typeof MathJax !== 'undefined' && !!MathJax.startup,
        maths: maths.length,
        typeset: maths.filter(m => m.querySelector('mjx-container')).length,
        containers: document.querySelectorAll('mjx-container').length,
        raw: ['$$', '\\\\(', '\\\\[', '\\\\begin{'].filter(d => visible.includes(d)),
        notes: (visible.match(/NBVAL|nbval|\\bTODO\\b|\\bFIXME\\b|\\bticket\\b/g) || []),
        images, scripts, links, cutoff, origin: location.origin});
};
const images = [...document.images].map(img => img.complete ? Promise.resolve()
  : new Promise(r => { img.onload = r; img.onerror = r; }));
const typeset = (typeof MathJax !== 'undefined' && MathJax.startup && MathJax.startup.promise)
  ? MathJax.startup.promise : Promise.resolve();
Promise.all([typeset, ...images]).then(collect, collect);
"""


class _Quiet(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *args):
        pass


@pytest.fixture(scope="module")
def server():
    handler = functools.partial(_Quiet, directory=str(BOOK))
    httpd = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=httpd.serve_forever, daemon=True)
    thread.start()
    yield f"http://127.0.0.1:{httpd.server_address[1]}"
    httpd.shutdown()
    httpd.server_close()


@pytest.fixture(scope="module")
def browser(tmp_path_factory):
    webdriver = pytest.importorskip("selenium.webdriver")
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    options.binary_location = next(shutil.which(b) for b in BROWSERS if shutil.which(b))
    for flag in ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
                 "--no-first-run", "--disable-background-networking",
                 "--disable-component-update", "--disable-sync", "--window-size=1280,900",
                 f"--user-data-dir={tmp_path_factory.mktemp('chromium-profile')}"):
        options.add_argument(flag)
    driver = webdriver.Chrome(service=Service(shutil.which("chromedriver")), options=options)
    driver.set_script_timeout(60)
    driver.set_page_load_timeout(60)
    yield driver
    driver.quit()


@pytest.fixture(scope="module")
def page(server, browser):
    """``page(path)``: the facts of one page of the book, each page loaded once."""
    cache = {}

    def load(path: str) -> dict:
        if path not in cache:
            browser.get(f"{server}/{path}")
            cache[path] = browser.execute_async_script(FACTS_JS)
        return cache[path]

    return load


def test_every_chapter_is_built():
    assert len(CHAPTERS) >= 6, CHAPTERS


def test_the_mathematical_chapters_have_typeset_formulas(page):
    # the per-chapter check above passes on a page without formulas; this one cannot
    with_math = [c for c in CHAPTERS if page(f"chapters/{c}")["maths"] > 0]
    assert len(with_math) >= 5, with_math
    assert all(page(f"chapters/{c}")["mathjax"] for c in with_math)


@pytest.mark.parametrize("chapter", CHAPTERS)
def test_math_is_typeset_offline(page, chapter):
    facts = page(f"chapters/{chapter}")
    assert not facts["raw"], f"raw TeX delimiters visible: {facts['raw']}"
    if facts["maths"]:  # Sphinx loads MathJax only on pages with formulas
        assert facts["mathjax"], "MathJax did not load"
        assert facts["typeset"] == facts["maths"], (
            f"{facts['maths'] - facts['typeset']} of {facts['maths']} formulas not typeset")
        assert facts["containers"] >= facts["maths"]
    remote = [s for s in facts["scripts"] if not s.startswith(facts["origin"])]
    assert not remote, f"scripts loaded from elsewhere: {remote}"


@pytest.mark.parametrize("chapter", CHAPTERS)
def test_no_notes_for_the_authors_on_the_page(page, chapter):
    notes = page(f"chapters/{chapter}")["notes"]
    assert not notes, f"text meant for the authors, not the reader: {notes}"


@pytest.mark.parametrize("chapter", CHAPTERS)
def test_every_figure_loads_with_number_caption_and_alt(page, chapter):
    images = page(f"chapters/{chapter}")["images"]
    assert images, "no figure on the page"
    for img in images:
        assert img["complete"] and img["width"] > 0, f"image did not load: {img['src']}"
        assert img["alt"].strip(), f"no alt text: {img['src']}"
        assert img["number"].startswith("Fig."), f"not a numbered figure: {img['src']}"
        assert len(img["caption"]) > len(img["number"]) + 20, f"no caption: {img['src']}"


@pytest.mark.parametrize("path", [f"chapters/{c}" for c in CHAPTERS]
                         + ["intro.html", "choosing.html", "glossary.html"])
def test_nothing_a_reader_sees_is_cut_off_at_the_columns_edge(page, path):
    """At a 1280 px window, no visible code, printed output or table scrolls sideways, nor
    does folded code once unfolded (the stylesheet sizes code for 88 characters, folded code
    for 100; folded outputs may scroll)."""
    cutoff = page(path)["cutoff"]
    assert not cutoff, "cut off at the column's edge:\n" + "\n".join(cutoff)


def test_figures_are_shrunk_to_the_column_the_legend_check_assumes(page):
    from test_book_figures import COLUMN_PX, FOLDED_COLUMN_PX

    shown = [img for c in CHAPTERS for img in page(f"chapters/{c}")["images"]
             if img["rendered"] > 0]
    assert shown, "no figure drawn on any page"
    # the widest figures fill the column: its width is what the static check assumes
    column = max(img["rendered"] for img in shown)
    assert abs(column - COLUMN_PX) <= 1, (column, COLUMN_PX)
    shrunk = [img for img in shown if img["width"] > img["rendered"] + 1]
    assert shrunk, "no figure wider than the column"
    # a figure wider than its column (the page's, or a folded cell's) is drawn at that
    # column's width, never narrower than the static check assumes (a narrower figure may be
    # enlarged, which only enlarges its text: the static check takes no credit for that)
    for img in shrunk:
        assert FOLDED_COLUMN_PX - 1 <= img["rendered"] <= COLUMN_PX + 1, (
            img["src"], img["rendered"])


def test_reference_pages_exist_and_are_linked(page):
    index = page("index.html")
    for target in ("reference/index.html", "reference/cli.html"):
        assert (BOOK / target).is_file(), target
        assert any(link.split("#")[0].endswith(target) for link in index["links"]), target
    api = sorted((BOOK / "reference" / "api").glob("*.html"))
    assert len(api) >= 10, api
    for chapter in CHAPTERS:
        links = page(f"chapters/{chapter}")["links"]
        assert any("/reference/api/" in link and "#clap_unified" in link for link in links), (
            f"{chapter} links to no entry of the API reference")


def _text(path: Path) -> str:
    """A page's text without tags or whitespace (highlighting splits usage lines)."""
    raw = re.sub(r"<[^>]+>", "", path.read_text(encoding="utf-8"))
    return re.sub(r"\s+", "", html.unescape(raw))


def test_cli_reference_documents_every_command():
    text = _text(BOOK / "reference" / "cli.html")
    for command in COMMANDS:
        assert f"clap-unified{command}" in text, command
    for words in ("Exitstatuses", "--method", "--seed", "--hypotheses", "--prior", "--map"):
        assert words in text, words


def test_api_reference_documents_the_entry_points():
    html = (BOOK / "reference" / "api" / "core.html").read_text(encoding="utf-8")
    for anchor in ("clap_unified.fit", "clap_unified.compare", "clap_unified.ConsensusResult"):
        assert f'id="{anchor}"' in html, anchor
