"""SE(2): rigid motions of the plane, as batched 3 x 3 homogeneous matrices."""

from __future__ import annotations

import numpy as np

from .._validation import check_array, check_positive
from .base import MatrixLieGroup

__all__ = ["SE2"]


def _coefficients(theta):
    """``sin(t)/t`` and ``(1 - cos t)/t``, exact near 0.

    ``(1 - cos t)/t`` is computed as ``2 sin(t/2)**2 / t`` (no cancellation);
    both are set to their limits 1 and 0 at ``t = 0``.
    """
    theta = np.asarray(theta, dtype=float)
    zero = theta == 0
    safe = np.where(zero, 1.0, theta)
    a = np.where(zero, 1.0, np.sin(theta) / safe)
    b = 2.0 * np.sin(theta / 2) ** 2 / safe
    return a, b


class SE2(MatrixLieGroup):
    """Planar poses ``T = [[R(theta), t], [0, 1]]``, points of shape ``(..., 3, 3)``.

    The tangent vector is ``(rho_x, rho_y, theta)`` with the closed-form
    exponential ``t = V(theta) rho``, ``V = [[a, -b], [b, a]]``,
    ``a = sin(theta)/theta``, ``b = (1 - cos(theta))/theta`` (Taylor series
    near ``theta = 0``); the logarithm returns ``theta`` in ``(-pi, pi]``.

    The distance ``d(a, b) = sqrt(|rho|^2 + angle_weight^2 theta^2)`` of
    ``log(a^-1 b)`` is left-invariant and symmetric (except at ``theta = pi``
    exactly) but not a true metric: it is not the geodesic distance of a
    Riemannian metric and the triangle inequality can fail.

    Parameters
    ----------
    angle_weight : float
        lambda, metres per radian; ``tangent_weights = (1, 1, lambda)``.

    Examples
    --------
    >>> g = SE2(angle_weight=2.0)
    >>> a = g.from_xytheta(1.0, 2.0, np.pi / 2)
    >>> g.to_xytheta(g.compose(a, a)).round(6).tolist()
    [-1.0, 3.0, 3.141593]
    >>> print(f"{float(g.distance(g.identity(), g.from_xytheta(0.0, 0.0, 0.5))):.4f}")
    1.0000
    """

    dim = 3
    matrix_size = 3
    is_metric = False
    small_pairwise = 512
    name = "SE(2)"
    has_split_mean = True
    has_chordal_embedding = True
    embedding_bounds_distance = True

    def __init__(self, angle_weight: float = 1.0):
        self.angle_weight = check_positive(angle_weight, "angle_weight")
        super().__init__(tangent_weights=np.array([1.0, 1.0, self.angle_weight]))

    def __repr__(self) -> str:
        return f"SE2(angle_weight={self.angle_weight:g})"

    # ------------------------------------------------------------ constructors
    @staticmethod
    def from_xytheta(x, y, theta) -> np.ndarray:
        """Poses from positions and headings.

        Parameters
        ----------
        x, y, theta : array_like, broadcastable to a common shape S
            Position (metres) and heading (radians).

        Returns
        -------
        ndarray of shape S + (3, 3)

        Examples
        --------
        >>> SE2.from_xytheta([0.0, 1.0], 2.0, 0.0)[:, :2, 2].tolist()
        [[0.0, 2.0], [1.0, 2.0]]
        """
        x, y, theta = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(y, dtype=float),
                                          np.asarray(theta, dtype=float))
        if not (np.isfinite(x).all() and np.isfinite(y).all() and np.isfinite(theta).all()):
            for v, n in ((x, "x"), (y, "y"), (theta, "theta")):
                check_array(v, n)  # names the offending argument
        c, s = np.cos(theta), np.sin(theta)
        T = np.zeros((*x.shape, 3, 3))
        T[..., 0, 0], T[..., 0, 1], T[..., 0, 2] = c, -s, x
        T[..., 1, 0], T[..., 1, 1], T[..., 1, 2] = s, c, y
        T[..., 2, 2] = 1.0
        return T

    @staticmethod
    def to_xytheta(T) -> np.ndarray:
        """Positions and headings of poses.

        Parameters
        ----------
        T : ndarray of shape (..., 3, 3)

        Returns
        -------
        ndarray of shape (..., 3)
            Rows ``(x, y, theta)`` with ``theta`` in ``(-pi, pi]``.

        Examples
        --------
        >>> SE2.to_xytheta(SE2.from_xytheta(1.0, -2.0, 0.5)).round(6).tolist()
        [1.0, -2.0, 0.5]
        """
        T = check_array(T, "T", shape=(Ellipsis, 3, 3))
        return np.stack([T[..., 0, 2], T[..., 1, 2], np.arctan2(T[..., 1, 0], T[..., 0, 0])], -1)

    # ------------------------------------------------------------ group maps
    def inverse(self, a) -> np.ndarray:
        """Closed-form inverse ``[[R^T, -R^T t], [0, 1]]`` of ``(..., 3, 3)`` poses."""
        a = np.asarray(a, dtype=float)
        out = np.zeros_like(a)
        Rt = np.swapaxes(a[..., :2, :2], -1, -2)
        out[..., :2, :2] = Rt
        out[..., :2, 2] = -(Rt @ a[..., :2, 2:3])[..., 0]
        out[..., 2, 2] = 1.0
        return out

    def hat(self, tangent) -> np.ndarray:
        """``(..., 3) -> (..., 3, 3)``: ``[[0, -theta, rho_x], [theta, 0, rho_y], [0, 0, 0]]``."""
        v = np.asarray(tangent, dtype=float)
        out = np.zeros((*v.shape[:-1], 3, 3))
        out[..., 0, 1], out[..., 1, 0] = -v[..., 2], v[..., 2]
        out[..., :2, 2] = v[..., :2]
        return out

    def vee(self, matrix) -> np.ndarray:
        """``(..., 3, 3) -> (..., 3)``, inverse of :meth:`hat`."""
        m = np.asarray(matrix)
        return np.stack([m[..., 0, 2], m[..., 1, 2], m[..., 1, 0]], -1)

    def expmap(self, tangent) -> np.ndarray:
        """Closed-form exponential ``(..., 3) -> (..., 3, 3)``."""
        v = np.asarray(tangent, dtype=float)
        theta = v[..., 2]
        a, b = _coefficients(theta)
        x = a * v[..., 0] - b * v[..., 1]
        y = b * v[..., 0] + a * v[..., 1]
        return self.from_xytheta(x, y, theta)

    def chordal_embedding(self, points) -> np.ndarray:
        """Euclidean coordinates ``(..., 4)`` whose distances bound the SE(2) distance below.

        ``(x, y, lambda cos(theta), lambda sin(theta))``: two embeddings are
        ``sqrt(|t1 - t2|^2 + lambda^2 (2 sin(dtheta / 2))^2)`` apart, never more
        than :meth:`distance` (``|rho| >= |t1 - t2|`` because ``V(theta)`` shrinks,
        and ``|dtheta| >= 2 |sin(dtheta / 2)|``) and equal to it to second order in
        the angle, so a k-d tree on them finds every neighbourhood.

        Examples
        --------
        >>> g = SE2(angle_weight=2.0)
        >>> T = g.from_xytheta(np.array([0.0, 1.0]), 0.0, np.array([0.0, 0.3]))
        >>> e = g.chordal_embedding(T)
        >>> print(f"{np.linalg.norm(e[0] - e[1]):.5f} <= {float(g.distance(T[0], T[1])):.5f}")
        1.16504 <= 1.16942
        """
        T = np.asarray(points, dtype=float)
        lam = self.angle_weight
        return np.stack([T[..., 0, 2], T[..., 1, 2], lam * T[..., 0, 0], lam * T[..., 1, 0]],
                        axis=-1)

    def log(self, point, base_point) -> np.ndarray:
        """``logmap(base^-1 point)`` from the matrix entries, without forming the product.

        The relative heading is ``atan2`` of the sine and cosine differences
        and the relative translation is ``R_base^T (t - t_base)``: a few
        elementwise operations, the hot path of CLAP's pairwise distances.
        """
        a = np.asarray(base_point, dtype=float)
        b = np.asarray(point, dtype=float)
        ca, sa = a[..., 0, 0], a[..., 1, 0]
        cb, sb = b[..., 0, 0], b[..., 1, 0]
        theta = np.arctan2(ca * sb - sa * cb, ca * cb + sa * sb)
        dx, dy = b[..., 0, 2] - a[..., 0, 2], b[..., 1, 2] - a[..., 1, 2]
        tx, ty = ca * dx + sa * dy, -sa * dx + ca * dy
        return self._log_from(tx, ty, theta)

    @staticmethod
    def _log_from(tx, ty, theta):
        a, b = _coefficients(theta)
        det = a**2 + b**2  # V^-1 = [[a, b], [-b, a]] / det; det >= 4 / pi^2 for |theta| <= pi
        return np.stack([(a * tx + b * ty) / det, (-b * tx + a * ty) / det, theta], -1)

    def logmap(self, point) -> np.ndarray:
        """Closed-form logarithm ``(..., 3, 3) -> (..., 3)``, ``theta`` in ``(-pi, pi]``."""
        T = np.asarray(point, dtype=float)
        theta = np.arctan2(T[..., 1, 0], T[..., 0, 0])
        return self._log_from(T[..., 0, 2], T[..., 1, 2], theta)

    # --------------------------------------------------------------- average
    def split_mean(self, points, weights=None) -> np.ndarray:
        """Circular mean of the headings and arithmetic mean of the positions.

        Parameters
        ----------
        points : ndarray of shape (N, 3, 3)
        weights : ndarray of shape (N,), optional
            Non-negative, normalised to sum to one.

        Returns
        -------
        ndarray of shape (3, 3)
            Heading ``atan2(sum w sin(theta), sum w cos(theta))`` (0 when the
            headings cancel exactly), position ``sum w t``.

        Examples
        --------
        >>> g = SE2()
        >>> pts = g.from_xytheta([0.0, 2.0], [0.0, 0.0], [3.0, -3.0])
        >>> g.to_xytheta(g.split_mean(pts)).round(6).tolist()
        [1.0, 0.0, 3.141593]
        """
        pts = self._check_sample(points)
        w = self._check_weights(weights, pts.shape[0])
        xyt = self.to_xytheta(pts)
        theta = np.arctan2(w @ np.sin(xyt[:, 2]), w @ np.cos(xyt[:, 2]))
        return self.from_xytheta(w @ xyt[:, 0], w @ xyt[:, 1], theta)
