"""Rotations in 3D as plain batched array functions: hat, vee, exp, log, left Jacobian.

These are the building blocks of :class:`~clap_unified.geometry.se3.SE3` (the
thin class keeps the group bookkeeping, these keep the formulas, as in
spatialmath). Rotation vectors ``phi`` have shape ``(..., 3)``, rotation
matrices ``(..., 3, 3)``; every function broadcasts over the leading axes.
With ``theta = |phi|`` and ``K = hat(phi)``:

* ``exp(phi) = I + sin(theta)/theta K + (1 - cos(theta))/theta^2 K^2`` (Rodrigues);
* ``V(phi) = I + (1 - cos(theta))/theta^2 K + (theta - sin(theta))/theta^3 K^2``
  is the left Jacobian of SO(3), the matrix with ``t = V(phi) rho`` in the
  SE(3) exponential.

The coefficients switch to Taylor series for ``theta < 1e-6`` (their error is
then below ``1e-24``).
"""

from __future__ import annotations

import numpy as np

from .._validation import check_array

__all__ = ["so3_hat", "so3_vee", "so3_exp", "so3_log", "so3_left_jacobian",
           "so3_left_jacobian_inverse"]

_SMALL = 1e-6


def so3_hat(phi) -> np.ndarray:
    """Skew-symmetric matrices of vectors.

    Parameters
    ----------
    phi : ndarray of shape (..., 3)

    Returns
    -------
    ndarray of shape (..., 3, 3)
        ``hat(phi) @ v == cross(phi, v)``.

    Examples
    --------
    >>> so3_hat([1.0, 2.0, 3.0]).tolist()
    [[0.0, -3.0, 2.0], [3.0, 0.0, -1.0], [-2.0, 1.0, 0.0]]
    """
    phi = check_array(phi, "phi", shape=(Ellipsis, 3))
    x, y, z = phi[..., 0], phi[..., 1], phi[..., 2]
    o = np.zeros_like(x)
    return np.stack([np.stack([o, -z, y], -1), np.stack([z, o, -x], -1),
                     np.stack([-y, x, o], -1)], -2)


def so3_vee(matrix) -> np.ndarray:
    """Vectors of skew-symmetric matrices (inverse of :func:`so3_hat`).

    Parameters
    ----------
    matrix : ndarray of shape (..., 3, 3)

    Returns
    -------
    ndarray of shape (..., 3)

    Examples
    --------
    >>> so3_vee(so3_hat([1.0, 2.0, 3.0])).tolist()
    [1.0, 2.0, 3.0]
    """
    m = np.asarray(matrix)
    return np.stack([m[..., 2, 1], m[..., 0, 2], m[..., 1, 0]], -1)


#: Below this angle ``(t - sin t)/t^3`` and the ``V^-1`` coefficient, whose closed forms
#: cancel catastrophically near 0, come from their Taylor series (truncation < 1e-22).
_SERIES = 1e-2


def _coefficients(theta):
    """``sin(t)/t``, ``(1 - cos t)/t^2``, ``(t - sin t)/t^3``, accurate at every angle.

    ``(1 - cos t)/t^2`` is computed as ``2 sin(t/2)^2 / t^2`` (no cancellation);
    ``(t - sin t)/t^3`` by its Taylor series below :data:`_SERIES` (the closed
    form loses every digit near ``t = 1e-5``).
    """
    t2 = theta**2
    small = theta < _SMALL
    ts = np.where(small, 1.0, theta)
    a = np.where(small, 1 - t2 / 6, np.sin(ts) / ts)
    b = np.where(small, 0.5 - t2 / 24, 2 * np.sin(ts / 2) ** 2 / ts**2)
    series = theta < _SERIES
    tc = np.where(series, 1.0, theta)
    c = np.where(series, 1 / 6 - t2 / 120 + t2**2 / 5040 - t2**3 / 362880,
                 (tc - np.sin(tc)) / tc**3)
    return a, b, c


def so3_exp(phi) -> np.ndarray:
    """Rotation matrices of rotation vectors (Rodrigues' formula).

    Parameters
    ----------
    phi : ndarray of shape (..., 3)
        Axis times angle (radians).

    Returns
    -------
    ndarray of shape (..., 3, 3)

    Examples
    --------
    >>> (so3_exp([0.0, 0.0, np.pi / 2]).round(6) + 0.0).tolist()
    [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]
    """
    phi = check_array(phi, "phi", shape=(Ellipsis, 3))
    theta = np.linalg.norm(phi, axis=-1)
    a, b, _ = _coefficients(theta)
    K = so3_hat(phi)
    return np.eye(3) + a[..., None, None] * K + b[..., None, None] * (K @ K)


def so3_log(R) -> np.ndarray:
    """Rotation vectors of rotation matrices, with the angle in ``[0, pi]``.

    The angle is ``atan2(|v|, (trace R - 1) / 2)`` with ``v = vee(R - R^T) / 2 =
    sin(theta) axis``, accurate at both ends. Near ``theta = 0`` the vector is
    ``v theta / sin(theta)`` (Taylor series). Near ``pi`` (``theta > pi - 1e-3``),
    where ``v`` vanishes, the axis is read from the symmetric part
    ``(R + R^T)/2 = cos(theta) I + (1 - cos(theta)) axis axis^T`` and its sign
    from ``v``. At exactly ``pi`` both signs are logarithms; one is returned.

    Parameters
    ----------
    R : ndarray of shape (..., 3, 3)
        Rotation matrices (orthonormality is not checked).

    Returns
    -------
    ndarray of shape (..., 3)

    Examples
    --------
    >>> phi = np.array([[0.0, 0.0, 1e-9], [0.0, np.pi - 1e-8, 0.0]])
    >>> [f"{x:.10f}" for x in np.linalg.norm(so3_log(so3_exp(phi)), axis=-1)]
    ['0.0000000010', '3.1415926436']
    """
    R = check_array(R, "R", shape=(Ellipsis, 3, 3))
    v = so3_vee(R - np.swapaxes(R, -1, -2)) / 2  # sin(theta) * axis
    sin = np.linalg.norm(v, axis=-1)
    cos = (np.trace(R, axis1=-2, axis2=-1) - 1) / 2
    theta = np.arctan2(sin, cos)
    near_pi = theta > np.pi - 1e-3
    small = theta < _SMALL
    scale = np.where(small, 1 + theta**2 / 6, theta / np.where(small | near_pi, 1.0, sin))
    out = v * scale[..., None]
    if np.any(near_pi):
        Rp = R[near_pi]
        th = theta[near_pi]
        sym = (Rp + np.swapaxes(Rp, -1, -2)) / 2
        c = np.cos(th)[:, None, None]
        B = (sym - c * np.eye(3)) / (1 - c)  # axis axis^T
        col = np.argmax(np.diagonal(B, axis1=-2, axis2=-1), axis=-1)
        axis = np.take_along_axis(B, col[:, None, None], axis=-1)[..., 0]
        axis /= np.linalg.norm(axis, axis=-1, keepdims=True)
        sgn = np.sign(np.sum(axis * v[near_pi], axis=-1))
        sgn = np.where(sgn == 0, 1.0, sgn)
        out[near_pi] = axis * (sgn * th)[:, None]
    return out


def so3_left_jacobian(phi) -> np.ndarray:
    """Left Jacobian ``V(phi)`` of SO(3) (the SE(3) translation map).

    Parameters
    ----------
    phi : ndarray of shape (..., 3)

    Returns
    -------
    ndarray of shape (..., 3, 3)
        ``V(phi)``, with ``exp([rho, phi]) = [[exp(phi), V(phi) rho], [0, 1]]``.

    Examples
    --------
    >>> phi = np.array([0.3, -0.2, 0.5])
    >>> bool(np.allclose(so3_left_jacobian(phi) @ so3_left_jacobian_inverse(phi), np.eye(3)))
    True
    """
    phi = check_array(phi, "phi", shape=(Ellipsis, 3))
    _, b, c = _coefficients(np.linalg.norm(phi, axis=-1))
    K = so3_hat(phi)
    return np.eye(3) + b[..., None, None] * K + c[..., None, None] * (K @ K)


def so3_left_jacobian_inverse(phi) -> np.ndarray:
    """Inverse of :func:`so3_left_jacobian` in closed form.

    ``V^-1 = I - K/2 + (1 - theta sin(theta) / (2 (1 - cos(theta)))) / theta^2 K^2``,
    with the series ``1/12 + theta^2/720 + ...`` below 0.01; defined for ``theta < 2 pi``
    (logarithms have ``theta <= pi``).

    Parameters
    ----------
    phi : ndarray of shape (..., 3)

    Returns
    -------
    ndarray of shape (..., 3, 3)

    Examples
    --------
    >>> (so3_left_jacobian_inverse(np.zeros(3)) + 0.0).tolist()
    [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    """
    phi = check_array(phi, "phi", shape=(Ellipsis, 3))
    theta = np.linalg.norm(phi, axis=-1)
    a, b, _ = _coefficients(theta)
    series = theta < _SERIES  # the closed form cancels catastrophically near 0
    ts = np.where(series, 1.0, theta)
    t2 = theta**2
    d = np.where(series, 1 / 12 + t2 / 720 + t2**2 / 30240 + t2**3 / 1209600,
                 (1 - a / (2 * np.where(series, 1.0, b))) / ts**2)
    K = so3_hat(phi)
    return np.eye(3) - 0.5 * K + d[..., None, None] * (K @ K)
