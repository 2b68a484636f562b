"""SE(2): rigid motions of the plane, as batched 3 x 3 homogeneous matrices."""

from __future__ import annotations

import numpy as np

from .._validation import check_positive
from .base import MatrixLieGroup
from .lines import wrap_angle

__all__ = ["SE2"]


def _coefficients(theta):
    """sin(t)/t and (1 - cos t)/t with Taylor series near 0."""
    small = np.abs(theta) < 1e-6
    ts = np.where(small, 1.0, theta)
    a = np.where(small, 1 - theta**2 / 6, np.sin(ts) / ts)
    b = np.where(small, theta / 2 - theta**3 / 24, (1 - np.cos(ts)) / ts)
    return a, b


class SE2(MatrixLieGroup):
    """Planar poses ``[[R, t], [0, 1]]``; tangent ``(rho_x, rho_y, theta)``.

    The distance ``sqrt(|rho|^2 + angle_weight^2 theta^2)`` of ``log(a^-1 b)``
    is left-invariant and symmetric; it is not a true metric in general (the
    log chart is not a geodesic distance of a bi-invariant metric).

    Parameters
    ----------
    angle_weight : float
        lambda, metres per radian.

    Examples
    --------
    >>> g = SE2()
    >>> a = g.from_xytheta(1.0, 2.0, np.pi / 2)
    >>> g.to_xytheta(g.compose(a, a)).round(6).tolist()
    [-1.0, 3.0, 3.141593]
    """

    dim = 3
    matrix_size = 3
    is_metric = False
    name = "SE(2)"

    def __init__(self, angle_weight: float = 1.0):
        self.angle_weight = check_positive(angle_weight, "angle_weight")
        super().__init__(tangent_weights=np.array([1.0, 1.0, self.angle_weight]))

    def __repr__(self) -> str:
        return f"SE2(angle_weight={self.angle_weight:g})"

    @staticmethod
    def from_xytheta(x, y, theta) -> np.ndarray:
        """Matrices ``(..., 3, 3)`` from positions and headings (broadcast)."""
        x, y, theta = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (x, y, theta)))
        c, s = np.cos(theta), np.sin(theta)
        T = np.zeros((*x.shape, 3, 3))
        T[..., 0, 0], T[..., 0, 1], T[..., 0, 2] = c, -s, x
        T[..., 1, 0], T[..., 1, 1], T[..., 1, 2] = s, c, y
        T[..., 2, 2] = 1.0
        return T

    @staticmethod
    def to_xytheta(T) -> np.ndarray:
        """``(..., 3)`` rows ``(x, y, theta)`` with theta in ``[-pi, pi)``."""
        T = np.asarray(T, dtype=float)
        return np.stack([T[..., 0, 2], T[..., 1, 2], np.arctan2(T[..., 1, 0], T[..., 0, 0])], -1)

    def inverse(self, a) -> np.ndarray:
        a = np.asarray(a, dtype=float)
        out = np.zeros_like(a)
        Rt = np.swapaxes(a[..., :2, :2], -1, -2)
        out[..., :2, :2] = Rt
        out[..., :2, 2] = -(Rt @ a[..., :2, 2:3])[..., 0]
        out[..., 2, 2] = 1.0
        return out

    def hat(self, tangent) -> np.ndarray:
        v = np.asarray(tangent, dtype=float)
        out = np.zeros((*v.shape[:-1], 3, 3))
        out[..., 0, 1], out[..., 1, 0] = -v[..., 2], v[..., 2]
        out[..., :2, 2] = v[..., :2]
        return out

    def vee(self, matrix) -> np.ndarray:
        m = np.asarray(matrix)
        return np.stack([m[..., 0, 2], m[..., 1, 2], m[..., 1, 0]], -1)

    def expmap(self, tangent) -> np.ndarray:
        v = np.asarray(tangent, dtype=float)
        theta = v[..., 2]
        a, b = _coefficients(theta)
        x = a * v[..., 0] - b * v[..., 1]
        y = b * v[..., 0] + a * v[..., 1]
        return self.from_xytheta(x, y, theta)

    def logmap(self, point) -> np.ndarray:
        T = np.asarray(point, dtype=float)
        theta = np.arctan2(T[..., 1, 0], T[..., 0, 0])
        a, b = _coefficients(theta)
        det = a**2 + b**2
        tx, ty = T[..., 0, 2], T[..., 1, 2]
        return np.stack([(a * tx + b * ty) / det, (-b * tx + a * ty) / det, theta], -1)

    def split_mean(self, points, weights=None) -> np.ndarray:
        """Circular mean of the headings and arithmetic mean of the positions."""
        pts = self._check_sample(points)
        w = self._check_weights(weights, pts.shape[0])
        xyt = self.to_xytheta(pts)
        theta = np.arctan2(w @ np.sin(xyt[:, 2]), w @ np.cos(xyt[:, 2]))
        return self.from_xytheta(w @ xyt[:, 0], w @ xyt[:, 1], wrap_angle(theta))
