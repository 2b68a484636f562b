"""One numbered figure per notebook cell, and a warning for any figure without caption or alt.

myst-nb wraps *every* display output of a cell whose metadata has ``mystnb.figure`` in a
figure with that caption. This transform keeps one figure per cell: outputs that are not
images (a ``Text(...)`` repr, a table printed by the same cell) are unwrapped, and the images
of a cell that draws several (one plot call per panel group) are gathered into the cell's
first figure, under its one caption. A figure with no ``name`` gets an id so that it is
numbered. Then every image in a cell output must be in a figure with a caption and have alt
text: otherwise a warning, which the book's ``-W`` build turns into an error.
"""

from __future__ import annotations

from docutils import nodes
from sphinx.transforms import SphinxTransform
from sphinx.util import logging

logger = logging.getLogger(__name__)


def _has_image(node: nodes.Node) -> bool:
    return any(
        str(c.get("mime_type", "")).startswith("image/")
        for c in node.findall(nodes.container)
    ) or any(True for _ in node.findall(nodes.image))


def _unwrap(figure: nodes.figure) -> None:
    keep = [c for c in figure.children if not isinstance(c, (nodes.caption, nodes.legend))]
    figure.replace_self(keep)


class CellFigures(SphinxTransform):
    default_priority = 400

    def apply(self, **kwargs) -> None:
        for cell in list(self.document.findall(nodes.container)):
            if cell.get("nb_element") != "cell_code":
                continue
            figures = [f for f in cell.findall(nodes.figure)]
            with_image = [f for f in figures if _has_image(f)]
            for f in figures:
                if f not in with_image:
                    _unwrap(f)
            if len(with_image) > 1:
                first = with_image[0]
                caption_at = next((i for i, c in enumerate(first.children)
                                   if isinstance(c, nodes.caption)), len(first.children))
                moved = []
                for f in with_image[1:]:
                    moved += [c for c in f.children
                              if not isinstance(c, (nodes.caption, nodes.legend))]
                    f.parent.remove(f)
                for k, child in enumerate(moved):
                    first.insert(caption_at + k, child)
            for f in with_image[:1]:
                if not f["ids"]:
                    self.document.set_id(f)
            self._check(cell)

    def _check(self, cell: nodes.container) -> None:
        for container in cell.findall(nodes.container):
            if not str(container.get("mime_type", "")).startswith("image/"):
                continue
            figure = container.parent
            while figure is not None and not isinstance(figure, nodes.figure):
                figure = figure.parent
            where = (self.env.docname, cell.get("cell_index"))
            if figure is None or not any(isinstance(c, nodes.caption) for c in figure.children):
                logger.warning("figure without a caption in %s, cell %s "
                               "(set mystnb.figure.caption in the cell's metadata)", *where,
                               location=cell)
            for image in container.findall(nodes.image):
                if not image.get("alt"):
                    logger.warning("image without alt text in %s, cell %s "
                                   "(set mystnb.image.alt in the cell's metadata)", *where,
                                   location=cell)


def setup(app):
    app.add_transform(CellFigures)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
