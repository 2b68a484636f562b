"""The spaces hypotheses live in: manifolds and matrix Lie groups.

Every consensus strategy in this library needs only four things from the space
its hypotheses live in: a logarithm ``log(point, base_point)`` that maps a point
to a tangent vector at ``base_point``, the matching exponential, a distance,
and an average. :class:`Manifold` states that contract once; the concrete
spaces (2D lines, SE(2), SE(3), homographies) implement ``log`` and ``exp`` and
inherit the rest.

Conventions (geomstats style):

* points are batched over leading axes: an array of shape ``(..., *point_shape)``;
  tangent vectors have shape ``(..., dim)``;
* arguments are ordered ``log(point, base_point)``, ``exp(tangent, base_point)``;
* every iterative average has an iteration cap (``max_iter``) and a tolerance.
"""

from __future__ import annotations

from abc import ABC, abstractmethod

import numpy as np

from .._validation import check_array, check_int, check_positive

__all__ = ["Manifold", "MatrixLieGroup"]

#: Pairwise distances are computed in blocks of at most this many pairs.
PAIRWISE_BLOCK = 250_000


class Manifold(ABC):
    """A space of hypotheses with a chart at every point.

    Subclasses set :attr:`dim`, :attr:`point_shape` and implement :meth:`log`
    and :meth:`exp`. The distance is the weighted norm of the logarithm,
    ``d(a, b) = || w * log(b, a) ||`` with per-coordinate weights
    ``tangent_weights``; whether that is a true metric depends on the space
    and is stated in :attr:`is_metric`.
    """

    #: Intrinsic dimension: length of a tangent vector.
    dim: int
    #: Shape of one point, e.g. ``(3, 3)`` for SE(2) matrices.
    point_shape: tuple
    #: True when :meth:`distance` satisfies the triangle inequality.
    is_metric: bool = False
    #: True when ``d(a, b) = d(b, a)``; pairwise matrices then evaluate each pair once.
    is_symmetric: bool = True
    #: Up to this many points a symmetric pairwise matrix is one broadcast call
    #: (every pair twice, fewer Python-level calls); cheap distances raise it.
    small_pairwise: int = 64
    #: Declared abilities beyond the protocol: ``split_mean`` and
    #: ``chordal_embedding`` exist only where these are True.
    has_split_mean: bool = False
    has_chordal_embedding: bool = False
    #: The Euclidean distance of two points' ``chordal_embedding`` equals their distance.
    embedding_is_distance: bool = False
    #: It is at most their distance: a k-d tree on the embedding then finds a superset of
    #: every neighbourhood (:class:`~clap_unified.clap.density.EmbeddedNeighbours`).
    embedding_bounds_distance: bool = False
    #: Short name used in reprs and figures.
    name: str = "manifold"

    def __init__(self, tangent_weights=None):
        if tangent_weights is None:
            self.tangent_weights = np.ones(self.dim)
        else:
            w = check_array(tangent_weights, "tangent_weights", shape=(self.dim,))
            if np.any(w <= 0):
                raise ValueError("tangent_weights: every weight must be positive")
            self.tangent_weights = w

    def __repr__(self) -> str:
        return f"{type(self).__name__}()"

    # ---------------------------------------------------------------- charts
    @abstractmethod
    def log(self, point, base_point) -> np.ndarray:
        """Tangent vector at ``base_point`` pointing to ``point``; shape ``(..., dim)``."""

    @abstractmethod
    def exp(self, tangent, base_point) -> np.ndarray:
        """Point reached from ``base_point`` along ``tangent``."""

    @abstractmethod
    def reference_point(self) -> np.ndarray:
        """A fixed base point (the identity for a group) for log-Euclidean averages."""

    def validate(self, points, name: str = "points") -> np.ndarray:
        """Check that ``points`` is an array of shape ``(..., *point_shape)`` of finite values."""
        return check_array(points, name, shape=(Ellipsis, *self.point_shape))

    def projection(self, points) -> np.ndarray:
        """Map arrays near the manifold onto it (normalisation). Identity by default."""
        return np.asarray(points, dtype=float)

    # ------------------------------------------------------------- distances
    def norm(self, tangent) -> np.ndarray:
        """Weighted norm of tangent vectors, shape ``(...)``."""
        t = np.asarray(tangent) * self.tangent_weights
        if np.iscomplexobj(t):
            t = np.abs(t)
        return np.sqrt(np.einsum("...i,...i->...", t, t))

    def distance(self, point_a, point_b) -> np.ndarray:
        """Distance ``|| w * log(point_b, point_a) ||``, broadcast over leading axes."""
        return self.norm(self.log(point_b, point_a))

    def pairwise_distance(self, points_a, points_b=None) -> np.ndarray:
        """All distances between two sets of points.

        Parameters
        ----------
        points_a : ndarray of shape (N,) + point_shape
        points_b : ndarray of shape (M,) + point_shape, optional
            Defaults to ``points_a``.

        Returns
        -------
        ndarray of shape (N, M)
            ``out[i, j] = distance(points_a[i], points_b[j])``.
        """
        a = np.asarray(points_a, dtype=float)
        b = a if points_b is None else np.asarray(points_b, dtype=float)
        k = len(self.point_shape)
        if a.ndim != k + 1 or b.ndim != k + 1:
            raise ValueError(
                f"points: expected shape (N, {', '.join(map(str, self.point_shape))}), "
                f"got {a.shape} and {b.shape}"
            )
        n, m = a.shape[0], b.shape[0]
        if points_b is None and self.is_symmetric:
            return self._pairwise_symmetric(a)
        out = np.empty((n, m))
        rows = max(1, PAIRWISE_BLOCK // max(m, 1))
        for start in range(0, n, rows):
            stop = min(n, start + rows)
            base = a[start:stop, None]
            out[start:stop] = self.distance(base, b[None, :])
        return out

    def _pairwise_symmetric(self, a) -> np.ndarray:
        """All distances within one set, evaluating each unordered pair once."""
        n = a.shape[0]
        if n <= self.small_pairwise:
            # few points: one broadcast call beats gathering the upper triangle,
            # then symmetrise from the upper triangle so out[i, j] == out[j, i]
            out = self.distance(a[:, None], a[None, :])
            upper = np.triu(out, 1)
            return upper + upper.T
        out = np.zeros((n, n))
        i, j = np.triu_indices(n, 1)
        for start in range(0, len(i), PAIRWISE_BLOCK):
            sl = slice(start, start + PAIRWISE_BLOCK)
            d = self.distance(a[i[sl]], a[j[sl]])
            out[i[sl], j[sl]] = d
            out[j[sl], i[sl]] = d
        return out

    # -------------------------------------------------------------- averages
    def _check_weights(self, weights, n: int) -> np.ndarray:
        if weights is None:
            return np.full(n, 1.0 / n)
        w = check_array(weights, "weights", shape=(n,))
        if np.any(w < 0) or w.sum() <= 0:
            raise ValueError("weights: expected non-negative weights with a positive sum")
        return w / w.sum()

    def _check_sample(self, points) -> np.ndarray:
        pts = self.validate(points)
        if pts.ndim != len(self.point_shape) + 1 or pts.shape[0] == 0:
            raise ValueError(
                f"points: expected a non-empty stack of shape (N, "
                f"{', '.join(map(str, self.point_shape))}), got {pts.shape}"
            )
        return pts

    def mean(self, points, weights=None, *, initial=None, max_iter: int = 50,
             tol: float = 1e-12) -> np.ndarray:
        """Karcher (Frechet) mean by fixed-point iteration in the tangent space.

        ``base <- exp(sum_i w_i log(p_i, base), base)`` until the step norm is
        below ``tol`` or ``max_iter`` steps were taken.

        Parameters
        ----------
        points : ndarray of shape (N,) + point_shape
        weights : ndarray of shape (N,), optional
            Non-negative; normalised to sum to one.
        initial : ndarray of shape point_shape, optional
            Starting point; defaults to the first point.
        max_iter : int
            Iteration cap.
        tol : float
            Stop when the tangent step is shorter than this.
        """
        pts = self._check_sample(points)
        w = self._check_weights(weights, pts.shape[0])
        max_iter = check_int(max_iter, "max_iter", minimum=1)
        tol = check_positive(tol, "tol", allow_zero=True)
        base = pts[int(np.argmax(w))] if initial is None else self.validate(initial, "initial")
        for _ in range(max_iter):
            step = np.tensordot(w, self.log(pts, base), axes=1)
            base = self.exp(step, base)
            if np.linalg.norm(step) <= tol:
                break
        return base

    def log_euclidean_mean(self, points, weights=None) -> np.ndarray:
        """Average of the logarithms at :meth:`reference_point`, mapped back by ``exp``."""
        pts = self._check_sample(points)
        w = self._check_weights(weights, pts.shape[0])
        ref = self.reference_point()
        return self.exp(np.tensordot(w, self.log(pts, ref), axes=1), ref)

    def median(self, points, weights=None, *, initial=None, max_iter: int = 100,
               tol: float = 1e-10, eps: float = 1e-12) -> np.ndarray:
        """Geometric median in the tangent space (Weiszfeld iterations).

        Each step maps the points to the tangent space at the current estimate,
        takes one Weiszfeld step there (weights ``w_i / max(d_i, eps)`` with the
        weighted distances ``d_i``), and maps back.
        """
        pts = self._check_sample(points)
        w = self._check_weights(weights, pts.shape[0])
        max_iter = check_int(max_iter, "max_iter", minimum=1)
        if initial is None:
            base = self.mean(pts, w, max_iter=10)
        else:
            base = self.validate(initial, "initial")
        for _ in range(max_iter):
            logs = self.log(pts, base)
            d = np.maximum(self.norm(logs), eps)
            coef = w / d
            step = np.tensordot(coef / coef.sum(), logs, axes=1)
            base = self.exp(step, base)
            if np.linalg.norm(step) <= tol:
                break
        return base

    def medoid_index(self, points, weights=None) -> int:
        """Index of the point minimising the weighted sum of distances to all others."""
        pts = self._check_sample(points)
        w = self._check_weights(weights, pts.shape[0])
        return int(np.argmin(self.pairwise_distance(pts) @ w))


class MatrixLieGroup(Manifold):
    """A matrix Lie group with a left-invariant chart.

    Subclasses implement :meth:`expmap` and :meth:`logmap` at the identity (and
    :meth:`hat` / :meth:`vee`); then ``log(point, base) = logmap(base^-1 point)``
    and ``exp(v, base) = base expmap(v)``, so the distance is left-invariant:
    ``d(g a, g b) = d(a, b)``.
    """

    #: Size n of the n x n matrices.
    matrix_size: int

    @property
    def point_shape(self) -> tuple:  # type: ignore[override]
        return (self.matrix_size, self.matrix_size)

    def identity(self, shape: tuple = ()) -> np.ndarray:
        """Identity matrices of shape ``(*shape, n, n)``."""
        return np.broadcast_to(np.eye(self.matrix_size), (*shape, *self.point_shape)).copy()

    def reference_point(self) -> np.ndarray:
        return self.identity()

    def compose(self, a, b) -> np.ndarray:
        """Group product ``a b`` (batched matrix product)."""
        return np.matmul(a, b)

    def inverse(self, a) -> np.ndarray:
        """Group inverse (batched)."""
        return np.linalg.inv(a)

    @abstractmethod
    def expmap(self, tangent) -> np.ndarray:
        """Exponential at the identity: ``(..., dim) -> (..., n, n)``."""

    @abstractmethod
    def logmap(self, point) -> np.ndarray:
        """Logarithm at the identity: ``(..., n, n) -> (..., dim)``."""

    @abstractmethod
    def hat(self, tangent) -> np.ndarray:
        """Tangent coordinates to Lie algebra matrices."""

    @abstractmethod
    def vee(self, matrix) -> np.ndarray:
        """Lie algebra matrices to tangent coordinates."""

    def log(self, point, base_point) -> np.ndarray:
        return self.logmap(self.compose(self.inverse(base_point), point))

    def exp(self, tangent, base_point) -> np.ndarray:
        return self.compose(base_point, self.expmap(tangent))

    def random(self, n: int, *, rng=None, scale: float = 1.0) -> np.ndarray:
        """``n`` random elements ``expmap(scale * z)`` with standard normal ``z``."""
        from .._validation import as_generator

        g = as_generator(rng)
        return self.expmap(scale * g.standard_normal((n, self.dim)))
