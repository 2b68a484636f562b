"""Rotations in 3D: hat, vee, exp, log and the SE(3) left Jacobian (batched functions)."""

from __future__ import annotations

import numpy as np

__all__ = ["so3_hat", "so3_vee", "so3_exp", "so3_log", "so3_left_jacobian",
           "so3_left_jacobian_inverse"]

_SMALL = 1e-6


def so3_hat(phi) -> np.ndarray:
    """Skew matrices ``(..., 3, 3)`` of vectors ``(..., 3)``."""
    phi = np.asarray(phi, dtype=float)
    x, y, z = phi[..., 0], phi[..., 1], phi[..., 2]
    o = np.zeros_like(x)
    return np.stack([np.stack([o, -z, y], -1), np.stack([z, o, -x], -1),
                     np.stack([-y, x, o], -1)], -2)


def so3_vee(m) -> np.ndarray:
    """Vectors ``(..., 3)`` of skew matrices."""
    m = np.asarray(m)
    return np.stack([m[..., 2, 1], m[..., 0, 2], m[..., 1, 0]], -1)


def _coefficients(theta):
    """sin(t)/t, (1-cos t)/t^2, (t - sin t)/t^3 with Taylor series near 0."""
    t2 = theta**2
    small = theta < _SMALL
    ts = np.where(small, 1.0, theta)
    a = np.where(small, 1 - t2 / 6, np.sin(ts) / ts)
    b = np.where(small, 0.5 - t2 / 24, (1 - np.cos(ts)) / ts**2)
    c = np.where(small, 1 / 6 - t2 / 120, (ts - np.sin(ts)) / ts**3)
    return a, b, c


def so3_exp(phi) -> np.ndarray:
    """Rodrigues' formula, ``(..., 3) -> (..., 3, 3)``.

    Examples
    --------
    >>> so3_exp([0.0, 0.0, np.pi / 2]).round(6).tolist()
    [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]
    """
    phi = np.asarray(phi, dtype=float)
    theta = np.linalg.norm(phi, axis=-1)
    a, b, _ = _coefficients(theta)
    K = so3_hat(phi)
    return np.eye(3) + a[..., None, None] * K + b[..., None, None] * (K @ K)


def so3_log(R) -> np.ndarray:
    """Rotation vectors ``(..., 3)`` of rotation matrices, robust near 0 and pi."""
    R = np.asarray(R, dtype=float)
    cos = np.clip((np.trace(R, axis1=-2, axis2=-1) - 1) / 2, -1.0, 1.0)
    theta = np.arccos(cos)
    v = so3_vee(R - np.swapaxes(R, -1, -2)) / 2  # sin(theta) * axis
    sin = np.sin(theta)
    near_pi = theta > np.pi - 1e-3
    small = theta < _SMALL
    scale = np.where(small, 1 + theta**2 / 6, theta / np.where(small | near_pi, 1.0, sin))
    out = v * scale[..., None]
    if np.any(near_pi):
        Rp = R[near_pi]
        th = theta[near_pi]
        # symmetric part: (R + R^T)/2 = cos(t) I + (1 - cos(t)) axis axis^T, exact for any t
        sym = (Rp + np.swapaxes(Rp, -1, -2)) / 2
        c = np.cos(th)[:, None, None]
        B = (sym - c * np.eye(3)) / (1 - c)
        col = np.argmax(np.diagonal(B, axis1=-2, axis2=-1), axis=-1)
        axis = np.take_along_axis(B, col[:, None, None], axis=-1)[..., 0]
        axis /= np.linalg.norm(axis, axis=-1, keepdims=True)
        sgn = np.sign(np.sum(axis * v[near_pi], axis=-1))
        sgn = np.where(sgn == 0, 1.0, sgn)
        out[near_pi] = axis * (sgn * th)[:, None]
    return out


def so3_left_jacobian(phi) -> np.ndarray:
    """V(phi) with ``t = V(phi) rho`` in the SE(3) exponential."""
    phi = np.asarray(phi, dtype=float)
    _, b, c = _coefficients(np.linalg.norm(phi, axis=-1))
    K = so3_hat(phi)
    return np.eye(3) + b[..., None, None] * K + c[..., None, None] * (K @ K)


def so3_left_jacobian_inverse(phi) -> np.ndarray:
    """Inverse of :func:`so3_left_jacobian` (closed form)."""
    phi = np.asarray(phi, dtype=float)
    theta = np.linalg.norm(phi, axis=-1)
    a, b, _ = _coefficients(theta)
    small = theta < _SMALL
    ts = np.where(small, 1.0, theta)
    d = np.where(small, 1 / 12 + theta**2 / 720, (1 - a / (2 * np.where(small, 1.0, b))) / ts**2)
    K = so3_hat(phi)
    return np.eye(3) - 0.5 * K + d[..., None, None] * (K @ K)
