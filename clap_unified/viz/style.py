"""The book style: print precision, figure defaults, method colours, tables."""

from __future__ import annotations

import numpy as np

__all__ = ["CANDIDATE_COLOUR", "CLUSTER_COLOURS", "METHOD_STYLE", "TRUTH_COLOUR", "book_style",
           "format_table", "markdown_table"]

# Okabe-Ito colours: distinguishable with the common colour-vision deficiencies.
_PALETTE = ["#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#000000"]

#: Colour, marker, line style and label of every method drawn in the book. Methods that
#: share hypotheses and the refit often end on the same estimate, so their curves coincide:
#: the line styles and markers differ as well as the colours, so that each stays visible
#: where they overlap.
METHOD_STYLE = {
    "hough": {"color": "#0072B2", "marker": "s", "linestyle": "-",
              "label": "Hough (classical)"},
    "randomized_hough": {"color": "#56B4E9", "marker": "D", "linestyle": "-.",
                         "label": "randomized Hough"},
    "ransac": {"color": "#D55E00", "marker": "o", "linestyle": "--", "label": "RANSAC"},
    "clap": {"color": "#009E73", "marker": "^", "linestyle": "-", "label": "CLAP"},
    "skimage_ransac": {"color": "#E69F00", "marker": "v", "linestyle": ":",
                       "label": "skimage ransac"},
    "cv2_hough": {"color": "#CC79A7", "marker": "P", "linestyle": (0, (5, 1, 1, 1)),
                  "label": "cv2.HoughLinesPointSet"},
    "open3d": {"color": "#CC79A7", "marker": "s", "linestyle": ":", "label": "Open3D RANSAC"},
}

#: The truth in figures (a true line, pose or structure): a colour no method has.
TRUTH_COLOUR = "crimson"
#: Candidate hypotheses drawn behind the answers.
CANDIDATE_COLOUR = "0.6"
#: CLAP's clusters, where a figure tells two apart: the first (or the one at the truth) in
#: CLAP's own colour, the other in a purple no method has, so that in a figure of methods a
#: method's colour marks nothing else.
CLUSTER_COLOURS = (METHOD_STYLE["clap"]["color"], "#7B3294")


#: Matplotlib settings applied by :func:`book_style`.
BOOK_RC = {
    "figure.figsize": (8.0, 3.6),
    "figure.dpi": 100,
    "savefig.dpi": 100,
    "figure.constrained_layout.use": True,
    "font.size": 10,
    "axes.titlesize": 10,
    "axes.labelsize": 10,
    "legend.fontsize": 9,
    "xtick.labelsize": 9,
    "ytick.labelsize": 9,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "grid.linewidth": 0.6,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "image.cmap": "viridis",
    "lines.linewidth": 1.6,
    "lines.markersize": 5,
    "legend.frameon": False,
}


def book_style() -> None:
    """Set the book's print precision and figure style.

    NumPy prints four decimals without scientific notation
    (``np.set_printoptions(precision=4, suppress=True)``); Matplotlib figures
    are 8 x 3.6 inches at 100 dpi with a colour-blind-safe colour cycle.
    The backend is not changed: in Jupyter the inline (PNG) backend stays.
    """
    import matplotlib as mpl
    from cycler import cycler

    np.set_printoptions(precision=4, suppress=True)
    mpl.rcParams.update(BOOK_RC)
    mpl.rcParams["axes.prop_cycle"] = cycler(color=_PALETTE)


def format_table(rows, columns) -> str:
    """A plain-text table with one explicit format per column.

    Parameters
    ----------
    rows : sequence of sequences
        One row per line, values in the order of ``columns``.
    columns : sequence of (str, str)
        ``(header, format_spec)`` pairs, e.g. ``("angle [deg]", ".3f")``;
        the format spec also fixes the column's alignment and width.

    Returns
    -------
    str

    Examples
    --------
    >>> print(format_table([["clap", 0.01234, 95], ["ransac", 1.5, 88]],
    ...                    [("method", "<8"), ("angle [deg]", "11.3f"), ("inliers", "7d")]))
    method   angle [deg] inliers
    clap           0.012      95
    ransac         1.500      88
    """
    columns = list(columns)
    cells = [[format(v, spec) for v, (_, spec) in zip(row, columns, strict=True)] for row in rows]
    widths = [max([len(h)] + [len(r[i]) for r in cells]) for i, (h, _) in enumerate(columns)]
    left = [spec.startswith("<") or spec == "s" for _, spec in columns]

    def line(values):
        out = [v.ljust(w) if lft else v.rjust(w) for v, w, lft in zip(values, widths, left,
                                                                      strict=True)]
        return " ".join(out).rstrip()

    return "\n".join([line([h for h, _ in columns])] + [line(r) for r in cells])


def markdown_table(rows, columns) -> str:
    """The same table as :func:`format_table`, as Markdown (rendered to HTML in the book).

    A Markdown table wraps to the text column where a printed one scrolls; in a notebook,
    show it with ``IPython.display.Markdown(markdown_table(...))``.

    Parameters
    ----------
    rows : sequence of sequences
        One row per line, values in the order of ``columns``.
    columns : sequence of (str, str)
        ``(header, format_spec)`` pairs; a spec starting with ``<`` (or ``"s"``) aligns the
        column left, any other right.

    Returns
    -------
    str

    Examples
    --------
    >>> print(markdown_table([["clap", 0.01234, 95], ["ransac", 1.5, 88]],
    ...                      [("method", "<8"), ("angle [deg]", ".3f"), ("inliers", "d")]))
    | method | angle [deg] | inliers |
    |:--|--:|--:|
    | clap | 0.012 | 95 |
    | ransac | 1.500 | 88 |
    """
    columns = list(columns)
    cells = [[format(v, spec).strip() for v, (_, spec) in zip(row, columns, strict=True)]
             for row in rows]
    align = [":--" if spec.startswith("<") or spec == "s" else "--:" for _, spec in columns]
    lines = ["| " + " | ".join(h for h, _ in columns) + " |", "|" + "|".join(align) + "|"]
    lines += ["| " + " | ".join(c.replace("|", "\\|") for c in r) + " |" for r in cells]
    return "\n".join(lines)
