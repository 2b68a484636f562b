"""Density in hypothesis space: neighbour counts, bandwidths and peak seeds."""

from __future__ import annotations

import numpy as np

from ..geometry.base import PAIRWISE_BLOCK

__all__ = ["EmbeddedNeighbours", "auto_bandwidth", "dense_candidates", "knn_distance",
           "neighbour_counts"]


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


def _low_quantile_of_knn(distances, k: int, quantile: float) -> float | None:
    """``np.quantile(knn, quantile)`` of the rows' k-th neighbour distances, cheaply.

    A low quantile depends only on the few smallest k-NN distances. Row ``i``
    has its k-th neighbour within ``r`` exactly when at least ``k + 1``
    entries of the row (itself included) are ``<= r``, so one counting pass at
    a trial radius finds every row that can matter; only those rows are
    partitioned. The trial radius comes from the exact k-NN distances of a
    few spread rows. Returns ``None`` when the trial radius catches too few
    rows (the caller then partitions every row); the value returned is
    otherwise exactly ``np.quantile`` of the full k-NN vector.
    """
    n = len(distances)
    pos = quantile * (n - 1)
    need = int(np.floor(pos)) + 2  # order statistics up to ceil(pos) (with a margin)
    if n < 64 or need > n // 4:
        return None
    probe = np.partition(distances[:: max(1, n // 32)], k, axis=1)[:, k]
    r = float(np.quantile(probe, min(1.0, 3.0 * need / n)))
    rows = np.flatnonzero(np.count_nonzero(distances <= r, axis=1) > k)
    if len(rows) < need:
        return None
    full = np.full(n, np.nextafter(r, np.inf) if np.isfinite(r) else np.inf)
    full[rows] = np.partition(distances[rows], k, axis=1)[:, k]
    return float(np.quantile(full, quantile))


def auto_bandwidth(manifold, points, *, k: int | None = None, quantile: float = 0.1,
                   distances=None) -> float:
    """A bandwidth from the data: a low quantile of the k-nearest-neighbour distances.

    Dense clusters (the correct hypotheses) have small k-NN distances and
    scattered outliers large ones; the 10 % quantile sits in the dense part as
    long as at least a few percent of the hypotheses are correct.
    ``k`` defaults to ``max(3, 1 % of the hypotheses)``. With ``distances``
    (the pairwise matrix) a low quantile is found without partitioning every
    row; the value is the same.

    Examples
    --------
    >>> from clap_unified.geometry import SE2
    >>> rng = np.random.default_rng(0)
    >>> pts = SE2().exp(rng.normal(0, 1, (200, 3)), np.eye(3))
    >>> D = SE2().pairwise_distance(pts)
    >>> bw = auto_bandwidth(SE2(), pts, quantile=0.05, distances=D)
    >>> bool(bw == np.quantile(np.partition(D, 3, axis=1)[:, 3], 0.05))
    True
    """
    pts = np.asarray(points)
    if len(pts) < 2:
        return np.inf
    if k is None:
        k = max(3, int(np.ceil(0.01 * len(pts))))
    k = min(k, len(pts) - 1)
    bw = None if distances is None else _low_quantile_of_knn(distances, k, quantile)
    d = None
    if bw is None:
        d = knn_distance(manifold, pts, k, distances=distances)
        bw = float(np.quantile(d, quantile))
    if bw > 0:
        return bw
    if d is None:
        d = knn_distance(manifold, pts, k, distances=distances)
    return float(np.min(d[d > 0], initial=np.inf))


def dense_candidates(manifold, models, radius: float, min_count: int) -> np.ndarray:
    """Indices of candidate poses with at least ``min_count`` candidates within ``radius``.

    Counted with a k-d tree on :meth:`~clap_unified.geometry.SE3.chordal_embedding`
    (``O(H log H)``). For the ``relative`` metric nothing CLAP could use is
    lost with ``radius = 2 * bandwidth``: a member of a cluster lies within
    the bandwidth of a seed that has ``min_support`` candidates within the
    bandwidth, hence (triangle inequality) within twice the bandwidth of the
    member, and chordal distances never exceed ``relative`` ones. For the
    other metrics it is a close approximation.

    Examples
    --------
    >>> from clap_unified.geometry import SE3
    >>> g = SE3(2.0, metric="relative")
    >>> T = g.expmap(np.r_[np.zeros((5, 6)), 10 * np.eye(6)[:2]])
    >>> dense_candidates(g, T, 0.1, 3).tolist()
    [0, 1, 2, 3, 4]
    """
    from scipy.spatial import cKDTree

    emb = manifold.chordal_embedding(models)
    counts = cKDTree(emb).query_ball_point(emb, radius, return_length=True)
    return np.flatnonzero(counts >= min_count)


class EmbeddedNeighbours:
    """Neighbour queries on a k-d tree, for manifolds whose embedding distance is the distance.

    A manifold that declares ``embedding_is_distance`` (e.g.
    :class:`~clap_unified.geometry.homography_transfer.HomographyTransfer`)
    gives every point a vector whose Euclidean distance is the manifold's
    distance, so counts, k-th neighbour distances and balls come from
    :class:`scipy.spatial.cKDTree` in ``O(H log H)`` time and ``O(H)``
    memory: no ``H x H`` matrix at any size. Points without an embedding
    (NaN rows) have no neighbours and are no one's neighbour.

    Parameters
    ----------
    manifold : Manifold
        With ``embedding_is_distance = True``.
    points : ndarray
        Points of the manifold, shape ``(H, *point_shape)``.

    Examples
    --------
    >>> from clap_unified.geometry.homography_transfer import HomographyTransfer
    >>> g = HomographyTransfer(np.zeros((1, 2)))
    >>> H = np.repeat(np.eye(3)[None], 4, axis=0)
    >>> H[:, 0, 2] = [0.0, 1.0, 2.0, 10.0]              # shifts of 0, 1, 2 and 10 px
    >>> nb = EmbeddedNeighbours(g, H)
    >>> nb.counts(1.5).tolist(), nb.knn(1).tolist()
    ([2, 3, 2, 1], [1.0, 1.0, 1.0, 8.0])
    """

    def __init__(self, manifold, points):
        from scipy.spatial import cKDTree

        emb = np.asarray(manifold.chordal_embedding(points), dtype=float)
        self.manifold = manifold
        self.embedding = emb
        self.valid = np.all(np.isfinite(emb), axis=1)
        self.index = np.flatnonzero(self.valid)
        self.tree = cKDTree(emb[self.valid]) if len(self.index) else None

    def __len__(self) -> int:
        return len(self.embedding)

    def knn(self, k: int) -> np.ndarray:
        """Distance of each point to its ``k``-th nearest other point (``inf``: none)."""
        out = np.full(len(self), np.inf)
        if self.tree is None or len(self.index) < 2:
            return out
        k = min(k, len(self.index) - 1)
        d = self.tree.query(self.embedding[self.index], k + 1)[0]
        out[self.index] = d[:, k]
        return out

    def counts(self, radius: float) -> np.ndarray:
        """Points within ``radius`` of each point, itself included (0 without an embedding)."""
        out = np.zeros(len(self), dtype=np.intp)
        if self.tree is not None:
            out[self.index] = self.tree.query_ball_point(self.embedding[self.index], radius,
                                                         return_length=True)
        return out

    def ball(self, i: int, radius: float) -> np.ndarray:
        """Indices of the points within ``radius`` of point ``i``, sorted."""
        return self.ball_of(self.embedding[i], radius)

    def ball_of(self, vector, radius: float) -> np.ndarray:
        """Indices of the points within ``radius`` of an embedded ``vector``, sorted."""
        if self.tree is None or not np.all(np.isfinite(vector)):
            return np.zeros(0, dtype=np.intp)
        return np.sort(self.index[self.tree.query_ball_point(vector, radius)])

    def pairwise(self, idx) -> np.ndarray:
        """The distance matrix among ``points[idx]`` (points that have an embedding)."""
        from scipy.spatial.distance import cdist

        e = self.embedding[idx]
        return cdist(e, e)

    def auto_bandwidth(self, *, k: int | None = None, quantile: float = 0.1) -> float:
        """:func:`auto_bandwidth` from the tree (the same rule, no matrix)."""
        n = len(self.index)
        if n < 2:
            return np.inf
        k = max(3, int(np.ceil(0.01 * len(self)))) if k is None else k
        d = self.knn(min(k, n - 1))[self.index]
        bw = float(np.quantile(d, quantile))
        return bw if bw > 0 else float(np.min(d[d > 0], initial=np.inf))
