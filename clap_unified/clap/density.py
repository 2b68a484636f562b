"""Density in hypothesis space: neighbour counts, bandwidths and peak seeds."""

from __future__ import annotations

import numpy as np

from ..geometry.base import PAIRWISE_BLOCK

__all__ = ["KNN_BUDGET", "EmbeddedNeighbours", "auto_bandwidth", "dense_candidates",
           "even_subset", "knn_distance", "neighbour_counts"]


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


def even_subset(indices, m: int) -> np.ndarray:
    """At most ``m`` of ``indices``, evenly spread over them (all of them when they are few).

    Examples
    --------
    >>> even_subset(np.arange(10, 20), 4).tolist()
    [10, 13, 16, 19]
    """
    n = len(indices)
    return indices[np.unique(np.linspace(0, n - 1, min(n, m)).astype(np.intp))]


#: Neighbour queries over more rows than this estimate the bandwidth's quantile from an
#: evenly spread subset of the rows (each against every point), so that finding the
#: bandwidth costs at most about this many neighbour results.
KNN_BUDGET = 4_000_000


class EmbeddedNeighbours:
    """Neighbour queries on a k-d tree over a Euclidean embedding of the manifold.

    Two kinds of embedding serve. When the manifold declares
    ``embedding_is_distance`` (e.g.
    :class:`~clap_unified.geometry.homography_transfer.HomographyTransfer`) the
    Euclidean distance of two embedded points *is* their distance, and the
    tree answers alone. When it declares ``embedding_bounds_distance``
    (:class:`~clap_unified.geometry.SE2`, :class:`~clap_unified.geometry.SE3`
    with the ``lie`` or ``relative`` metric: the chordal embedding never
    exceeds the distance) the tree proposes candidates, a superset of the
    answer, and the manifold's own distance decides; the answers are exact
    either way. Counts, k-th neighbour distances and balls then cost time in
    proportion to the neighbours found, ``O(H log H)`` for scattered
    hypotheses, and ``O(H)`` memory: no ``H x H`` matrix at any size. Points
    without an embedding (NaN rows) have no neighbours and are no one's
    neighbour.

    Parameters
    ----------
    manifold : Manifold
        With ``embedding_is_distance`` or ``embedding_bounds_distance``.
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

    With a bounding embedding the answers are those of the distance itself:

    >>> from clap_unified.geometry import SE2
    >>> T = SE2().from_xytheta(np.array([0.0, 0.1, 0.0]), 0.0, np.array([0.0, 0.0, 3.0]))
    >>> nb = EmbeddedNeighbours(SE2(), T)
    >>> nb.counts(0.2).tolist(), bool(nb.knn(1)[2] == SE2().distance(T[0], T[2]))
    ([2, 2, 1], True)
    """

    def __init__(self, manifold, points):
        from scipy.spatial import cKDTree

        self.exact = bool(manifold.embedding_is_distance)
        if not (self.exact or manifold.embedding_bounds_distance):
            raise ValueError(f"manifold: {manifold!r} has no embedding that gives or bounds "
                             "its distance")
        self.points = np.asarray(points, dtype=float)
        emb = np.asarray(manifold.chordal_embedding(self.points), dtype=float)
        self.manifold = manifold
        self.embedding = emb
        self.valid = np.all(np.isfinite(emb), axis=1)
        self.index = np.flatnonzero(self.valid)
        self.tree = cKDTree(emb[self.valid]) if len(self.index) else None

    def __len__(self) -> int:
        return len(self.embedding)

    def _distance(self, rows, cols) -> np.ndarray:
        """The manifold's distances ``d(points[rows], points[cols])``, pair by pair."""
        out = np.empty(len(rows))
        for s in range(0, len(rows), PAIRWISE_BLOCK):
            sl = slice(s, s + PAIRWISE_BLOCK)
            out[sl] = self.manifold.distance(self.points[rows[sl]], self.points[cols[sl]])
        return out

    def _balls(self, rows, radius):
        """Pairs ``(row, j)`` with ``j`` in the embedded ball of each row, and the distances.

        ``radius`` is one radius or one per row; the distances are the
        manifold's (the embedding's when it is the distance).
        """
        # a bound met with equality may round either way: widen the query a little
        query = radius if self.exact else np.asarray(radius) * (1 + 1e-9)
        lists = self.tree.query_ball_point(self.embedding[rows], query)
        sizes = np.fromiter((len(x) for x in lists), np.intp, len(lists))
        i = np.repeat(rows, sizes)
        j = (self.index[np.concatenate(lists).astype(np.intp)] if sizes.sum()
             else np.zeros(0, np.intp))
        if self.exact:
            d = np.linalg.norm(self.embedding[i] - self.embedding[j], axis=1)
        else:
            d = self._distance(i, j)
        return i, j, d

    def _row_blocks(self, rows, per_row: float):
        """``rows`` in blocks of about :data:`PAIRWISE_BLOCK` expected pairs."""
        step = max(1, int(PAIRWISE_BLOCK // max(per_row, 1.0)))
        for s in range(0, len(rows), step):
            yield rows[s:s + step]

    def knn(self, k: int, rows=None) -> np.ndarray:
        """Distance of each point (or of ``points[rows]``) to its ``k``-th nearest other point.

        ``inf`` for points without an embedding or without ``k`` others.
        """
        every = rows is None
        rows = self.index if every else np.asarray(rows, dtype=np.intp)
        out = np.full(len(self), np.inf)
        if self.tree is not None and len(self.index) >= 2:
            k = min(k, len(self.index) - 1)
            for block in self._row_blocks(rows[self.valid[rows]], k + 1):
                out[block] = self._knn_block(block, k)
        return out if every else out[rows]

    def _knn_block(self, block, k: int) -> np.ndarray:
        d, j = self.tree.query(self.embedding[block], k + 1)
        if self.exact:
            return d[:, k]
        # k + 1 points (the row itself among them) lie within the largest of their
        # distances, so the ball of that radius holds the k-th neighbour
        upper = self._distance(np.repeat(block, k + 1), self.index[j].ravel())
        i, _, dist = self._balls(block, upper.reshape(len(block), k + 1).max(axis=1))
        order = np.lexsort((dist, i))  # by row, then by distance
        return dist[order][np.searchsorted(i[order], block) + k]

    def counts(self, radius: float, rows=None) -> np.ndarray:
        """Points within ``radius`` of each point (or of ``points[rows]``), itself included.

        0 for points without an embedding. With an embedding that bounds the
        distance, the counts are exact while the embedded balls hold at most
        :data:`KNN_BUDGET` pairs; beyond (hypotheses piled in a few very dense
        clusters), they are the embedded counts, at least the exact ones and
        within a fraction of a percent of them at a CLAP bandwidth.
        """
        every = rows is None
        rows = self.index if every else np.asarray(rows, dtype=np.intp)
        out = np.zeros(len(self), dtype=np.intp)
        rows = rows[self.valid[rows]]
        if self.tree is not None and len(rows):
            found = self.tree.query_ball_point(self.embedding[rows], radius, return_length=True)
            if self.exact or found.sum() > KNN_BUDGET:
                # more pairs than the budget (hypotheses piled in a few dense clusters):
                # the embedded counts, an upper bound within a fraction of a percent
                out[rows] = found
            else:
                for block in self._row_blocks(rows, float(np.mean(found))):
                    i, _, d = self._balls(block, radius)
                    out += np.bincount(i[d <= radius], minlength=len(self))
        return out if every else out[rows]

    def budget_rows(self, k: int) -> np.ndarray:
        """The rows whose neighbourhoods of about ``k`` points fit :data:`KNN_BUDGET`.

        Every point with an embedding while ``H (k + 1)`` fits, else an evenly
        spread subset of at least 1024 of them: density is then estimated at
        those rows only (each against every point), so that it costs
        ``O(H log H)`` however large ``H`` and its clusters grow.
        """
        n = len(self.index)
        if n * (k + 1) <= KNN_BUDGET:
            return self.index
        return even_subset(self.index, max(1024, KNN_BUDGET // (k + 1)))

    def ball(self, i: int, radius: float) -> np.ndarray:
        """Indices of the points within ``radius`` of point ``i``, sorted."""
        if self.tree is None or not self.valid[i]:
            return np.zeros(0, dtype=np.intp)
        if self.exact:  # the tree's answer is the answer
            return np.sort(self.index[self.tree.query_ball_point(self.embedding[i], radius)])
        _, j, d = self._balls(np.array([i]), radius)
        return np.sort(j[d <= radius])

    def ball_of(self, point, radius: float) -> np.ndarray:
        """Indices of the points within ``radius`` of a ``point`` of the manifold, sorted."""
        vector = self.manifold.chordal_embedding(np.asarray(point, dtype=float))
        if self.tree is None or not np.all(np.isfinite(vector)):
            return np.zeros(0, dtype=np.intp)
        j = np.sort(self.index[self.tree.query_ball_point(
            vector, radius if self.exact else radius * (1 + 1e-9))])
        if self.exact or not len(j):
            return j
        return j[self.manifold.distance(point, self.points[j]) <= radius]

    def pairwise(self, idx) -> np.ndarray:
        """The distance matrix among ``points[idx]`` (points that have an embedding)."""
        from scipy.spatial.distance import cdist

        if not self.exact:
            return self.manifold.pairwise_distance(self.points[idx])
        e = self.embedding[idx]
        return cdist(e, e)

    def auto_bandwidth(self, *, k: int | None = None, quantile: float = 0.1) -> float:
        """:func:`auto_bandwidth` from the tree (the same rule, no matrix).

        Beyond :data:`KNN_BUDGET` neighbour results the quantile is taken over
        the rows of :meth:`budget_rows` (each row's k-th neighbour is still
        sought among all points), so the cost stays bounded as ``k`` grows with
        the number of hypotheses.
        """
        n = len(self.index)
        if n < 2:
            return np.inf
        k = min(max(3, int(np.ceil(0.01 * len(self)))) if k is None else k, n - 1)
        d = self.knn(k, self.budget_rows(k))
        bw = float(np.quantile(d, quantile))
        return bw if bw > 0 else float(np.min(d[d > 0], initial=np.inf))
