"""Hypothesis space of 2D lines: two points make a line."""

from __future__ import annotations

import numpy as np

from .._validation import Checked, check_choice, check_points, unwrap_checked
from ..geometry.line_transfer import LineTransfer
from ..geometry.lines import Line2D
from ..geometry.lines_nd import principal_axes
from .base import HypothesisSpace

__all__ = ["LineSpace"]


class LineSpace(HypothesisSpace):
    """Straight lines ``x cos(theta) + y sin(theta) = rho`` fitted to 2D points.

    Data are points of shape ``(N, 2)``; a model is ``(theta, rho)`` (see
    :class:`~clap_unified.geometry.Line2D`). Residuals are orthogonal
    point-to-line distances. The refit is weighted total least squares.

    Parameters
    ----------
    length_scale : float, optional
        Data units per radian in the line distance. ``None`` (default) takes
        the RMS radius of the data the first time :meth:`for_data` is called.
    origin : array_like of shape (2,), optional
        Offsets in the hypothesis distance are measured from here.
    manifold : Line2D, optional
        The distance between lines itself (e.g. a
        :class:`~clap_unified.geometry.line_transfer.LineTransfer`); then
        ``length_scale`` and ``origin`` are not used.

    Examples
    --------
    >>> space = LineSpace()
    >>> pts = np.array([[0.0, 1.0], [2.0, 1.0], [5.0, 1.0]])
    >>> models, owner = space.solve_minimal(pts, np.array([[0, 1], [1, 2], [0, 0]]))
    >>> models.round(6).tolist(), owner.tolist()
    ([[1.570796, 1.0], [1.570796, 1.0]], [0, 1])
    """

    min_samples = 2
    model_shape = (2,)
    name = "line"

    def __init__(self, length_scale: float = 1.0, origin=(0.0, 0.0), *,
                 manifold: Line2D | None = None):
        if manifold is not None and not isinstance(manifold, Line2D):
            raise ValueError(f"manifold: expected a Line2D, got {type(manifold).__name__}")
        self._manifold = (Line2D(length_scale=length_scale, origin=origin) if manifold is None
                          else manifold)

    @classmethod
    def for_data(cls, points, *, metric: str = "chart") -> LineSpace:
        """A space whose distance is scaled to ``points``.

        Parameters
        ----------
        points : array_like of shape (N, 2)
        metric : {"chart", "transfer"}
            ``"chart"`` (default): the :class:`~clap_unified.geometry.Line2D`
            distance with the origin at the centroid of ``points`` and
            ``length_scale`` their RMS radius. ``"transfer"``: lines compared
            by where they pass five anchors of the data region, in data units
            (:class:`~clap_unified.geometry.line_transfer.LineTransfer` with
            :func:`~clap_unified.geometry.homography_transfer.region_anchors`):
            a metric with an exact Euclidean embedding, so CLAP's neighbour
            queries need no ``H x H`` distance matrix.

        Examples
        --------
        >>> pts = np.c_[np.arange(10.0), np.arange(10.0) % 3]
        >>> LineSpace.for_data(pts, metric="transfer").manifold
        LineTransfer(anchors=5)
        """
        check_choice(metric, "metric", {"chart", "transfer"})
        pts = unwrap_checked(points, lambda p: check_points(p, "points", dim=2, min_count=2))
        if metric == "transfer":
            from ..geometry.homography_transfer import region_anchors

            anchors = region_anchors(Checked(pts))
            if len(np.unique(anchors, axis=0)) < 2:  # all points at one place: no region
                anchors = anchors[4] + np.array([[-1.0, 0], [1, 0], [0, -1], [0, 1], [0, 0]])
            return cls(manifold=LineTransfer(anchors))
        centre = pts.mean(axis=0)
        radius = float(np.sqrt(np.mean(np.sum((pts - centre) ** 2, axis=1))))
        return cls(length_scale=max(radius, 1e-12), origin=centre)

    def __repr__(self) -> str:
        m = self._manifold
        if isinstance(m, LineTransfer):
            return f"LineSpace({m!r})"
        return f"LineSpace(length_scale={m.length_scale:g}, origin={m.origin.tolist()})"

    @property
    def manifold(self) -> Line2D:
        return self._manifold

    def check_data(self, data) -> np.ndarray:
        return check_points(data, "points", dim=2, min_count=self.min_samples)

    def solve_minimal(self, data, samples):
        p = data[samples[:, 0]]
        q = data[samples[:, 1]]
        d = q - p
        length = np.hypot(d[:, 0], d[:, 1])  # no underflow of the squares at 1e-300
        # degenerate: the two points coincide to the precision of their own coordinates,
        # whatever the data's unit
        extent = np.maximum(np.abs(p).max(axis=1), np.abs(q).max(axis=1))
        ok = length > 1e-12 * extent
        normal = np.stack([-d[ok, 1], d[ok, 0]], axis=1) / length[ok, None]
        offset = np.sum(normal * p[ok], axis=1)
        return Line2D.from_normal_offset(normal, offset), np.flatnonzero(ok)

    def refit(self, data, weights=None, initial=None):
        axes = principal_axes(data, weights)
        if axes is None:
            return None
        centre, evals, evecs = axes
        if evals[1] <= 1e-24:
            return None
        normal = evecs[:, 0]
        return Line2D.from_normal_offset(normal, normal @ centre)

    def residuals(self, models, data) -> np.ndarray:
        models = np.asarray(models, dtype=float).reshape(-1, 2)
        normal, offset = Line2D.normal_offset(models)
        return np.abs(normal @ np.asarray(data, dtype=float).T - offset[:, None])

    def model_to_dict(self, model) -> dict:
        normal, offset = Line2D.normal_offset(model)
        return {"normal": [float(normal[0]), float(normal[1])], "offset": float(offset)}

    def default_threshold(self, data) -> float:
        # 2 % of the data's RMS radius: a scale-free default; pass a value for real units.
        centre = data.mean(axis=0)
        radius = float(np.sqrt(np.mean(np.sum((data - centre) ** 2, axis=1))))
        return 0.02 * max(radius, 1e-12)

    @staticmethod
    def predict_y(model, x) -> np.ndarray:
        """The ``y`` of the line ``model`` at ``x`` (scikit-image's ``predict_y``).

        A vertical line has no unique ``y``: ``ValueError``.

        Examples
        --------
        >>> line = Line2D.from_normal_offset([-1.0, 1.0], 1.0)   # -x + y = 1
        >>> LineSpace.predict_y(line, [0.0, 1.0]).round(12).tolist()
        [1.0, 2.0]
        """
        return _predict(model, x, along=0)

    @staticmethod
    def predict_x(model, y) -> np.ndarray:
        """The ``x`` of the line ``model`` at ``y`` (scikit-image's ``predict_x``).

        A horizontal line has no unique ``x``: ``ValueError``.

        Examples
        --------
        >>> line = Line2D.from_normal_offset([1.0, 0.0], 2.0)    # x = 2
        >>> LineSpace.predict_x(line, [0.0, 5.0]).tolist()
        [2.0, 2.0]
        """
        return _predict(model, y, along=1)


def _predict(model, value, along: int) -> np.ndarray:
    """The other coordinate of the points of a ``(theta, rho)`` line with coordinate
    ``along`` equal to ``value``."""
    (normal, offset) = Line2D.normal_offset(np.asarray(model, dtype=float).reshape(2))
    other = 1 - along
    if abs(normal[other]) <= 1e-15:
        names = "xy"
        raise ValueError(f"{names[along]}: the line is parallel to the {names[other]} axis: "
                         f"no unique {names[other]}")
    return (offset - normal[along] * np.asarray(value, dtype=float)) / normal[other]
