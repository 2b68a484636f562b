"""Command ``clap-unified segment {line,circle,homography}``: every model in one data file.

The multi-model counterpart of ``fit``: it reads the same CSV files with the same reader
(:func:`~clap_unified.io.read_points_csv`, the same messages), runs
:func:`~clap_unified.segment` and prints
:meth:`SegmentationResult.to_dict() <clap_unified.SegmentationResult.to_dict>`. Exit status 0
when at least one model was found, 1 when none was (the JSON says why, every label -1), 2 for
bad input (the common convention, :data:`~clap_unified.cli.EXIT_STATUS`).

Each kind is one entry of :data:`KINDS`: its space, the columns of a row and how the data are
segmented. Adding a kind is adding an entry; for matches, the kind's defaults are its
segmentation preset (:func:`~clap_unified.imaging.segment_matches.segment_preset`, in
:mod:`clap_unified.presets`), shared with the library, the benchmark and the book; the other
kinds run :func:`~clap_unified.segment`'s own defaults.
"""

from __future__ import annotations

import argparse
import inspect
import textwrap
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ._validation import Checked
from .cli import EXIT_STATUS, _Parser
from .imaging.segment_matches import segment_matches, segment_preset
from .io import MAX_HYPOTHESES, MAX_ROWS, float_option, int_option, read_points_csv
from .registry import segmenter_names
from .result import SegmentationResult
from .segmenting import segment
from .spaces import LineSpace
from .spaces.circles import CircleSpace
from .spaces.fundamental import FundamentalSpace
from .spaces.homography import HomographySpace

__all__ = ["KINDS", "MAX_SEGMENT_ROWS", "MAX_SEGMENT_WORK", "MAX_T_LINKAGE_ROWS", "SEGMENT_OUTPUT",
           "SegmentKind", "register", "segment_command"]

#: ``segment`` reads at most this many rows.
MAX_SEGMENT_ROWS = 100_000
#: ``--hypotheses`` times the number of rows at most: CLAP scores every hypothesis on every
#: datum, in time and memory proportional to this product.
MAX_SEGMENT_WORK = 50_000_000
#: ``--method t_linkage`` at most this many rows: it compares every pair of data, in time and
#: memory that grow as the square of the rows.
MAX_T_LINKAGE_ROWS = 2000

#: What ``segment`` prints, as its ``--help`` shows it.
SEGMENT_OUTPUT = """\
output:
  one JSON object on standard output: method, success, reason, models (each with model,
  support, score; best first), labels (one per row: the index of its model, -1 for an
  outlier), selection, data (rows), threshold, seconds. Finding no model is a failed
  estimate (exit 1): the JSON is printed with the reason and every label -1."""

#: ``segment``'s own defaults (for kinds without a preset).
_SEGMENT_DEFAULTS = inspect.signature(segment).parameters
_N_HYPOTHESES = _SEGMENT_DEFAULTS["n_hypotheses"].default


@dataclass(frozen=True)
class SegmentKind:
    """One ``segment`` kind: what a row holds and how its data are segmented.

    Attributes
    ----------
    space : callable
        ``space()``: the hypothesis space, for the ``--method`` choices
        (:func:`~clap_unified.registry.segmenter_names`).
    columns : int
        Numbers per CSV row.
    run : callable
        ``run(kind, data, method, threshold, n_hypotheses, seed, min_support, coherence) ->
        SegmentationResult``; ``None`` values take the kind's defaults.
    row : str
        The row, for the help (``"x,y"``).
    metavar : str
        The file argument (``"POINTS.csv"``).
    what : str
        One structure, for the help (``"2D lines"``).
    model : str
        The JSON form of one model, for the help.
    threshold : str
        The threshold's unit and default, for the help.
    n_hypotheses : int
        The default ``--hypotheses``.
    """

    space: Callable
    columns: int
    run: Callable
    row: str
    metavar: str
    what: str
    model: str
    threshold: str
    n_hypotheses: int


def _in_space(space: type, for_data: Callable) -> Callable:
    """A kind's ``run`` calling :func:`~clap_unified.segment` in ``for_data(data)``: the data
    checked once, by ``space().check_data``, then handed to both."""
    def run(kind, data, method, threshold, n_hypotheses, seed, min_support, coherence=None):
        data = Checked(space().check_data(data))
        return segment(for_data(data), data, method, n_hypotheses=n_hypotheses,
                       threshold=threshold, rng=seed, min_support=min_support,
                       coherence=(_SEGMENT_DEFAULTS["coherence"].default if coherence is None
                                  else coherence))
    return run


def _matches(kind, data, method, threshold, n_hypotheses, seed, min_support, coherence=None):
    """A kind's ``run`` for matches: :func:`~clap_unified.imaging.segment_matches.segment_matches`
    (its defaults are the kind's preset,
    :func:`~clap_unified.imaging.segment_matches.segment_preset`)."""
    return segment_matches(data, kind, method, threshold=threshold, rng=seed,
                           n_hypotheses=n_hypotheses, min_support=min_support,
                           coherence=coherence)


#: The kinds of ``segment``: name -> :class:`SegmentKind`.
KINDS = {
    "line": SegmentKind(
        space=LineSpace, columns=2,
        run=_in_space(LineSpace, lambda pts: LineSpace.for_data(pts, metric="transfer")),
        row="x,y", metavar="POINTS.csv", what="2D lines",
        model='{"normal": [a, b], "offset": c} (a*x + b*y = c)',
        threshold="distance in data units (default 2%% of the data's RMS radius, as fit line)",
        n_hypotheses=_N_HYPOTHESES),
    "circle": SegmentKind(
        space=CircleSpace, columns=2, run=_in_space(CircleSpace, lambda pts: CircleSpace()),
        row="x,y", metavar="POINTS.csv", what="circles",
        model='{"centre": [x, y], "radius": r}',
        threshold="distance in data units (default 1%% of the data's RMS radius)",
        n_hypotheses=_N_HYPOTHESES),
    "homography": SegmentKind(
        space=HomographySpace, columns=4, run=_matches,
        row="x1,y1,x2,y2", metavar="MATCHES.csv", what="homographies (planes)",
        model='{"H": 3 x 3 row-major, H33 = 1} mapping point 1 to point 2',
        threshold="reprojection error in pixels (default "
                  f"{segment_preset('homography').fit['threshold']:g})",
        n_hypotheses=segment_preset("homography").fit["n_hypotheses"]),
    "fundamental": SegmentKind(
        space=FundamentalSpace, columns=4, run=_matches,
        row="x1,y1,x2,y2", metavar="MATCHES.csv", what="fundamental matrices (rigid motions)",
        model='{"F": 3 x 3 row-major, unit norm} with x2^T F x1 = 0',
        threshold="Sampson error in pixels (default "
                  f"{segment_preset('fundamental').fit['threshold']:g})",
        n_hypotheses=segment_preset("fundamental").fit["n_hypotheses"]),
}


def register(sub) -> None:
    """Add ``segment`` and one sub-command per kind of :data:`KINDS`."""
    names = ",".join(KINDS)
    parser = sub.add_parser(
        "segment", help=f"find every model in data ({names.replace(',', ', ')})",
        description=textwrap.fill(  # the epilog keeps its layout: the description is wrapped
            "Find every model (several lines, circles, planes) in the data of a CSV file and "
            "which row belongs to which. Run 'clap-unified segment KIND --help' for a kind's "
            "input and options.", 92),
        epilog=f"{SEGMENT_OUTPUT}\n\n{EXIT_STATUS}",
        formatter_class=argparse.RawDescriptionHelpFormatter)
    kinds = parser.add_subparsers(dest="kind", required=True, parser_class=_Parser,
                                  metavar="{" + names + "}")
    for name, kind in KINDS.items():
        _add_kind(kinds, name, kind)


def _add_kind(kinds, name: str, kind: SegmentKind) -> None:
    p = kinds.add_parser(
        name, help=f"find every {name} in {kind.metavar} (rows {kind.row})",
        description=f"Find the {kind.what} in the rows of {kind.metavar} and which row belongs "
                    f"to which. Each model in the JSON is {kind.model}. Finding none is a "
                    "failed estimate (exit 1).",
        epilog=SEGMENT_OUTPUT)
    p.add_argument("data", metavar=kind.metavar,
                   help=f"CSV file, one row per datum: {kind.row} (header line optional; "
                        f"finite numbers; at most {MAX_SEGMENT_ROWS} rows)")
    methods = segmenter_names(kind.space())
    p.add_argument("--method", choices=list(methods), default="clap",
                   help="segmenter (default clap): clap (dense clusters of hypotheses), ransac "
                        "(sequential RANSAC), randomized_hough (accumulator peaks), t_linkage "
                        f"(at most {MAX_T_LINKAGE_ROWS} rows)"
                        + (", or another library's estimator in a remove-inliers loop"
                           if len(methods) > 4 else ""))
    p.add_argument("--threshold", type=float_option(), default=None, metavar="T",
                   help=f"inlier {kind.threshold}")
    p.add_argument("--seed", type=int_option(), default=0, metavar="N",
                   help="random seed (default 0; the same seed gives the same output)")
    p.add_argument("--hypotheses", type=int_option(1, MAX_HYPOTHESES), default=None, metavar="H",
                   help=f"hypotheses drawn (default {kind.n_hypotheses}); at most "
                        f"{MAX_HYPOTHESES}, and hypotheses x rows at most {MAX_SEGMENT_WORK:.0e}")
    p.add_argument("--min-support", type=int_option(1, MAX_ROWS), default=None, metavar="K",
                   help=f"rows a model must explain to be kept (at least "
                        f"{kind.space().min_samples}, one minimal sample; default the larger "
                        "of 10, two minimal samples and 2%% of the rows)")
    preset = segment_preset(name) if kind.run is _matches else None
    default = (_SEGMENT_DEFAULTS["coherence"].default if preset is None
               else preset.fit["coherence"])
    p.add_argument("--coherence", type=float_option(0.0, closed=True), default=None, metavar="W",
                   help="spatial coherence: the cost of two neighbouring rows on different "
                        "models, in units of an outlier's cost (0: each row to its nearest "
                        f"model; default {default:g})")
    p.set_defaults(run=segment_command, segment_kind=name)


def _check_size(args, kind: SegmentKind, n: int, n_hypotheses: int) -> None:
    """Refuse what would run for minutes or exhaust memory, naming the option."""
    if n_hypotheses * n > MAX_SEGMENT_WORK:
        raise ValueError(f"--hypotheses: {n_hypotheses} hypotheses on {n} rows exceed the limit "
                         f"of {MAX_SEGMENT_WORK:.0e} hypothesis-row pairs; use fewer hypotheses "
                         "or fewer rows")
    if args.method == "t_linkage" and n > MAX_T_LINKAGE_ROWS:
        raise ValueError(f"--method: t_linkage compares every pair of rows; {args.data} has {n}, "
                         f"at most {MAX_T_LINKAGE_ROWS} (use another method)")


def segment_command(args) -> dict:
    """Run ``segment KIND``: read, check, segment; the JSON form of the result."""
    name = args.segment_kind
    kind = KINDS[name]
    space = kind.space()
    if args.min_support is not None and args.min_support < space.min_samples:
        raise ValueError(f"--min-support: expected at least {space.min_samples} (one minimal "
                         f"sample of a {space.name}), got {args.min_support}")
    args.progress.stage("reading the data")
    data = read_points_csv(args.data, columns=kind.columns, min_rows=1,
                           max_rows=MAX_SEGMENT_ROWS)
    n_hypotheses = kind.n_hypotheses if args.hypotheses is None else args.hypotheses
    _check_size(args, kind, len(data), n_hypotheses)
    if len(data) < space.min_samples:  # too few for one model: a failed estimate, as fit's
        reason = f"need at least {space.min_samples} rows for one {space.name}, got {len(data)}"
        return _nothing(args.method, reason, len(data), space, args.threshold).to_dict()
    args.progress.stage(f"segmenting ({args.method}, {n_hypotheses} hypotheses)")
    return kind.run(name, data, args.method, args.threshold, n_hypotheses, args.seed,
                    args.min_support, args.coherence).to_dict()


def _nothing(method: str, reason: str, n: int, space, threshold) -> SegmentationResult:
    """No model: every row an outlier."""
    return SegmentationResult(method, False, reason, models=np.empty((0, *space.model_shape)),
                              labels=np.full(n, -1, np.intp), scores=np.zeros(0), space=space,
                              threshold=threshold)
