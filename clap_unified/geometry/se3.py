"""SE(3): rigid motions of space, as batched 4 x 4 homogeneous matrices."""

from __future__ import annotations

import numpy as np

from .._validation import check_array, check_int, check_positive
from .base import MatrixLieGroup
from .so3 import so3_exp, so3_hat, so3_left_jacobian, so3_left_jacobian_inverse, so3_log, so3_vee

__all__ = ["SE3"]


class SE3(MatrixLieGroup):
    """Poses ``T = [[R, t], [0, 1]]``, points of shape ``(..., 4, 4)``.

    The tangent vector is ``(rho, phi)`` (dim 6, translation part first) with
    the closed-form exponential ``R = exp(phi)``, ``t = V(phi) rho`` (see
    :mod:`~clap_unified.geometry.so3`); note that ``rho = V(phi)^-1 t`` is
    not the translation itself.

    The paper's distances between poses:

    * relative transform error ``(e_t, e_r)`` of ``T1^-1 T2``: :meth:`relative_error`;
    * Lie-log scalar ``sqrt(|rho|^2 + lambda^2 |phi|^2)`` of ``log(T1^-1 T2)``:
      :meth:`distance` with ``angle_weight = lambda``, i.e. tangent weights
      ``(1, 1, 1, lambda, lambda, lambda)``. It is left-invariant and
      symmetric but not a true metric (the triangle inequality can fail);
    * point-set induced distance: :meth:`point_set_distance`.

    Which of them :meth:`distance` (and so clustering, trimming and the
    medoid) uses is chosen by ``metric``; the averages (Karcher,
    log-Euclidean, split) always use the group's log and exp.

    Parameters
    ----------
    angle_weight : float
        lambda, metres per radian.
    metric : {"lie", "relative", "point_set"}
        ``"lie"``: the Lie-log scalar above (default). ``"relative"``: the
        relative transform error folded into one number,
        ``sqrt(e_t^2 + lambda^2 e_r^2)``; a true metric (``e_t = |t2 - t1|``
        and ``e_r`` is the geodesic angle) and several times cheaper than the
        logarithm, because ``e_r`` comes from ``|R1 - R2|_F = 2 sqrt(2)
        sin(e_r / 2)``. ``"point_set"``: :meth:`point_set_distance` over
        ``reference_points`` (``angle_weight`` is then unused).
    reference_points : ndarray of shape (P, 3), optional
        Needed by ``metric="point_set"``.

    Examples
    --------
    >>> g = SE3(angle_weight=0.5)
    >>> T = g.expmap([1.0, 0.0, 0.0, 0.0, 0.0, 0.2])
    >>> print(f"{float(g.distance(g.identity(), T)):.4f}")
    1.0050
    >>> print(f"{float(SE3(0.5, metric='relative').distance(g.identity(), T)):.4f}")
    1.0033
    """

    dim = 6
    matrix_size = 4
    is_metric = False
    name = "SE(3)"
    has_split_mean = True
    has_chordal_embedding = True

    #: Distances :meth:`distance` can use.
    METRICS = ("lie", "relative", "point_set")

    def __init__(self, angle_weight: float = 1.0, *, metric: str = "lie",
                 reference_points=None):
        self.angle_weight = check_positive(angle_weight, "angle_weight")
        super().__init__(tangent_weights=np.r_[np.ones(3), np.full(3, self.angle_weight)])
        if metric not in self.METRICS:
            raise ValueError(f"metric: expected one of {list(self.METRICS)}, got {metric!r}")
        self.metric = metric
        self.reference_points = None
        if metric == "point_set":
            if reference_points is None:
                raise ValueError("reference_points: metric='point_set' needs reference points")
            X = check_array(reference_points, "reference_points", shape=(None, 3))
            if len(X) == 0:
                raise ValueError("reference_points: need at least one point, got 0")
            self.reference_points = X
            self._moments = (X.mean(axis=0), X.T @ X / len(X))
        self.is_metric = metric != "lie"
        #: The chordal embedding bounds the ``lie`` and ``relative`` distances below (not
        #: ``point_set``).
        self.embedding_bounds_distance = metric != "point_set"

    def __repr__(self) -> str:
        if self.metric == "lie":
            return f"SE3(angle_weight={self.angle_weight:g})"
        if self.metric == "point_set":
            return f"SE3(metric='point_set', points={len(self.reference_points)})"
        return f"SE3(angle_weight={self.angle_weight:g}, metric={self.metric!r})"

    def distance(self, point_a, point_b) -> np.ndarray:
        """Distance chosen by ``metric``, broadcast over leading axes.

        Examples
        --------
        >>> X = np.array([[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
        >>> g = SE3(metric="point_set", reference_points=X)
        >>> T = SE3.from_rt(np.eye(3), [0.0, 0.0, 0.3])
        >>> print(f"{float(g.distance(g.identity(), T)):.3f}")
        0.300
        """
        if self.metric == "lie":
            return super().distance(point_a, point_b)
        a = np.asarray(point_a, dtype=float)
        b = np.asarray(point_b, dtype=float)
        if self.metric == "relative":
            dt = a[..., :3, 3] - b[..., :3, 3]
            dR = a[..., :3, :3] - b[..., :3, :3]
            chord = np.sqrt(np.einsum("...ij,...ij->...", dR, dR)) / (2 * np.sqrt(2))
            angle = 2 * np.arcsin(np.minimum(chord, 1.0))
            return np.sqrt(np.einsum("...i,...i->...", dt, dt) + (self.angle_weight * angle) ** 2)
        return self._point_set(a, b, *self._moments)

    def _pairwise_symmetric(self, a) -> np.ndarray:
        """The ``relative`` metric of up to 400 poses by broadcasting (no pair indexing)."""
        if self.metric != "relative" or len(a) > 400:
            return super()._pairwise_symmetric(a)
        flat = a[:, :3, :].reshape(-1, 12)  # rows [R00 R01 R02 t0 R10 ...]
        diff = flat[:, None] - flat[None]
        sq = diff * diff
        dt2 = sq[..., 3::4].sum(axis=-1)
        chord = np.sqrt(sq.sum(axis=-1) - dt2) / (2 * np.sqrt(2))
        angle = 2 * np.arcsin(np.minimum(chord, 1.0))
        return np.sqrt(dt2 + (self.angle_weight * angle) ** 2)

    def chordal_embedding(self, points) -> np.ndarray:
        """Euclidean coordinates ``(..., 12)`` whose distances bound the ``relative`` metric.

        ``(t, lambda / sqrt(2) vec(R))``: the Euclidean distance of two
        embeddings is ``sqrt(|t1 - t2|^2 + lambda^2 (2 sin(e_r / 2))^2)``, at
        most the ``relative`` distance and equal to it to second order in the
        angle. A k-d tree on these finds neighbourhoods in ``O(H log H)``
        instead of the ``O(H^2)`` pairwise matrix.

        Examples
        --------
        >>> g = SE3(2.0, metric="relative")
        >>> T = g.expmap(np.array([[0.0] * 6, [0.1, 0, 0, 0, 0, 0.5]]))
        >>> e = g.chordal_embedding(T)
        >>> print(f"{np.linalg.norm(e[0] - e[1]):.5f} <= {float(g.distance(T[0], T[1])):.5f}")
        0.99455 <= 1.00488
        """
        T = np.asarray(points, dtype=float)
        R = T[..., :3, :3].reshape(*T.shape[:-2], 9)
        return np.concatenate([T[..., :3, 3], self.angle_weight / np.sqrt(2) * R], axis=-1)

    @staticmethod
    def _point_set(T1, T2, mu, S):
        D = T1[..., :3, :] - T2[..., :3, :]  # (..., 3, 4): [dR | dt]
        dR, dt = D[..., :3], D[..., 3]
        msq = (np.einsum("...ij,jk,...ik->...", dR, S, dR)
               + 2 * np.einsum("...i,...ij,j->...", dt, dR, mu)
               + np.einsum("...i,...i->...", dt, dt))
        return np.sqrt(np.maximum(msq, 0.0))

    # ------------------------------------------------------------ constructors
    @staticmethod
    def from_rt(R, t) -> np.ndarray:
        """Poses from rotations and translations.

        Parameters
        ----------
        R : ndarray of shape (..., 3, 3)
        t : ndarray of shape (..., 3)
            Leading axes broadcast against those of ``R``.

        Returns
        -------
        ndarray of shape (..., 4, 4)

        Examples
        --------
        >>> SE3.from_rt(np.eye(3), [1.0, 2.0, 3.0])[:3, 3].tolist()
        [1.0, 2.0, 3.0]
        """
        R = check_array(R, "R", shape=(Ellipsis, 3, 3))
        t = check_array(t, "t", shape=(Ellipsis, 3))
        shape = np.broadcast_shapes(R.shape[:-2], t.shape[:-1])
        T = np.zeros((*shape, 4, 4))
        T[..., :3, :3] = R
        T[..., :3, 3] = t
        T[..., 3, 3] = 1.0
        return T

    @staticmethod
    def to_rt(T):
        """Rotations ``(..., 3, 3)`` and translations ``(..., 3)`` of poses ``(..., 4, 4)``."""
        T = np.asarray(T, dtype=float)
        return T[..., :3, :3], T[..., :3, 3]

    # ------------------------------------------------------------ group maps
    def inverse(self, a) -> np.ndarray:
        """Closed-form inverse ``[[R^T, -R^T t], [0, 1]]`` of ``(..., 4, 4)`` poses."""
        R, t = self.to_rt(a)
        Rt = np.swapaxes(R, -1, -2)
        out = np.zeros(np.shape(a))
        out[..., :3, :3] = Rt
        out[..., :3, 3] = -(Rt @ t[..., None])[..., 0]
        out[..., 3, 3] = 1.0
        return out

    def hat(self, tangent) -> np.ndarray:
        """``(..., 6) -> (..., 4, 4)``: ``[[hat(phi), rho], [0, 0]]``."""
        v = np.asarray(tangent, dtype=float)
        out = np.zeros((*v.shape[:-1], 4, 4))
        out[..., :3, :3] = so3_hat(v[..., 3:])
        out[..., :3, 3] = v[..., :3]
        return out

    def vee(self, matrix) -> np.ndarray:
        """``(..., 4, 4) -> (..., 6)``, inverse of :meth:`hat`."""
        m = np.asarray(matrix)
        return np.concatenate([m[..., :3, 3], so3_vee(m[..., :3, :3])], -1)

    def expmap(self, tangent) -> np.ndarray:
        """Closed-form exponential ``(..., 6) -> (..., 4, 4)``."""
        v = np.asarray(tangent, dtype=float)
        phi = v[..., 3:]
        t = (so3_left_jacobian(phi) @ v[..., :3, None])[..., 0]
        return self.from_rt(so3_exp(phi), t)

    def logmap(self, point) -> np.ndarray:
        """Closed-form logarithm ``(..., 4, 4) -> (..., 6)``, rotation angle in ``[0, pi]``."""
        R, t = self.to_rt(point)
        phi = so3_log(R)
        rho = (so3_left_jacobian_inverse(phi) @ t[..., None])[..., 0]
        return np.concatenate([rho, phi], -1)

    # -------------------------------------------------------- paper distances
    def relative_error(self, T1, T2):
        """Translation and rotation error of ``Delta = T1^-1 T2``.

        Parameters
        ----------
        T1, T2 : ndarray of shape (..., 4, 4)
            Broadcast against each other.

        Returns
        -------
        e_t : ndarray of shape (...)
            ``|t_Delta|`` (the units of the translations).
        e_r : ndarray of shape (...)
            ``|log(R_Delta)|``, the rotation angle in radians, in ``[0, pi]``.

        Examples
        --------
        >>> g = SE3()
        >>> e_t, e_r = g.relative_error(g.identity(), g.from_rt(so3_exp([0, 0, 0.3]), [3, 4, 0]))
        >>> print(f"{float(e_t):.3f} {float(e_r):.3f}")
        5.000 0.300
        """
        T1 = self.validate(T1, "T1")
        T2 = self.validate(T2, "T2")
        R, t = self.to_rt(self.compose(self.inverse(T1), T2))
        return np.linalg.norm(t, axis=-1), np.linalg.norm(so3_log(R), axis=-1)

    def point_set_distance(self, T1, T2, reference_points) -> np.ndarray:
        """Root mean square distance between reference points moved by ``T1`` and by ``T2``.

        ``sqrt(mean_p |T1 x_p - T2 x_p|^2)``, evaluated from the first and
        second moments of the reference points, so the cost does not grow
        with their number. It is a true metric on poses when the points are
        not collinear, but depends on where the points are.

        Parameters
        ----------
        T1, T2 : ndarray of shape (..., 4, 4)
            Broadcast against each other.
        reference_points : ndarray of shape (P, 3)

        Returns
        -------
        ndarray of shape (...)

        Examples
        --------
        >>> g = SE3()
        >>> X = np.array([[1.0, 0.0, 0.0], [-1.0, 0.0, 0.0]])
        >>> flip = g.from_rt(so3_exp([0.0, 0.0, np.pi]), np.zeros(3))
        >>> print(f"{float(g.point_set_distance(g.identity(), flip, X)):.6f}")
        2.000000
        """
        T1 = self.validate(T1, "T1")
        T2 = self.validate(T2, "T2")
        X = check_array(reference_points, "reference_points", shape=(None, 3))
        if len(X) == 0:
            raise ValueError("reference_points: need at least one point, got 0")
        return self._point_set(T1, T2, X.mean(axis=0), X.T @ X / len(X))

    # --------------------------------------------------------------- average
    def split_mean(self, points, weights=None, *, max_iter: int = 50,
                   tol: float = 1e-12) -> np.ndarray:
        """Karcher mean of the rotations on SO(3), arithmetic mean of the translations.

        The rotation iterates ``R <- R exp(sum_i w_i log(R^T R_i))`` from the
        heaviest rotation until the step is shorter than ``tol`` (radians) or
        ``max_iter`` steps were taken.

        Parameters
        ----------
        points : ndarray of shape (N, 4, 4)
        weights : ndarray of shape (N,), optional
            Non-negative, normalised to sum to one.
        max_iter : int
            Iteration cap.
        tol : float
            Stop when the rotation step is shorter than this (radians).

        Returns
        -------
        ndarray of shape (4, 4)

        Examples
        --------
        >>> g = SE3()
        >>> pts = g.from_rt(so3_exp([[0, 0, 0.2], [0, 0, -0.2]]), [[0, 0, 0], [2, 0, 0]])
        >>> (g.split_mean(pts)[:3].round(6) + 0.0).tolist()
        [[1.0, 0.0, 0.0, 1.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]]
        """
        pts = self._check_sample(points)
        w = self._check_weights(weights, pts.shape[0])
        max_iter = check_int(max_iter, "max_iter", minimum=1)
        tol = check_positive(tol, "tol", allow_zero=True)
        R, t = self.to_rt(pts)
        Rm = R[int(np.argmax(w))]
        for _ in range(max_iter):
            step = w @ so3_log(Rm.T @ R)
            Rm = Rm @ so3_exp(step)
            if np.linalg.norm(step) <= tol:
                break
        return self.from_rt(Rm, w @ t)
