"""The space of straight lines in the plane.

A line is stored as ``(theta, rho)``: the set of points ``(x, y)`` with
``x cos(theta) + y sin(theta) = rho``. The pairs ``(theta, rho)`` and
``(theta + pi, -rho)`` are the same line, so the space is a Moebius band; the
canonical representative has ``theta`` in ``[0, pi)``.
"""

from __future__ import annotations

import numpy as np

from .._validation import check_array, check_positive
from .base import Manifold

__all__ = ["Line2D", "canonical_lines", "wrap_angle"]


def wrap_angle(angle):
    """Wrap angles to ``[-pi, pi)``.

    Examples
    --------
    >>> float(wrap_angle(3 * np.pi / 2)) == -np.pi / 2
    True
    """
    return (np.asarray(angle) + np.pi) % (2 * np.pi) - np.pi


def canonical_lines(lines) -> np.ndarray:
    """Canonical ``(theta, rho)`` with ``theta`` in ``[0, pi)``.

    Examples
    --------
    >>> canonical_lines([[-np.pi / 2, 2.0]]).round(6).tolist()
    [[1.570796, -2.0]]
    """
    lines = np.array(lines, dtype=float)
    theta = np.mod(lines[..., 0], 2 * np.pi)
    flip = theta >= np.pi
    lines[..., 0] = np.where(flip, theta - np.pi, theta)
    lines[..., 1] = np.where(flip, -lines[..., 1], lines[..., 1])
    # theta exactly pi after rounding
    at_pi = lines[..., 0] >= np.pi
    lines[..., 0] = np.where(at_pi, 0.0, lines[..., 0])
    lines[..., 1] = np.where(at_pi, -lines[..., 1], lines[..., 1])
    return lines


class Line2D(Manifold):
    """Lines in the plane, ``(theta, rho)``, with a chart at every line.

    The logarithm at a base line is ``(dtheta, drho)``: the angle from the
    base normal to the nearer of the two normals of the other line (so
    ``|dtheta| <= pi/2``), and the difference of offsets measured from
    ``origin`` once the normals agree. The distance weighs the angle by
    ``length_scale`` (data units per radian)::

        d = sqrt((length_scale * dtheta)**2 + drho**2)

    It is symmetric and zero only for equal lines, but it is **not a true
    metric**: the triangle inequality can fail for lines more than 90 degrees
    apart, and the offset term depends on ``origin`` (put it at the centre of
    the data).

    Parameters
    ----------
    length_scale : float
        Data units per radian of angle; the radius of the data is a good value.
    origin : array_like of shape (2,)
        Point offsets are measured from.

    Examples
    --------
    >>> space = Line2D(length_scale=10.0)
    >>> a = np.array([0.0, 1.0]); b = np.array([np.pi - 0.01, -1.0])
    >>> print(f"{float(space.distance(a, b)):.3f}")
    0.100
    """

    dim = 2
    point_shape = (2,)
    is_metric = False
    name = "lines"
    has_split_mean = True

    def __init__(self, length_scale: float = 1.0, origin=(0.0, 0.0)):
        self.length_scale = check_positive(length_scale, "length_scale")
        self.origin = check_array(origin, "origin", shape=(2,))
        super().__init__(tangent_weights=np.array([self.length_scale, 1.0]))

    def __repr__(self) -> str:
        return f"Line2D(length_scale={self.length_scale:g}, origin={self.origin.tolist()})"

    def _rho_from_origin(self, lines):
        theta, rho = lines[..., 0], lines[..., 1]
        return rho - np.cos(theta) * self.origin[0] - np.sin(theta) * self.origin[1]

    def log(self, point, base_point) -> np.ndarray:
        p = np.asarray(point, dtype=float)
        b = np.asarray(base_point, dtype=float)
        dtheta = wrap_angle(p[..., 0] - b[..., 0])
        rho_p = self._rho_from_origin(p)
        rho_b = self._rho_from_origin(b)
        flip = np.abs(dtheta) > np.pi / 2
        dtheta = np.where(flip, dtheta - np.pi * np.sign(dtheta), dtheta)
        rho_p = np.where(flip, -rho_p, rho_p)
        return np.stack(np.broadcast_arrays(dtheta, rho_p - rho_b), axis=-1)

    def exp(self, tangent, base_point) -> np.ndarray:
        v = np.asarray(tangent, dtype=float)
        b = np.asarray(base_point, dtype=float)
        theta = b[..., 0] + v[..., 0]
        rho_o = self._rho_from_origin(b) + v[..., 1]
        rho = rho_o + np.cos(theta) * self.origin[0] + np.sin(theta) * self.origin[1]
        return canonical_lines(np.stack(np.broadcast_arrays(theta, rho), axis=-1))

    def reference_point(self) -> np.ndarray:
        return np.array([0.0, float(self.origin[0])])

    def projection(self, points) -> np.ndarray:
        return canonical_lines(points)

    def split_mean(self, points, weights=None) -> np.ndarray:
        """Average angle (axial mean of the normals) and offset separately."""
        pts = self._check_sample(points)
        w = self._check_weights(weights, pts.shape[0])
        ref = pts[int(np.argmax(w))]
        logs = self.log(pts, ref)
        return self.exp(np.tensordot(w, logs, axes=1), ref)

    # -------------------------------------------------------------- helpers
    @staticmethod
    def normal_offset(lines):
        """``(unit normal (..., 2), offset (...))`` of lines ``a x + b y = c``."""
        lines = np.asarray(lines, dtype=float)
        theta = lines[..., 0]
        return np.stack([np.cos(theta), np.sin(theta)], axis=-1), lines[..., 1]

    @staticmethod
    def from_normal_offset(normal, offset) -> np.ndarray:
        """Lines from (not necessarily unit) normals ``(..., 2)`` and offsets ``(...)``."""
        normal = np.asarray(normal, dtype=float)
        length = np.linalg.norm(normal, axis=-1)
        if np.any(length == 0):
            raise ValueError("normal: a line normal must be non-zero")
        theta = np.arctan2(normal[..., 1], normal[..., 0])
        return canonical_lines(np.stack([theta, np.asarray(offset) / length], axis=-1))
