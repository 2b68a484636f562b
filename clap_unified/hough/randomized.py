"""Randomized Hough: minimal-sample hypotheses binned on a grid in a log chart.

Where the classical transform lets every datum vote for every compatible
model, the randomized transform lets each *hypothesis* (from a minimal
sample) cast one vote, in the cell of its logarithm at a base point. It is
CLAP with the density estimated by a histogram: the same hypotheses can be
given to both.
"""

from __future__ import annotations

import numpy as np

from .._validation import check_int
from ..fitting import fit
from ..registry import Strategy, register_strategy
from ..result import Cluster, Consensus, ConsensusResult, runner_up_ratio
from ..spaces.base import HypothesisSet
from .peaks import sparse_peaks

__all__ = ["bin_hypotheses", "randomized_hough", "run_randomized_hough"]


def bin_hypotheses(manifold, models, cell_size, base_point=None, *, coordinates=None,
                   periods=None):
    """Cells of hypotheses on a grid in the (weighted) log chart at ``base_point``.

    Parameters
    ----------
    manifold : Manifold
    models : ndarray of shape (H,) + point_shape
    cell_size : float or array_like of shape (d,)
        Cell edge per coordinate.
    base_point : ndarray, optional
        Where the log chart is taken (ignored with ``coordinates``).
    coordinates : callable, optional
        ``models -> (H, d)`` coordinates to bin instead of the log chart,
        e.g. ``SE2.to_xytheta`` for an ``(x, y, theta)`` grid.
    periods : sequence of float or None, optional
        Period of each coordinate (``None``: not periodic). A periodic
        coordinate's cells wrap around, so the period must be a whole number
        of cells.

    Returns
    -------
    cells : ndarray of int, shape (C, dim)
        Occupied cells.
    counts : ndarray of int, shape (C,)
    cell_of : ndarray of int, shape (H,)
        Index into ``cells`` of every hypothesis.
    """
    if coordinates is None:
        base = manifold.reference_point() if base_point is None else base_point
        coords = manifold.log(models, base) * manifold.tangent_weights
        if np.iscomplexobj(coords):
            coords = coords.real
    else:
        coords = np.asarray(coordinates(models), dtype=float).reshape(len(models), -1)
    cell_size = np.broadcast_to(np.asarray(cell_size, dtype=float), coords.shape[1:])
    keys = np.floor(coords / cell_size).astype(np.int64)
    if periods is not None:
        for k, period in enumerate(periods):
            if period is None:
                continue
            n_cells = period / cell_size[k]
            if abs(n_cells - round(n_cells)) > 1e-9 * n_cells:
                raise ValueError(f"cell_size: {cell_size[k]:g} does not divide the period "
                                 f"{period:g} of coordinate {k}")
            keys[:, k] %= int(round(n_cells))
    cells, cell_of, counts = np.unique(keys, axis=0, return_inverse=True, return_counts=True)
    return cells, counts, cell_of.reshape(-1)


def randomized_hough(space, data, **options) -> ConsensusResult:
    """Randomized Hough: :func:`~clap_unified.fit` with ``method="randomized_hough"``.

    Its own options are documented at :func:`run_randomized_hough`.

    Examples
    --------
    >>> from clap_unified.spaces import LineSpace
    >>> rng = np.random.default_rng(0)
    >>> x = rng.uniform(-5, 5, 80)
    >>> pts = np.c_[x, 0.5 * x + 1 + rng.normal(0, 0.01, 80)]
    >>> pts[:40] = rng.uniform(-5, 5, (40, 2))
    >>> res = randomized_hough(LineSpace.for_data(pts), pts, threshold=0.05, cell_size=0.1,
    ...                        rng=0)
    >>> res.success, res.n_inliers >= 40
    (True, True)
    """
    return fit(space, data, "randomized_hough", **options)


def run_randomized_hough(space, data, hypotheses: HypothesisSet, *, threshold: float,
                         prior=None, radius=None, rng=None, n_hypotheses: int = 0,
                         cell_size=None, base_point=None, coordinates=None, periods=None,
                         recentre: bool = True, num_peaks: int = 5,
                         min_distance: int = 1) -> Consensus:
    """The randomized Hough strategy: vote hypotheses into grid cells, the fullest wins.

    Parameters
    ----------
    space : HypothesisSpace
    data : ndarray
        Checked data (unused: the vote is in hypothesis space).
    hypotheses : HypothesisSet
    threshold, prior, radius, rng, n_hypotheses
        Unused here (see :func:`~clap_unified.fit`).
    cell_size : float or array_like of shape (d,), optional
        Cell edge in the manifold's weighted tangent coordinates (the same
        units as its distance), or per coordinate. Default
        ``space.default_cell_size(data)``.
    base_point : ndarray, optional
        Where the chart is taken; default the manifold's reference point.
    coordinates : callable, optional
        Bin ``coordinates(models)`` (shape ``(H, d)``) instead of the log
        chart. Default: the space's own grid (``space.hough_grid()``, e.g.
        ``(x, y, theta)`` for planar poses) when it declares ``grid``.
    periods : sequence of float or None, optional
        Periods of the ``coordinates`` (see :func:`bin_hypotheses`).
    recentre : bool
        Bin a second time in the chart at the first peak, so the peak does not
        sit on a chart seam or far from the base where the chart distorts
        (log chart only).
    num_peaks, min_distance : int
        Peaks to report and their separation in cells.

    Returns
    -------
    Consensus
        The estimate is the mean of the hypotheses in the best cell.
    """
    if coordinates is None and space.capabilities.grid:
        coordinates, grid_periods = space.hough_grid()
        periods = grid_periods if periods is None else periods
    if cell_size is None:
        cell_size = space.default_cell_size(data)
    cell = np.asarray(cell_size, dtype=float)
    if cell.ndim > 1 or not np.all(np.isfinite(cell)) or np.any(cell <= 0):
        raise ValueError(f"cell_size: expected a positive number or a 1D array of them, "
                         f"got {cell_size!r}")
    cell = float(cell) if cell.ndim == 0 else cell
    num_peaks = check_int(num_peaks, "num_peaks", minimum=1)
    models = hypotheses.models
    manifold = space.manifold
    h = len(models)
    diag = {"cell_size": cell}
    half_cell = float(np.max(cell)) / 2

    def vote(base):
        cells, counts, cell_of = bin_hypotheses(manifold, models, cell, base,
                                                coordinates=coordinates, periods=periods)
        return cells, counts, cell_of, sparse_peaks(cells, counts, min_distance=min_distance,
                                                    num_peaks=num_peaks)

    cells, counts, cell_of, peaks = vote(base_point)
    diag["occupied_cells"] = len(cells)
    if recentre and coordinates is None:
        first = np.flatnonzero(cell_of == peaks[0])
        base, why = _cell_mean(manifold, models[first])
        if base is None:
            return Consensus.failed(f"the mean of the {len(first)} hypotheses in the fullest "
                                    f"cell is no model ({why})", **diag)
        cells, counts, cell_of, peaks = vote(base)
        diag["occupied_cells"] = len(cells)
    clusters = []
    for rank, p in enumerate(peaks):
        members = np.flatnonzero(cell_of == p)
        centre, why = _cell_mean(manifold, models[members])
        if centre is None:
            if rank == 0:  # the fullest cell is the answer: no answer, not a lesser one
                return Consensus.failed(f"the mean of the {len(members)} hypotheses in the "
                                        f"fullest cell is no model ({why})", **diag)
            diag["dropped_peaks"] = diag.get("dropped_peaks", 0) + 1
            continue
        clusters.append(Cluster(centre, int(counts[p]), half_cell, members))
    diag["runner_up_ratio"] = runner_up_ratio(clusters)
    support = np.zeros(h, bool)
    support[clusters[0].members] = True
    return Consensus(clusters[0].model, tuple(clusters), support,
                     float(clusters[0].support), "ok", diag)


def _cell_mean(manifold, models):
    """``(mean, "")`` of a cell's hypotheses, or ``(None, why)`` when the manifold refuses it.

    The mean of valid models need not be one (the mean of homographies can be
    singular, or send the image origin to infinity): the manifold then raises
    ``ValueError`` naming what is wrong, and the vote has no answer there.
    """
    try:
        return manifold.mean(models, max_iter=20), ""
    except ValueError as exc:
        return None, str(exc)


register_strategy(Strategy(
    "randomized_hough", run_randomized_hough,
    summary="hypotheses vote into cells of a grid; the fullest cell wins"))
