"""Hypothesis space of lines in ``R^d``: two points make a line, in any dimension."""

from __future__ import annotations

import numpy as np

from .._validation import check_int, check_points, unwrap_checked
from ..geometry.lines_nd import (
    LineND,
    canonical_lines_nd,
    line_residuals,
    points_at,
    predict_coordinate,
    principal_axes,
)
from .base import HypothesisSpace

__all__ = ["LineNDSpace"]


class LineNDSpace(HypothesisSpace):
    """Lines ``(origin, direction)`` fitted to points ``(N, d)``, any ``d >= 2``.

    scikit-image's ``LineModelND`` as a hypothesis space: a model is a
    ``(2, d)`` array, a point of the line and a unit direction (see
    :class:`~clap_unified.geometry.lines_nd.LineND`); residuals are distances
    of the points to the line; the refit is the (weighted) total least-squares
    line: through the centroid, along the principal axis. The 2-D
    :class:`~clap_unified.spaces.LineSpace` (``(theta, rho)`` models) stays
    the plane's own space; this one is the same family in any dimension.

    Parameters
    ----------
    dim : int
        Dimension of the data points (at least 2).
    length_scale : float, optional
        Data units per unit of direction change in the hypothesis distance.
    origin : array_like of shape (dim,), optional
        Centre of the hypothesis distance (default the coordinate origin).
    manifold : LineND, optional
        The distance itself; then ``length_scale`` and ``origin`` are not used.

    Examples
    --------
    >>> from clap_unified import fit
    >>> rng = np.random.default_rng(0)
    >>> t = rng.uniform(-10, 10, 80)
    >>> pts = np.array([1.0, 2.0, 3.0]) + t[:, None] * np.array([2.0, 1.0, 2.0]) / 3
    >>> pts[:30] = rng.uniform(-10, 10, (30, 3))   # 30 outliers
    >>> space = LineNDSpace.for_data(pts)
    >>> res = fit(space, pts, "clap", threshold=0.01, rng=0)
    >>> res.n_inliers, res.model[1].round(6).tolist()
    (50, [0.666667, 0.333333, 0.666667])
    >>> float(space.residuals(res.model, np.array([[1.0, 2.0, 3.0]]))[0, 0]) < 1e-9
    True
    """

    min_samples = 2
    name = "line_nd"

    def __init__(self, dim: int = 3, length_scale: float = 1.0, origin=None, *,
                 manifold: LineND | None = None):
        if manifold is not None and not isinstance(manifold, LineND):
            raise ValueError(f"manifold: expected a LineND, got {type(manifold).__name__}")
        self._manifold = (LineND(dim, length_scale=length_scale, origin=origin)
                          if manifold is None else manifold)
        self.dim = self._manifold.space_dim
        self.model_shape = (2, self.dim)

    @classmethod
    def for_data(cls, points) -> LineNDSpace:
        """A space for ``points`` ``(N, d)``: centred on them, ``length_scale`` their RMS radius.

        Examples
        --------
        >>> LineNDSpace.for_data([[0.0, 0, 0], [2, 0, 0]])
        LineNDSpace(LineND(3, length_scale=1, origin=[1.0, 0.0, 0.0]))
        """
        pts = unwrap_checked(points, _check_nd_points)
        centre = pts.mean(axis=0)
        radius = float(np.sqrt(np.mean(np.sum((pts - centre) ** 2, axis=1))))
        return cls(pts.shape[1], length_scale=max(radius, np.finfo(float).tiny), origin=centre)

    def __repr__(self) -> str:
        return f"LineNDSpace({self._manifold!r})"

    @property
    def manifold(self) -> LineND:
        return self._manifold

    def check_data(self, data) -> np.ndarray:
        return check_points(data, "points", dim=self.dim, min_count=self.min_samples)

    def solve_minimal(self, data, samples):
        p = data[samples[:, 0]]
        q = data[samples[:, 1]]
        # degenerate: the two points coincide to the precision of their own coordinates
        extent = np.maximum(np.abs(p).max(axis=1), np.abs(q).max(axis=1))
        ok = np.abs(q - p).max(axis=1) > 1e-12 * extent
        lines = np.stack([p[ok], q[ok] - p[ok]], axis=1)
        return canonical_lines_nd(lines, self._manifold.origin), np.flatnonzero(ok)

    def residuals(self, models, data) -> np.ndarray:
        return line_residuals(np.asarray(models, dtype=float).reshape(-1, 2, self.dim), data)

    def refit(self, data, weights=None, initial=None):
        axes = principal_axes(data, weights)
        if axes is None:
            return None
        centre, evals, evecs = axes
        if evals[-1] <= 1e-24:
            return None
        line = np.stack([centre, evecs[:, -1]])
        return canonical_lines_nd(line, self._manifold.origin)

    def model_to_dict(self, model) -> dict:
        m = np.asarray(model, dtype=float).reshape(2, self.dim)
        return {"origin": m[0].tolist(), "direction": m[1].tolist()}

    def default_threshold(self, data) -> float:
        # 2 % of the data's RMS radius: a scale-free default; pass a value for real units.
        centre = data.mean(axis=0)
        radius = float(np.sqrt(np.mean(np.sum((data - centre) ** 2, axis=1))))
        return 0.02 * max(radius, 1e-12)

    @staticmethod
    def point_at(model, t) -> np.ndarray:
        """Points ``origin + t * direction`` of ``model``, shape ``t.shape + (d,)``.

        Examples
        --------
        >>> LineNDSpace.point_at([[0.0, 0, 1], [1.0, 0, 0]], [2.0]).tolist()
        [[2.0, 0.0, 1.0]]
        """
        return points_at(model, t)

    @staticmethod
    def predict(model, x, axis: int = 0) -> np.ndarray:
        """Points of ``model`` whose coordinate ``axis`` is ``x`` (scikit-image's ``predict``).

        ``predict(model, x, 0)[:, 1]`` is ``predict_y`` of a 2-D line,
        ``predict(model, y, 1)[:, 0]`` its ``predict_x``.

        Examples
        --------
        >>> LineNDSpace.predict([[0.0, 0.0], [0.6, 0.8]], [3.0], axis=0).round(12).tolist()
        [[3.0, 4.0]]
        """
        model = np.asarray(model, dtype=float)
        return predict_coordinate(model, x, check_int(axis, "axis", minimum=0))


def _check_nd_points(points) -> np.ndarray:
    """``points`` as an ``(N, d)`` array of finite points, ``d >= 2``, ``N >= 1``."""
    pts = np.asarray(points, dtype=float)
    if pts.ndim != 2 or pts.shape[1] < 2:
        raise ValueError(f"points: expected shape (N, d) with d >= 2, got {pts.shape}")
    return check_points(pts, "points", dim=pts.shape[1], min_count=1)
