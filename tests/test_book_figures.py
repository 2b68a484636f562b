"""The chapters' figures as a reader sees them: no blank tile, no legend text too small to read.

The check is static: it reads each ``book/chapters/*.ipynb`` with its stored outputs (the PNGs
the book shows) and fails on

* a **blank tile**: a panel of a figure (an image drawn in an axes, a mosaic tile) that is one
  uniform colour, such as a panorama that failed to stitch drawn as an empty canvas. A panel is
  a connected region of pixels that differ from the figure's background; it is blank when it
  is at least :data:`MIN_TILE` pixels on each side, fills its bounding box, and
  :data:`UNIFORM_SHARE` of its pixels are within :data:`COLOUR_TOL` of its median colour;
* an **empty band**: a subplot that drew nothing at a figure's edge (a row of tiles with
  no image). The inline backend crops a figure to what it drew, so its content reaches within
  a few pixels of every edge; a margin wider than :data:`MAX_MARGIN` pixels is an axes left
  empty (a tile that says what is missing, such as "no panorama", is not);
* **tiny legend text**: a legend whose font, at the size the page renders the figure, is
  smaller than :data:`MIN_LEGEND_PX` pixels. A figure wider than the text column
  (:data:`COLUMN_PX`, or :data:`FOLDED_COLUMN_PX` in a folded cell; measured in the browser by
  ``tests/test_book_browser.py``) is shrunk to it; the legend's size is the ``fontsize`` of
  the cell's ``legend`` calls (or the book style's ``legend.fontsize``), or, in a cell that
  draws no legend of its own, that of the ``clap_unified.viz`` functions it calls;
* **tiny titles or tick labels**: the same rule for the titles (``set_title``, ``suptitle``,
  ``title``; the book style's ``axes.titlesize`` when no ``fontsize`` is given) and tick
  labels (``tick_params(labelsize=...)``, or the style's ``xtick.labelsize`` in a cell whose
  axes are not all switched off) of the cell and of the ``clap_unified.viz`` functions it
  calls;
* **an unused grid slot**: in a grid of image tiles (a mosaic), a slot with no tile while
  its row and its column both hold tiles elsewhere, such as an axes left empty in the middle
  of the grid (a whole empty last row is an empty band, above).
"""

from __future__ import annotations

import ast
import base64
import io
import json
import re
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parent.parent
BOOK = ROOT / "book" / "chapters"
CHAPTERS = sorted(BOOK.glob("*.ipynb"))

#: Width of the book's text column in CSS pixels at the browser test's 1280 px window, and of
#: a folded cell's (``hide-cell``: an exercise's solution), whose frame takes a little of it.
COLUMN_PX = 660
FOLDED_COLUMN_PX = 638
MIN_LEGEND_PX = 8.0
MIN_TILE = 40
UNIFORM_SHARE = 0.97
COLOUR_TOL = 0.04
MAX_MARGIN = 120  # px: a figure's margins are 7 to 40 px; an empty row of tiles, 150 or more
#: Tags under which a cell's outputs are not on the page.
NOT_SHOWN = {"remove-cell", "remove-output"}

#: Matplotlib's relative font sizes (``"small"`` is 0.833 x ``font.size``).
RELATIVE = {"xx-small": 0.579, "x-small": 0.694, "small": 0.833, "medium": 1.0,
            "large": 1.2, "x-large": 1.44, "xx-large": 1.728}


def _text(value) -> str:
    return "".join(value) if isinstance(value, list) else str(value)


def _png(b64: str) -> np.ndarray:
    import matplotlib.image as mpimg

    image = mpimg.imread(io.BytesIO(base64.b64decode(b64)), format="png")
    return image[..., :3] if image.ndim == 3 else np.repeat(image[..., None], 3, axis=2)


def blank_tiles(image: np.ndarray) -> list[tuple[int, int, int, int]]:
    """The uniform panels of one figure, as ``(top, left, height, width)``."""
    from scipy import ndimage

    rgb = np.asarray(image, dtype=float)
    border = np.concatenate([rgb[0], rgb[-1], rgb[:, 0], rgb[:, -1]])
    background = np.median(border, axis=0)
    content = np.abs(rgb - background).max(axis=2) > COLOUR_TOL
    labels, _ = ndimage.label(content)
    tiles = []
    for index, box in enumerate(ndimage.find_objects(labels), start=1):
        height = box[0].stop - box[0].start
        width = box[1].stop - box[1].start
        if height < MIN_TILE or width < MIN_TILE:
            continue
        mask = labels[box] == index
        if mask.mean() < 0.9:  # lines, markers, text: not a filled panel
            continue
        pixels = rgb[box][mask]
        close = np.abs(pixels - np.median(pixels, axis=0)).max(axis=1) <= COLOUR_TOL
        if close.mean() >= UNIFORM_SHARE:
            tiles.append((box[0].start, box[1].start, height, width))
    return tiles


def empty_bands(image: np.ndarray) -> list[str]:
    """The edges of one figure with more than :data:`MAX_MARGIN` empty pixels before content."""
    rgb = np.asarray(image, dtype=float)
    border = np.concatenate([rgb[0], rgb[-1], rgb[:, 0], rgb[:, -1]])
    content = np.abs(rgb - np.median(border, axis=0)).max(axis=2) > COLOUR_TOL
    rows, cols = np.flatnonzero(content.any(axis=1)), np.flatnonzero(content.any(axis=0))
    if not len(rows):
        return ["the whole figure"]
    margins = {"top": rows[0], "bottom": rgb.shape[0] - 1 - rows[-1],
               "left": cols[0], "right": rgb.shape[1] - 1 - cols[-1]}
    return [f"{edge} ({px} px)" for edge, px in margins.items() if px > MAX_MARGIN]


def _book_rc() -> dict:
    from clap_unified.viz.style import BOOK_RC

    return BOOK_RC


def _size_pt(value, rc) -> float | None:
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return float(value)
    if isinstance(value, str) and value in RELATIVE:
        return RELATIVE[value] * rc["font.size"]
    return None


def _legend_sizes(tree: ast.AST, rc) -> list[float]:
    """The font sizes (points) of the ``legend`` calls in one piece of code."""
    sizes = []
    for node in ast.walk(tree):
        if (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute)
                and node.func.attr == "legend"):
            size = rc["legend.fontsize"]
            for kw in node.keywords:
                if kw.arg == "fontsize" and isinstance(kw.value, ast.Constant):
                    size = _size_pt(kw.value.value, rc) or size
                if kw.arg == "prop" and isinstance(kw.value, ast.Dict):
                    for k, v in zip(kw.value.keys, kw.value.values, strict=True):
                        if isinstance(k, ast.Constant) and k.value == "size" \
                                and isinstance(v, ast.Constant):
                            size = _size_pt(v.value, rc) or size
            sizes.append(size)
    return sizes


TITLE_CALLS = {"set_title": "axes.titlesize", "title": "axes.titlesize",
               "suptitle": "figure.titlesize"}


def _turns_axes_off(tree: ast.AST) -> bool:
    return any(isinstance(n, ast.Call) and isinstance(n.func, ast.Attribute)
               and (n.func.attr == "set_axis_off" or (n.func.attr == "axis" and n.args and (
                   isinstance(n.args[0], ast.Constant) and n.args[0].value in ("off", False))))
               for n in ast.walk(tree))


def _axes_off_functions() -> set[str]:
    """The functions of ``clap_unified.viz`` and ``clap_unified.reproduce`` that switch their
    axes off (image grids: no tick labels)."""
    functions = [node for folder in ("viz", "reproduce")
                 for path in sorted((ROOT / "clap_unified" / folder).glob("*.py"))
                 for node in ast.walk(ast.parse(path.read_text(encoding="utf-8")))
                 if isinstance(node, ast.FunctionDef)]
    names = {f.name for f in functions if _turns_axes_off(f)}
    while True:  # and those that call one of them (a figure built by a helper)
        more = {f.name for f in functions if f.name not in names and any(
            isinstance(n, ast.Call) and getattr(n.func, "id", None) in names
            for n in ast.walk(f))}
        if not more:
            return names
        names |= more


def _text_sizes(tree: ast.AST, rc, axes_off=frozenset()) -> list[tuple[str, float]]:
    """The ``(what, points)`` of the titles and tick labels one piece of code sets (the
    style's tick labels unless its axes, or those of a function in ``axes_off`` it calls,
    are switched off)."""
    found = []
    axis_off = _turns_axes_off(tree) or any(
        isinstance(n, ast.Call) and (getattr(n.func, "id", None) in axes_off
                                     or getattr(n.func, "attr", None) in axes_off)
        for n in ast.walk(tree))
    for node in ast.walk(tree):
        if not (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute)):
            continue
        name = node.func.attr
        if name in TITLE_CALLS:
            size = _size_pt(rc.get(TITLE_CALLS[name], "large"), rc) or rc["font.size"]
            for kw in node.keywords:
                if kw.arg in ("fontsize", "size") and isinstance(kw.value, ast.Constant):
                    size = _size_pt(kw.value.value, rc) or size
            found.append(("title", size))
        if (name == "set_fontsize" and node.args and isinstance(node.args[0], ast.Constant)
                and isinstance(node.func.value, ast.Attribute)
                and node.func.value.attr == "title"):  # ax.title.set_fontsize(9)
            found.append(("title", _size_pt(node.args[0].value, rc) or rc["font.size"]))
        if name == "tick_params":
            for kw in node.keywords:
                if kw.arg == "labelsize" and isinstance(kw.value, ast.Constant):
                    found.append(("tick labels", _size_pt(kw.value.value, rc)
                                  or rc["xtick.labelsize"]))
    if not axis_off and not any(what == "tick labels" for what, _ in found):
        found.append(("tick labels", _size_pt(rc["xtick.labelsize"], rc)))
    return found


def _viz_functions():
    """Every function defined in ``clap_unified.viz``, as an AST node."""
    for path in sorted((ROOT / "clap_unified" / "viz").glob("*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        yield from (n for n in ast.walk(tree) if isinstance(n, ast.FunctionDef))


def _library_texts() -> dict[str, list[tuple[str, float]]]:
    """The title and tick-label sizes each function of ``clap_unified.viz`` sets, by name
    (only those it sets explicitly: a function drawing on the caller's axes keeps the
    caller's tick labels)."""
    rc = _book_rc()
    found = {}
    for node in _viz_functions():
        sizes = [t for t in _text_sizes(node, rc) if t[0] == "title" or _sets_ticks(node)]
        if sizes:
            found.setdefault(node.name, []).extend(sizes)
    return found


def _sets_ticks(tree: ast.AST) -> bool:
    return any(isinstance(n, ast.Call) and isinstance(n.func, ast.Attribute)
               and n.func.attr == "tick_params" for n in ast.walk(tree))


def text_sizes(source: str, library: dict, rc) -> list[tuple[str, float]]:
    """The title and tick-label sizes one cell's figures use (its own and the library's)."""
    try:
        tree = ast.parse(source)
    except SyntaxError:
        return []
    sizes = _text_sizes(tree, rc, _axes_off_functions())
    for node in ast.walk(tree):
        if isinstance(node, ast.Call):
            name = (node.func.id if isinstance(node.func, ast.Name)
                    else node.func.attr if isinstance(node.func, ast.Attribute) else None)
            sizes.extend(library.get(name, []))
    return sizes


def unused_slots(image: np.ndarray) -> list[tuple[int, int]]:
    """The empty middle slots ``(row, column)`` of a grid of image tiles.

    Tiles are regions that fill their bounding box (images), grouped into rows and columns
    by their centres. A slot is unused when nothing at all is drawn where its row meets its
    column (no tile, no text saying what is missing) and a tile comes after it in reading
    order: a hole in the grid, not the end of a last row that is only partly filled.
    """
    from scipy import ndimage

    rgb = np.asarray(image, dtype=float)
    border = np.concatenate([rgb[0], rgb[-1], rgb[:, 0], rgb[:, -1]])
    content = np.abs(rgb - np.median(border, axis=0)).max(axis=2) > COLOUR_TOL
    labels, _ = ndimage.label(content)
    boxes = []
    for index, box in enumerate(ndimage.find_objects(labels), start=1):
        h, w = box[0].stop - box[0].start, box[1].stop - box[1].start
        if h >= MIN_TILE and w >= MIN_TILE and (labels[box] == index).mean() >= 0.9:
            boxes.append((box[0].start, box[0].stop, box[1].start, box[1].stop))
    if len(boxes) < 3:
        return []

    def groups(lo, hi):
        """Group intervals whose centres lie within half the smaller one of each other."""
        centre, size = (lo + hi) / 2, hi - lo
        out = []
        for i in np.argsort(centre):
            if out and centre[i] - centre[out[-1][-1]] <= min(size[i], size[out[-1][-1]]) / 2:
                out[-1].append(i)
            else:
                out.append([i])
        index = np.empty(len(lo), int)
        for g, members in enumerate(out):
            index[members] = g
        return index, [(lo[m].min(), hi[m].max()) for m in out]

    b = np.array(boxes)
    rows, row_band = groups(b[:, 0], b[:, 1])
    cols, col_band = groups(b[:, 2], b[:, 3])
    if len(row_band) < 2 or len(col_band) < 2:
        return []  # one row or one column: no grid
    filled = set(zip(rows.tolist(), cols.tolist(), strict=True))
    last = max(filled)
    return [(r, c) for r in range(len(row_band)) for c in range(len(col_band))
            if (r, c) not in filled and (r, c) < last
            and not content[row_band[r][0]:row_band[r][1], col_band[c][0]:col_band[c][1]].any()]


def _library_legends() -> dict[str, list[float]]:
    """The legend font sizes each function of ``clap_unified.viz`` draws, by name."""
    rc = _book_rc()
    found = {}
    for node in _viz_functions():
        sizes = _legend_sizes(node, rc)
        if sizes:
            found.setdefault(node.name, []).extend(sizes)
    return found


def legend_sizes(source: str, library: dict[str, list[float]], rc) -> list[float]:
    """The legend font sizes (points) one cell's figures use."""
    try:
        tree = ast.parse(source)
    except SyntaxError:  # a cell with IPython syntax: no legend check
        return []
    sizes = _legend_sizes(tree, rc)
    if sizes:  # the cell draws its own legends, which replace a library function's
        return sizes
    for node in ast.walk(tree):
        if isinstance(node, ast.Call):
            name = (node.func.id if isinstance(node.func, ast.Name)
                    else node.func.attr if isinstance(node.func, ast.Attribute) else None)
            sizes.extend(library.get(name, []))
    return sizes


def rendered_px(size_pt: float, dpi: float, png_width: int, column: float = COLUMN_PX) -> float:
    """The on-page height in CSS pixels of a ``size_pt`` font in a figure ``png_width`` wide."""
    return size_pt * dpi / 72 * min(1.0, column / png_width)


def figure_defects(notebook: dict, library=None, rc=None, texts=None) -> list[str]:
    """Blank tiles, unused grid slots, tiny legends, titles and tick labels in one
    notebook's shown figures."""
    rc = rc or _book_rc()
    library = _library_legends() if library is None else library
    texts = _library_texts() if texts is None else texts
    defects = []
    for index, cell in enumerate(notebook["cells"]):
        if cell["cell_type"] != "code":
            continue
        if set(cell.get("metadata", {}).get("tags", [])) & NOT_SHOWN:
            continue
        pngs = [o["data"]["image/png"] for o in cell.get("outputs", [])
                if "image/png" in o.get("data", {})]
        if not pngs:
            continue
        sizes = legend_sizes(_text(cell["source"]), library, rc)
        others = text_sizes(_text(cell["source"]), texts, rc)
        tags = set(cell.get("metadata", {}).get("tags", []))
        column = FOLDED_COLUMN_PX if "hide-cell" in tags else COLUMN_PX
        for number, b64 in enumerate(pngs):
            image = _png(b64)
            where = f"cell {index}, figure {number}"
            for top, left, h, w in blank_tiles(image):
                defects.append(f"{where}: a blank {w} x {h} px tile at ({left}, {top})")
            for band in empty_bands(image):
                defects.append(f"{where}: an empty band at the {band}: a subplot drew nothing")
            for r, c in unused_slots(image):
                defects.append(f"{where}: an unused grid slot (row {r + 1}, column {c + 1}): "
                               "an axes left empty")
            for what, size in dict.fromkeys(others):
                px = rendered_px(size, rc["figure.dpi"], image.shape[1], column)
                if px < MIN_LEGEND_PX:
                    defects.append(f"{where}: {what} {size:g} pt render at {px:.1f} px (the "
                                   f"{image.shape[1]} px figure shrunk to the {column} px "
                                   f"column; at least {MIN_LEGEND_PX:g} px)")
            for size in sizes:
                px = rendered_px(size, rc["figure.dpi"], image.shape[1], column)
                if px < MIN_LEGEND_PX:
                    defects.append(f"{where}: legend text {size:g} pt renders at {px:.1f} px "
                                   f"(the {image.shape[1]} px figure shrunk to the "
                                   f"{column} px column; at least {MIN_LEGEND_PX:g} px)")
    return defects


def _param(path: Path):
    return pytest.param(path, id=path.stem)


@pytest.mark.parametrize("path", [_param(p) for p in CHAPTERS])
def test_chapter_figures_are_readable(path):
    defects = figure_defects(json.loads(path.read_text(encoding="utf-8")))
    assert not defects, f"{path.name}:\n" + "\n".join(defects)


# ----------------------------------------------------------------- the checks can fail
def _figure_png(draw, figsize=(8, 3.6)) -> str:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig = plt.figure(figsize=figsize, dpi=100, layout="constrained")
    draw(fig)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=100, bbox_inches="tight")  # as the inline backend
    plt.close(fig)
    return base64.b64encode(buf.getvalue()).decode()


def _cell(source, png, tags=()):
    return {"cell_type": "code", "source": source, "metadata": {"tags": list(tags)},
            "outputs": [{"output_type": "display_data",
                         "data": {"image/png": png, "text/plain": "<Figure>"}}]}


def _mosaic(fig, blank: bool, empty_row: bool = False):
    rng = np.random.default_rng(0)
    axes = fig.subplots(2, 3).ravel()
    for i, ax in enumerate(axes):
        ax.axis("off")
        ax.set_title(f"tile {i}")
        if empty_row and i >= 3:  # refused panoramas drawn as nothing at all
            continue
        tile = rng.uniform(size=(60, 80, 3))
        if blank and i == 1:
            tile[:] = 0.2  # a panorama that did not stitch: one flat colour
        ax.imshow(tile)


def _curves(fig):
    ax = fig.subplots()
    x = np.linspace(0, 1, 50)
    ax.plot(x, x, label="a")
    ax.plot(x, x**2, label="b")
    ax.bar([0.2, 0.5], [0.3, 0.6], width=0.1)
    ax.legend()


def test_a_blank_tile_or_an_empty_row_fails_and_a_full_mosaic_passes():
    rc = _book_rc()
    good = _cell("show_mosaic()", _figure_png(lambda f: _mosaic(f, blank=False)))
    bad = _cell("show_mosaic()", _figure_png(lambda f: _mosaic(f, blank=True)))
    hidden = _cell("show_mosaic()", bad["outputs"][0]["data"]["image/png"], tags=["remove-cell"])
    curves = _cell("plt.show()", _figure_png(_curves))
    empty = _cell("show_mosaic()", _figure_png(lambda f: _mosaic(f, False, empty_row=True),
                                               figsize=(8, 4.8)))
    defects = figure_defects({"cells": [good, bad, hidden, curves, empty]}, library={}, rc=rc,
                             texts={})
    assert len(defects) == 2, defects
    assert defects[0].startswith("cell 1, figure 0: a blank")
    assert defects[1].startswith("cell 4, figure 0: an empty band at the bottom")


def test_tiny_legend_text_fails():
    rc = _book_rc()
    wide = _figure_png(_curves, figsize=(12, 4))  # 1200 px, shrunk to the column
    book = _figure_png(_curves, figsize=(10, 4))  # 1000 px, the widest book figures
    narrow = _figure_png(_curves, figsize=(7, 3))
    cells = [_cell('ax.legend(loc="upper left", fontsize=8)', wide),
             _cell("ax.legend()", book),
             _cell("ax.legend(fontsize=8)", narrow),
             _cell("draw_field(ax)", wide),
             _cell('ax.legend(fontsize="x-small")', book),
             _cell("draw_field(ax)\nax.legend(handles=h)", book)]
    defects = [d for d in figure_defects({"cells": cells}, library={"draw_field": [7.0]},
                                         rc=rc, texts={}) if "legend" in d]
    where = [d.split(":")[0] for d in defects]
    assert where == ["cell 0, figure 0", "cell 3, figure 0", "cell 4, figure 0"], defects
    assert "legend text 8 pt renders at" in defects[0]
    assert rendered_px(9, 100, 1200) == pytest.approx(9 * 100 / 72 * COLUMN_PX / 1200)
    assert rendered_px(9, 100, 500) == pytest.approx(12.5)  # never enlarged


def test_library_legend_sizes_are_read_from_the_viz_modules():
    library = _library_legends()
    # every entry is a positive size in points; the figures of the chapters call these
    assert library and all(s > 0 for sizes in library.values() for s in sizes)


def test_the_chapters_are_found():
    assert len(CHAPTERS) >= 9, CHAPTERS
    assert re.search(r"\d", CHAPTERS[0].name)


def test_tiny_titles_and_tick_labels_fail():
    rc = _book_rc()
    wide = _figure_png(_curves, figsize=(12, 4))  # 1200 px, shrunk to the column
    narrow = _figure_png(_curves, figsize=(7, 3))
    cells = [_cell('ax.set_title("a", fontsize=8)\nax.axis("off")', narrow),   # 11 px: fine
             _cell('ax.set_title("a", fontsize=8)\nax.axis("off")', wide),     # 6.1 px
             _cell("ax.tick_params(labelsize=8)", narrow),
             _cell("ax.plot(x)", wide),              # the style's 9 pt ticks: 6.9 px
             _cell('ax.axis("off")', wide),           # no ticks drawn, no title
             _cell("show_grid(axes)", wide),          # a library function's 8 pt titles
             _cell('ax.axis("off")\nax.title.set_fontsize(9)', wide)]  # 7.4 px
    defects = figure_defects({"cells": cells}, library={}, rc=rc,
                             texts={"show_grid": [("title", 8.0)]})
    where = [d.split(": ")[0] + ": " + d.split(": ")[1].split(" ")[0] for d in defects]
    assert where == ["cell 1, figure 0: title", "cell 3, figure 0: tick",
                     "cell 5, figure 0: tick", "cell 5, figure 0: title",
                     "cell 6, figure 0: title"], defects


def _grid(fig, hole=None, last_empty=False, say=False):
    rng = np.random.default_rng(1)
    axes = fig.subplots(2, 3).ravel()
    for i, ax in enumerate(axes):
        ax.axis("off")
        if i == hole:
            if say:
                ax.text(0.5, 0.5, "no panorama", ha="center", va="center")
            continue
        if last_empty and i == len(axes) - 1:
            continue
        ax.imshow(rng.uniform(size=(60, 80, 3)))


def test_an_unused_middle_slot_fails_and_a_short_last_row_passes():
    def slots(**kw):
        return unused_slots(_png(_figure_png(lambda f: _grid(f, **kw), figsize=(8, 4.8))))

    assert slots() == []
    assert slots(hole=1) == [(0, 1)]          # the middle of the first row
    assert slots(hole=3) == [(1, 0)]          # the start of the second row
    assert slots(last_empty=True) == []       # a last row only partly filled
    assert slots(hole=1, say=True) == []      # a tile that says what is missing
    cell = _cell("show_grid()", _figure_png(lambda f: _grid(f, hole=4), figsize=(8, 4.8)))
    defects = figure_defects({"cells": [cell]}, library={}, rc=_book_rc(), texts={})
    assert any("unused grid slot (row 2, column 2)" in d for d in defects), defects


def test_a_pose_marker_off_the_field_widens_the_view_instead_of_being_cut():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from clap_unified.maps.field import load_field
    from clap_unified.viz import draw_field, draw_pose

    fig, ax = plt.subplots()
    draw_field(ax, load_field("adult"))
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    draw_pose(ax, [[0.0, y1 - 0.1, np.pi / 2]], size=1.0)   # points up, past the top edge
    assert ax.get_ylim()[1] > y1 + 0.8 and ax.get_ylim()[0] == y0
    assert ax.get_xlim() == (x0, x1)                           # never narrowed, nor widened
    plt.close(fig)


def test_a_method_colour_marks_only_that_method():
    """Figure 2.1 promises each method's colour throughout the book: the truth and CLAP's
    second cluster get colours no method has, CLAP's first (or true) cluster CLAP's own, and
    the field figures of chapters 1, 3 and 4 take them from ``clap_unified.viz`` instead of
    the colour cycle (``"C1"`` is RANSAC's vermilion)."""
    import matplotlib.colors as mcolors

    from clap_unified.viz import CLUSTER_COLOURS, METHOD_STYLE, TRUTH_COLOUR
    from clap_unified.viz.stitching import HOMOGRAPHY_STYLE

    methods = {mcolors.to_hex(s["color"])
               for s in [*METHOD_STYLE.values(), *HOMOGRAPHY_STYLE.values()]}
    assert CLUSTER_COLOURS[0] == METHOD_STYLE["clap"]["color"]
    for colour in (TRUTH_COLOUR, *CLUSTER_COLOURS[1:]):
        assert mcolors.to_hex(colour) not in methods, colour
    for name in ("01_one_abstraction", "03_localization_2d", "04_localization_3d"):
        cells = json.loads((BOOK / f"{name}.ipynb").read_text())["cells"]
        code = "\n".join("".join(c["source"]) for c in cells if c["cell_type"] == "code")
        assert not re.search(r"""colou?rs?=\[?["']C\d["']""", code), name
        assert not re.search(r"#D55E00", code), name  # RANSAC's colour, for no other thing
