"""Density in hypothesis space: neighbour counts, bandwidths and peak seeds."""

from __future__ import annotations

import numpy as np

from ..geometry.base import PAIRWISE_BLOCK

__all__ = ["neighbour_counts", "knn_distance", "auto_bandwidth"]


def neighbour_counts(manifold, points, bandwidth: float) -> np.ndarray:
    """For each point, how many points (itself included) lie within ``bandwidth``.

    Computed in blocks so memory stays bounded for many thousands of hypotheses.
    """
    pts = np.asarray(points)
    n = len(pts)
    counts = np.empty(n, dtype=np.intp)
    rows = max(1, PAIRWISE_BLOCK // max(n, 1))
    for start in range(0, n, rows):
        d = manifold.pairwise_distance(pts[start:start + rows], pts)
        counts[start:start + rows] = np.count_nonzero(d <= bandwidth, axis=1)
    return counts


def knn_distance(manifold, points, k: int, *, distances=None) -> np.ndarray:
    """Distance from each point to its ``k``-th nearest other point.

    ``distances`` may hold the precomputed ``(N, N)`` pairwise matrix.
    """
    pts = np.asarray(points)
    n = len(pts)
    k = min(k, n - 1)
    if distances is not None:
        return np.partition(distances, k, axis=1)[:, k]
    out = np.empty(n)
    rows = max(1, PAIRWISE_BLOCK // max(n, 1))
    for start in range(0, n, rows):
        d = manifold.pairwise_distance(pts[start:start + rows], pts)
        out[start:start + rows] = np.partition(d, k, axis=1)[:, k]
    return out


def auto_bandwidth(manifold, points, *, k: int | None = None, quantile: float = 0.1,
                   distances=None) -> float:
    """A bandwidth from the data: a low quantile of the k-nearest-neighbour distances.

    Dense clusters (the correct hypotheses) have small k-NN distances and
    scattered outliers large ones; the 10 % quantile sits in the dense part as
    long as at least a few percent of the hypotheses are correct.
    ``k`` defaults to ``max(3, 1 % of the hypotheses)``.
    """
    pts = np.asarray(points)
    if len(pts) < 2:
        return np.inf
    if k is None:
        k = max(3, int(np.ceil(0.01 * len(pts))))
    d = knn_distance(manifold, pts, k, distances=distances)
    bw = float(np.quantile(d, quantile))
    return bw if bw > 0 else float(np.min(d[d > 0], initial=np.inf))
