"""Plotting, printing and small synthetic scenes for the book.

Nothing in the estimators depends on this subpackage. The chapters of the
book import it so their cells stay short: one :func:`book_style` call at the
top of a chapter fixes print precision and figure style (which is what keeps
notebook outputs stable under ``pytest --nbval``), and the ``plot_*`` helpers
draw on a Matplotlib ``Axes`` the chapter passes in. The backend is never
touched here.

:func:`line_scene` returns a :class:`LineScene` split into ``input`` (the
noisy points, the only thing an estimator gets) and ``truth`` (labels and
true lines, for scoring).
"""

from .field import LANDMARK_STYLE, draw_detections, draw_field, draw_pose
from .plots import (
    plot_accumulator,
    plot_error_cdf,
    plot_error_curves,
    plot_hypotheses,
    plot_points_and_lines,
)
from .scenes import LineInput, LineScene, LineTruth, line_errors, line_scene
from .style import (
    CANDIDATE_COLOUR,
    CLUSTER_COLOURS,
    METHOD_STYLE,
    TRUTH_COLOUR,
    book_style,
    format_table,
    markdown_table,
)

__all__ = [
    "CANDIDATE_COLOUR",
    "CLUSTER_COLOURS",
    "LANDMARK_STYLE",
    "METHOD_STYLE",
    "LineInput",
    "LineScene",
    "LineTruth",
    "TRUTH_COLOUR",
    "book_style",
    "draw_detections",
    "draw_field",
    "draw_pose",
    "format_table",
    "markdown_table",
    "line_errors",
    "line_scene",
    "plot_accumulator",
    "plot_error_cdf",
    "plot_error_curves",
    "plot_hypotheses",
    "plot_points_and_lines",
]
