"""SE(3): rigid motions of space, as batched 4 x 4 homogeneous matrices."""

from __future__ import annotations

import numpy as np

from .._validation import check_array, check_int, check_positive
from .base import MatrixLieGroup
from .so3 import so3_exp, so3_hat, so3_left_jacobian, so3_left_jacobian_inverse, so3_log, so3_vee

__all__ = ["SE3"]


class SE3(MatrixLieGroup):
    """Poses ``[[R, t], [0, 1]]``; tangent ``(rho, phi)`` (translation part first).

    The paper's distances (Section IV-B):

    * relative transform error ``(e_t, e_r)`` of ``T1^-1 T2``: :meth:`relative_error`;
    * Lie-log scalar ``sqrt(|rho|^2 + lambda^2 |phi|^2)`` of ``log(T1^-1 T2)``:
      :meth:`distance` with ``angle_weight = lambda`` (left-invariant,
      symmetric, not a true metric);
    * point-set induced distance: :meth:`point_set_distance`.

    Examples
    --------
    >>> g = SE3(angle_weight=0.5)
    >>> T = g.expmap([1.0, 0.0, 0.0, 0.0, 0.0, 0.2])
    >>> print(f"{float(g.distance(g.identity(), T)):.4f}")
    1.0050
    """

    dim = 6
    matrix_size = 4
    is_metric = False
    name = "SE(3)"

    def __init__(self, angle_weight: float = 1.0):
        self.angle_weight = check_positive(angle_weight, "angle_weight")
        super().__init__(tangent_weights=np.r_[np.ones(3), np.full(3, self.angle_weight)])

    def __repr__(self) -> str:
        return f"SE3(angle_weight={self.angle_weight:g})"

    @staticmethod
    def from_rt(R, t) -> np.ndarray:
        """Matrices ``(..., 4, 4)`` from rotations ``(..., 3, 3)`` and translations ``(..., 3)``."""
        R = np.asarray(R, dtype=float)
        t = np.asarray(t, dtype=float)
        shape = np.broadcast_shapes(R.shape[:-2], t.shape[:-1])
        T = np.zeros((*shape, 4, 4))
        T[..., :3, :3] = R
        T[..., :3, 3] = t
        T[..., 3, 3] = 1.0
        return T

    @staticmethod
    def to_rt(T):
        """``(R (..., 3, 3), t (..., 3))``."""
        T = np.asarray(T, dtype=float)
        return T[..., :3, :3], T[..., :3, 3]

    def inverse(self, a) -> np.ndarray:
        R, t = self.to_rt(a)
        Rt = np.swapaxes(R, -1, -2)
        return self.from_rt(Rt, -(Rt @ t[..., None])[..., 0])

    def hat(self, tangent) -> np.ndarray:
        v = np.asarray(tangent, dtype=float)
        out = np.zeros((*v.shape[:-1], 4, 4))
        out[..., :3, :3] = so3_hat(v[..., 3:])
        out[..., :3, 3] = v[..., :3]
        return out

    def vee(self, matrix) -> np.ndarray:
        m = np.asarray(matrix)
        return np.concatenate([m[..., :3, 3], so3_vee(m[..., :3, :3])], -1)

    def expmap(self, tangent) -> np.ndarray:
        v = np.asarray(tangent, dtype=float)
        phi = v[..., 3:]
        t = (so3_left_jacobian(phi) @ v[..., :3, None])[..., 0]
        return self.from_rt(so3_exp(phi), t)

    def logmap(self, point) -> np.ndarray:
        R, t = self.to_rt(point)
        phi = so3_log(R)
        rho = (so3_left_jacobian_inverse(phi) @ t[..., None])[..., 0]
        return np.concatenate([rho, phi], -1)

    def relative_error(self, T1, T2):
        """``(e_t, e_r)`` of ``T1^-1 T2``: translation norm (metres), rotation angle (radians)."""
        D = self.compose(self.inverse(T1), T2)
        R, t = self.to_rt(D)
        return np.linalg.norm(t, axis=-1), np.linalg.norm(so3_log(R), axis=-1)

    def point_set_distance(self, T1, T2, reference_points) -> np.ndarray:
        """RMS distance between ``reference_points`` ``(P, 3)`` moved by ``T1`` and by ``T2``."""
        P = check_array(reference_points, "reference_points", shape=(None, 3))
        R1, t1 = self.to_rt(T1)
        R2, t2 = self.to_rt(T2)
        p1 = np.einsum("...ij,pj->...pi", R1, P) + t1[..., None, :]
        p2 = np.einsum("...ij,pj->...pi", R2, P) + t2[..., None, :]
        return np.sqrt(np.mean(np.sum((p1 - p2) ** 2, axis=-1), axis=-1))

    def split_mean(self, points, weights=None, *, max_iter: int = 50,
                   tol: float = 1e-12) -> np.ndarray:
        """Karcher mean of the rotations on SO(3) and arithmetic mean of the translations."""
        pts = self._check_sample(points)
        w = self._check_weights(weights, pts.shape[0])
        max_iter = check_int(max_iter, "max_iter", minimum=1)
        R, t = self.to_rt(pts)
        Rm = R[int(np.argmax(w))]
        for _ in range(max_iter):
            step = w @ so3_log(Rm.T @ R)
            Rm = Rm @ so3_exp(step)
            if np.linalg.norm(step) <= tol:
                break
        return self.from_rt(Rm, w @ t)
