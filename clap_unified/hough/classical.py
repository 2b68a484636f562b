"""Classical line Hough transform: data vote on a grid, peaks are the lines.

:func:`run_hough` is the strategy registered as ``"hough"`` (lines only: the
data vote, no hypotheses); :func:`hough_lines` is :func:`~clap_unified.fit`
with that method.
"""

from __future__ import annotations

import numpy as np

from ..fitting import fit
from ..registry import Strategy, register_strategy
from ..result import Cluster, Consensus, ConsensusResult, runner_up_ratio
from ..spaces.lines import LineSpace
from .accumulator import line_accumulator, rho_step
from .peaks import accumulator_peaks

__all__ = ["hough_lines", "run_hough"]


def hough_lines(points, *, space: LineSpace | None = None, **options) -> ConsensusResult:
    """Fit lines by voting in ``(theta, rho)``: :func:`~clap_unified.fit` with ``method="hough"``.

    Parameters
    ----------
    points : ndarray of shape (N, 2)
    space : LineSpace, optional
        Only used to describe the model; default ``LineSpace.for_data(points)``.
    **options
        ``threshold`` (default: half a rho cell or the space's default,
        whichever is larger), ``refine`` and the options of :func:`run_hough`.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> x = rng.uniform(-5, 5, 50)
    >>> pts = np.r_[np.c_[x, 2 * x - 1], rng.uniform(-5, 5, (25, 2))]
    >>> res = hough_lines(pts, threshold=0.05)
    >>> res.success, res.n_inliers >= 50
    (True, True)
    """
    space = LineSpace.for_data(points) if space is None else space
    return fit(space, points, "hough", **options)


def run_hough(space, data, hypotheses=None, *, threshold: float, prior=None, radius=None,
              rng=None, n_hypotheses: int = 0, theta_resolution: float = np.pi / 180,
              rho_resolution: float | None = None, num_peaks: int = 5,
              min_distance: int = 5) -> Consensus:
    """The classical Hough strategy: every point votes for every angle.

    Local maxima of the accumulator (non-maximum suppression) are the lines,
    strongest first; the best peak is the consensus.

    Parameters
    ----------
    space : LineSpace
    data : ndarray of shape (N, 2)
    hypotheses, threshold, prior, radius, rng, n_hypotheses
        Unused: the data vote directly.
    theta_resolution, rho_resolution : float
        Grid steps (radians; data units, default 1/200 of the extent).
    num_peaks : int
        Peaks reported in ``clusters``.
    min_distance : int
        Minimum separation of peaks, in cells.

    Returns
    -------
    Consensus
        ``clusters`` holds each peak with its votes as support and half the
        rho cell as spread; ``diagnostics["accumulator"]`` the votes.
    """
    acc = line_accumulator(data, theta_resolution=theta_resolution,
                           rho_resolution=rho_resolution)
    dr = float(acc.rhos[1] - acc.rhos[0]) if len(acc.rhos) > 1 else 1.0
    peaks = accumulator_peaks(acc.votes, min_distance=min_distance, num_peaks=num_peaks,
                              threshold=2)
    diag = {"accumulator_shape": acc.votes.shape, "rho_resolution": dr,
            "theta_resolution": theta_resolution}
    if len(peaks) == 0:
        return Consensus.failed("no accumulator cell has 2 or more votes", **diag)
    clusters = tuple(Cluster(acc.line(i, j), int(acc.votes[i, j]), dr / 2) for i, j in peaks)
    diag["runner_up_ratio"] = runner_up_ratio(clusters)
    diag["accumulator"] = acc
    return Consensus(clusters[0].model, clusters, np.zeros(0, bool),
                     float(clusters[0].support), "ok", diag)


def _default_threshold(space, data, options) -> float:
    """Half a rho cell would miss points on a cell edge: the larger of a cell and the default."""
    return max(space.default_threshold(data), rho_step(data, options.get("rho_resolution")))


def _finish(space, data, model, inliers, threshold, consensus):
    if space.refit(data[inliers]) is None:
        return 0.0, "the peak's inliers are degenerate (fewer than two distinct points)"
    return consensus.score, "ok"


register_strategy(Strategy(
    "hough", run_hough, uses_hypotheses=False, applies_to=("line",),
    finish=_finish, default_threshold=_default_threshold,
    summary="classical line Hough transform: every point votes on a (theta, rho) grid"))
