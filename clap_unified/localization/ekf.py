"""Extended Kalman filter on SE(2) fed by odometry and full-pose measurements.

The state is ``(x, y, theta)`` with covariance ``P``. Odometry
``(dx, dy, dtheta)`` in the robot frame moves it (the heading wraps); a pose
measurement (CLAP's estimate of the frame) corrects it, after a Mahalanobis
gate that rejects measurements the filter finds implausible: a wrong
cluster, or the mirror pose of the symmetric field.
"""

from __future__ import annotations

import numpy as np

from .._validation import check_array, check_positive
from ..geometry.lines import wrap_angle

__all__ = ["PoseEKF", "CHI2_3DOF_999"]

#: 99.9 % quantile of the chi-square distribution with 3 degrees of freedom.
CHI2_3DOF_999 = 16.266


class PoseEKF:
    """EKF for a planar pose.

    Parameters
    ----------
    mean : (x, y, theta)
    cov : ndarray of shape (3, 3)
    odometry_noise : float
        Motion noise standard deviation as a fraction of the odometry increment.
    process_noise : (float, float)
        Extra noise per step, metres and radians (slips, pushes).
    gate : float
        Mahalanobis-squared gate for measurements (default chi-square 3 DOF, 99.9 %).

    Examples
    --------
    >>> ekf = PoseEKF((0.0, 0.0, 0.0), np.diag([0.1, 0.1, 0.01]))
    >>> ekf.predict((0.1, 0.0, 0.0))
    >>> ekf.update((0.12, 0.01, 0.0), np.diag([0.01, 0.01, 0.001]))
    True
    >>> print(np.round(ekf.mean, 3))
    [0.118 0.009 0.   ]
    >>> ekf.update((3.0, 0.0, 3.0), np.diag([0.01, 0.01, 0.001]))  # the mirror: gated out
    False
    """

    def __init__(self, mean, cov, *, odometry_noise: float = 0.15,
                 process_noise=(0.01, np.pi / 180), gate: float = CHI2_3DOF_999):
        self.mean = check_array(mean, "mean", shape=(3,)).copy()
        self.cov = check_array(cov, "cov", shape=(3, 3)).copy()
        self.odometry_noise = check_positive(odometry_noise, "odometry_noise", allow_zero=True)
        self.process_noise = np.asarray(process_noise, dtype=float)
        self.gate = check_positive(gate, "gate")

    def predict(self, odometry) -> None:
        """Move by ``(dx, dy, dtheta)`` in the robot frame."""
        dx, dy, dth = check_array(odometry, "odometry", shape=(3,))
        x, y, th = self.mean
        c, s = np.cos(th), np.sin(th)
        self.mean = np.array([x + c * dx - s * dy, y + s * dx + c * dy, wrap_angle(th + dth)])
        F = np.array([[1, 0, -s * dx - c * dy], [0, 1, c * dx - s * dy], [0, 0, 1]])
        G = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
        step = np.hypot(dx, dy)
        sigma = self.odometry_noise * np.array([abs(dx) + 0.1 * step, abs(dy) + 0.1 * step,
                                                abs(dth) + 0.1 * step])
        Q = G @ np.diag(sigma**2) @ G.T + np.diag(np.r_[self.process_noise[:1].repeat(2),
                                                        self.process_noise[1:]] ** 2)
        self.cov = F @ self.cov @ F.T + Q

    def innovation(self, pose):
        """Innovation ``z - mean`` (heading wrapped) and its Mahalanobis squared norm."""
        z = check_array(pose, "pose", shape=(3,))
        v = z - self.mean
        v[2] = wrap_angle(v[2])
        return v

    def mahalanobis2(self, pose, noise) -> float:
        v = self.innovation(pose)
        S = self.cov + check_array(noise, "noise", shape=(3, 3))
        return float(v @ np.linalg.solve(S, v))

    def update(self, pose, noise) -> bool:
        """Correct with a pose measurement ``(x, y, theta)``; False if gated out."""
        v = self.innovation(pose)
        S = self.cov + check_array(noise, "noise", shape=(3, 3))
        if float(v @ np.linalg.solve(S, v)) > self.gate:
            return False
        K = np.linalg.solve(S, self.cov).T  # P S^-1 (both symmetric)
        self.mean = self.mean + K @ v
        self.mean[2] = wrap_angle(self.mean[2])
        I_K = np.eye(3) - K
        self.cov = I_K @ self.cov @ I_K.T + K @ noise @ K.T  # Joseph form
        return True

    def reset(self, mean, cov) -> None:
        self.mean = check_array(mean, "mean", shape=(3,)).copy()
        self.cov = check_array(cov, "cov", shape=(3, 3)).copy()
