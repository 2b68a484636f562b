"""The space of straight lines in ``R^d``, any ``d >= 2``.

A line is stored as a ``(2, d)`` array: row 0 a point of the line (its
*origin*), row 1 a unit *direction*, as scikit-image's ``LineModelND``
(``origin``, ``direction``). The same line has many such arrays (any point on
it, either sign of the direction); the canonical one has the foot of the
perpendicular from a fixed centre ``c`` as its origin and a direction whose
largest component (the first of equal ones) is positive.

:class:`LineND` compares lines by their canonical origins and their
directions up to sign::

    d(L1, L2) = sqrt(|o1 - o2|^2 + length_scale^2 * min(|u1 - u2|, |u1 + u2|)^2)

(data units; ``length_scale`` data units per unit of direction change, the
radius of the data is a good value, and ``c`` is best put at the centre of the
data). It is a metric: the Euclidean distance of ``R^(2d)`` taken modulo the
direction's sign. Its chart at a line aligns the other line's direction with
the base's, then subtracts; ``exp`` adds and maps back to canonical form (a
chart in ``2d`` coordinates, of which ``2d - 2`` are intrinsic).

The module also holds the lines' arithmetic the spaces and users share:
:func:`canonical_lines_nd`, :func:`line_residuals`, :func:`points_at` (the point
at a parameter along the line) and :func:`predict_coordinate` (the point of the
line with a given coordinate, scikit-image's ``predict``).

Examples
--------
>>> g = LineND(3, length_scale=2.0)
>>> z_axis = np.array([[0.0, 0, 5], [0, 0, 1]])
>>> shifted = np.array([[1.0, 0, 0], [0, 0, -1]])   # parallel, one unit away
>>> float(g.distance(z_axis, shifted))
1.0
"""

from __future__ import annotations

import numpy as np

from .._validation import check_array, check_int, check_positive
from .base import Manifold

__all__ = ["LineND", "canonical_lines_nd", "line_residuals", "points_at", "principal_axes",
           "predict_coordinate"]


def _unit(vectors):
    """Unit vectors along ``vectors`` (..., d), scaled first so that no square underflows."""
    v = np.asarray(vectors, dtype=float)
    big = np.max(np.abs(v), axis=-1, keepdims=True)
    v = v / np.where(big > 0, big, 1.0)
    length = np.linalg.norm(v, axis=-1, keepdims=True)
    return v / np.where(length > 0, length, 1.0)


def canonical_lines_nd(lines, centre=None) -> np.ndarray:
    """Canonical ``(origin, direction)`` arrays ``(..., 2, d)`` of ``lines``.

    The direction is made unit with its largest component (the first of equal
    ones) positive; the origin is the foot of the perpendicular from
    ``centre`` (default the coordinate origin).

    Examples
    --------
    >>> canonical_lines_nd([[[3.0, 1.0], [-2.0, 0.0]]]).tolist()
    [[[0.0, 1.0], [1.0, 0.0]]]
    """
    lines = np.asarray(lines, dtype=float)
    d = lines.shape[-1]
    c = np.zeros(d) if centre is None else np.asarray(centre, dtype=float)
    u = _unit(lines[..., 1, :])
    big = np.take_along_axis(u, np.argmax(np.abs(u), axis=-1)[..., None], axis=-1)
    u = np.where(big < 0, -u, u)
    o = lines[..., 0, :]
    o = o + np.sum((c - o) * u, axis=-1, keepdims=True) * u
    return np.stack([o, u], axis=-2)


def principal_axes(points, weights=None):
    """Weighted centroid of ``points`` and the eigen-decomposition of their scatter.

    The scatter is taken in the points' own unit (deviations divided by their largest
    magnitude), so data at 1e-300 do not underflow. ``None`` when fewer than two points
    have positive weight or they all coincide (to their precision).

    Returns
    -------
    centre : ndarray of shape (d,)
    evals, evecs : ndarray
        ``numpy.linalg.eigh`` of the scaled scatter: ascending eigenvalues, unit
        eigenvectors in columns (the last column is the direction of largest spread).

    Examples
    --------
    >>> centre, evals, evecs = principal_axes([[0.0, 0.0], [2.0, 0.0], [4.0, 0.0]])
    >>> centre.tolist(), np.abs(evecs[:, -1]).tolist()
    ([2.0, 0.0], [1.0, 0.0])
    >>> principal_axes([[1.0, 1.0], [1.0, 1.0]]) is None
    True
    """
    data = np.asarray(points, dtype=float)
    w = np.ones(len(data)) if weights is None else np.asarray(weights, dtype=float)
    keep = w > 0
    if np.count_nonzero(keep) < 2:
        return None
    x, w = data[keep], w[keep]
    centre = (w[:, None] * x).sum(axis=0) / w.sum()
    dev = x - centre
    spread = float(np.max(np.abs(dev)))
    if not spread > 1e-12 * float(np.max(np.abs(x))):
        return None  # all points coincide (to their precision): no direction
    dev /= spread  # in the points' own unit: no underflow at 1e-300
    cov = (dev.T * w) @ dev / w.sum()
    evals, evecs = np.linalg.eigh(cov)
    return centre, evals, evecs


def line_residuals(lines, points) -> np.ndarray:
    """Distances of ``points`` (N, d) to ``lines`` (H, 2, d), shape ``(H, N)``.

    The direction need not be unit (as scikit-image, which normalises it).

    Examples
    --------
    >>> line_residuals([[[0.0, 0, 0], [0, 0, 2]]], [[10.0, 0, 0], [0, 0, 3]]).tolist()
    [[10.0, 0.0]]
    """
    lines = np.asarray(lines, dtype=float).reshape(-1, 2, np.shape(lines)[-1])
    x = np.asarray(points, dtype=float)
    o, u = lines[:, None, 0], _unit(lines[:, 1])[:, None]
    v = x[None] - o  # (H, N, d)
    perp = v - np.sum(v * u, axis=-1, keepdims=True) * u
    return np.linalg.norm(perp, axis=-1)


def points_at(line, t) -> np.ndarray:
    """Points ``origin + t * direction`` of one line ``(2, d)``, shape ``t.shape + (d,)``.

    Examples
    --------
    >>> points_at([[1.0, 2.0], [0.0, 1.0]], [0.0, 3.0]).tolist()
    [[1.0, 2.0], [1.0, 5.0]]
    """
    line = np.asarray(line, dtype=float)
    t = np.asarray(t, dtype=float)
    return line[0] + t[..., None] * line[1]


def predict_coordinate(line, x, axis: int = 0) -> np.ndarray:
    """The points of one line ``(2, d)`` whose coordinate ``axis`` is ``x``, ``x.shape + (d,)``.

    scikit-image's ``LineModelND.predict(x, axis)``. A line perpendicular to
    that axis has no such point (or all of them): ``ValueError``.

    Examples
    --------
    >>> predict_coordinate([[0.0, 0.0], [0.2, 0.8]], [1.0, 2.0], axis=0).round(12).tolist()
    [[1.0, 4.0], [2.0, 8.0]]
    """
    line = np.asarray(line, dtype=float)
    axis = check_int(axis, "axis", minimum=0)
    if axis >= line.shape[-1]:
        raise ValueError(f"axis: the line is in {line.shape[-1]} dimensions, got axis {axis}")
    o, u = line[0], line[1]
    if u[axis] == 0:
        raise ValueError(f"axis: the line is perpendicular to axis {axis}: no unique point")
    return points_at(line, (np.asarray(x, dtype=float) - o[axis]) / u[axis])


class LineND(Manifold):
    """Lines in ``R^d`` as ``(origin, direction)`` arrays ``(2, d)``.

    Parameters
    ----------
    dim : int
        Dimension ``d`` of the space the lines live in (at least 2).
    length_scale : float
        Data units per unit of direction change; the radius of the data.
    origin : array_like of shape (d,), optional
        The centre ``c``: canonical origins are the feet of the perpendiculars
        from it (default the coordinate origin; put it at the data's centre).

    Examples
    --------
    >>> g = LineND(2)
    >>> a = np.array([[0.0, 0.0], [1.0, 0.0]])
    >>> b = np.array([[0.0, 0.0], [-1.0, 1e-9]])   # almost the same line, other sign
    >>> float(g.distance(a, b)) < 1e-8
    True
    >>> g.mean(np.stack([a, b])).round(6).tolist()
    [[0.0, 0.0], [1.0, -0.0]]
    """

    is_metric = True
    has_chordal_embedding = True
    #: ``|embedding(a) - embedding(b)| <= d(a, b)``: ``(1 - c^2) <= 2 (1 - |c|)``.
    embedding_bounds_distance = True
    small_pairwise = 256
    name = "lines in R^d"

    def __init__(self, dim: int, length_scale: float = 1.0, origin=None):
        self.space_dim = check_int(dim, "dim", minimum=2)
        self.length_scale = check_positive(length_scale, "length_scale")
        self.origin = (np.zeros(self.space_dim) if origin is None
                       else check_array(origin, "origin", shape=(self.space_dim,)))
        self.point_shape = (2, self.space_dim)
        self.dim = 2 * self.space_dim
        super().__init__(tangent_weights=np.r_[np.ones(self.space_dim),
                                               np.full(self.space_dim, self.length_scale)])

    def __repr__(self) -> str:
        return (f"LineND({self.space_dim}, length_scale={self.length_scale:g}, "
                f"origin={self.origin.tolist()})")

    def projection(self, points) -> np.ndarray:
        return canonical_lines_nd(points, self.origin)

    def log(self, point, base_point) -> np.ndarray:
        p = canonical_lines_nd(point, self.origin)
        b = canonical_lines_nd(base_point, self.origin)
        p, b = np.broadcast_arrays(p, b)
        sign = np.where(np.sum(p[..., 1, :] * b[..., 1, :], axis=-1) < 0, -1.0, 1.0)
        du = sign[..., None] * p[..., 1, :] - b[..., 1, :]
        return np.concatenate([p[..., 0, :] - b[..., 0, :], du], axis=-1)

    def exp(self, tangent, base_point) -> np.ndarray:
        v = np.asarray(tangent, dtype=float)
        b = canonical_lines_nd(base_point, self.origin)
        d = self.space_dim
        o = b[..., 0, :] + v[..., :d]
        u = b[..., 1, :] + v[..., d:]
        # a step that cancels the direction keeps the base's (no line has none)
        u = np.where(np.max(np.abs(u), axis=-1, keepdims=True) > 0, u, b[..., 1, :])
        return canonical_lines_nd(np.stack(np.broadcast_arrays(o, u), axis=-2), self.origin)

    def reference_point(self) -> np.ndarray:
        return np.stack([self.origin, np.eye(self.space_dim)[0]])

    def chordal_embedding(self, points) -> np.ndarray:
        """``(o, length_scale * vec(u u^T) / sqrt(2))`` per line, shape ``(..., d + d^2)``.

        Sign-free; its Euclidean distance is at most :meth:`distance`.
        """
        p = canonical_lines_nd(points, self.origin)
        u = p[..., 1, :]
        outer = u[..., :, None] * u[..., None, :]
        flat = outer.reshape(*outer.shape[:-2], self.space_dim ** 2)
        return np.concatenate([p[..., 0, :], self.length_scale * flat / np.sqrt(2.0)], axis=-1)
