"""Classical line Hough transform: data vote on a grid, peaks are the lines."""

from __future__ import annotations

import time

import numpy as np

from .._validation import check_positive
from ..refine import inliers_of, refit_on_inliers
from ..result import Cluster, ConsensusResult, runner_up_ratio
from ..spaces.lines import LineSpace
from .accumulator import line_accumulator
from .peaks import accumulator_peaks

__all__ = ["hough_lines"]


def hough_lines(points, *, theta_resolution: float = np.pi / 180,
                rho_resolution: float | None = None, num_peaks: int = 5,
                min_distance: int = 5, residual_threshold: float | None = None,
                refit: bool = True, space: LineSpace | None = None) -> ConsensusResult:
    """Fit lines by voting in ``(theta, rho)``.

    Every point votes for each angle; local maxima of the accumulator
    (non-maximum suppression) are the lines, strongest first. The best peak is
    the estimate, optionally refitted on its data inliers.

    Parameters
    ----------
    points : ndarray of shape (N, 2)
    theta_resolution, rho_resolution : float
        Grid steps (radians; data units, default 1/200 of the extent).
    num_peaks : int
        Peaks reported in ``clusters``.
    min_distance : int
        Minimum separation of peaks, in cells.
    residual_threshold : float, optional
        Data inlier threshold; default half a rho cell plus the space's default.
    refit : bool
    space : LineSpace, optional
        Only used to describe the model; default ``LineSpace.for_data(points)``.

    Returns
    -------
    ConsensusResult
        ``clusters`` holds each peak with its votes as support and the cell
        size as spread.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> x = rng.uniform(-5, 5, 50)
    >>> pts = np.r_[np.c_[x, 2 * x - 1], rng.uniform(-5, 5, (25, 2))]
    >>> res = hough_lines(pts, residual_threshold=0.05)
    >>> res.success, res.n_inliers >= 50
    (True, True)
    """
    t0 = time.perf_counter()
    space = LineSpace.for_data(points) if space is None else space
    data = space.check_data(points)
    acc = line_accumulator(data, theta_resolution=theta_resolution, rho_resolution=rho_resolution)
    dr = float(acc.rhos[1] - acc.rhos[0]) if len(acc.rhos) > 1 else 1.0
    t = (max(space.default_residual_threshold(data), dr) if residual_threshold is None
         else check_positive(residual_threshold, "residual_threshold"))
    peaks = accumulator_peaks(acc.votes, min_distance=min_distance, num_peaks=num_peaks,
                              threshold=2)
    diag = {"accumulator_shape": acc.votes.shape, "rho_resolution": dr,
            "theta_resolution": theta_resolution, "residual_threshold": t}
    if len(peaks) == 0:
        diag["seconds"] = time.perf_counter() - t0
        return ConsensusResult.failure("hough", "no accumulator cell has 2 or more votes",
                                       len(data), 0, space, **diag)
    clusters = [Cluster(acc.line(i, j), int(acc.votes[i, j]), dr / 2) for i, j in peaks]
    model = clusters[0].model
    inliers = inliers_of(space, model, data, t)
    if refit:
        model, inliers = refit_on_inliers(space, model, data, t)
    if space.refit(data[inliers]) is None:
        diag["seconds"] = time.perf_counter() - t0
        return ConsensusResult.failure("hough", "the peak's inliers are degenerate (fewer than "
                                       "two distinct points)", len(data), 0, space, **diag)
    diag["runner_up_ratio"] = runner_up_ratio(clusters)
    diag["seconds"] = time.perf_counter() - t0
    diag["accumulator"] = acc
    return ConsensusResult("hough", True, "ok", model, inliers, np.zeros(0, bool),
                           float(clusters[0].support), clusters, diag, space)
