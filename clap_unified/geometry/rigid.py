"""Rigid motions from point correspondences: one weighted Kabsch for the plane and space.

The closed-form least-squares alignment of Kabsch, Arun et al. and Umeyama
(without scale): for centred point sets the cross-covariance ``H = sum_k w_k
(p_k - p_bar) (q_k - q_bar)^T`` gives the rotation ``R`` maximising
``trace(R H)``, and ``t = q_bar - R p_bar``. Convention: ``q = R p + t``; a
pose ``T_world_body`` maps body points ``p`` to world points ``q``.

The rotation from ``H``:

* ``d = 3``: ``H = U S V^T``, ``R = V diag(1, 1, s) U^T`` with ``s =
  sign(det(V U^T))``, the *reflection fix*: without it a (nearly) planar or
  noisy set can come out mirrored, ``det R = -1``;
* ``d = 2``: the same optimum in closed form, ``theta = atan2(H_01 - H_10,
  H_00 + H_11)`` (``trace(R(theta) H)`` is ``a cos(theta) + b sin(theta)``
  with those ``a``, ``b``); no SVD, and ``R`` is exactly ``[[cos, -sin], [sin,
  cos]]`` of that angle, the form
  :meth:`~clap_unified.geometry.se2.SE2.from_xytheta` builds.

One arithmetic detail differs by dimension, on purpose: in space the centroids
and ``H`` are ``einsum`` sums under the normalised weights (batched over
thousands of triplets), in the plane they are matrix products under the
weights as given, divided by their sum. Writing the plane in the space's form
moves the 2D poses in their last bits, and with them the stored outputs of the
``localization2d`` experiment of ``clap-unified reproduce``; the library keeps
every experiment's output bit for bit, so each dimension keeps the order of
operations it had (``tests/test_geometry_rigid.py`` holds both to the SVD
solution).

The hypothesis spaces of 2D landmarks
(:class:`~clap_unified.spaces.landmarks2d.Landmark2DSpace`), 3D landmarks and 3D
correspondences all solve and refit with :func:`weighted_kabsch` (what :func:`kabsch`
runs after its checks), and move data by poses with :func:`transform_points`.
"""

from __future__ import annotations

import numpy as np

from .._validation import check_array

__all__ = ["kabsch", "pose_from_rt", "transform_points", "weighted_kabsch"]


def kabsch(source, target, weights=None):
    """Least-squares rotations and translations ``target ~ R source + t``, batched, d = 2 or 3.

    Parameters
    ----------
    source, target : ndarray of shape (..., K, d), d = 2 or 3
        Corresponding points, ``K >= d`` (fewer do not fix a rotation in space;
        in the plane two points do).
    weights : ndarray of shape (..., K), optional
        Non-negative weights (default: equal).

    Returns
    -------
    R : ndarray of shape (..., d, d)
        Proper rotations (``det R = +1``, reflection fixed).
    t : ndarray of shape (..., d)

    Examples
    --------
    >>> from clap_unified.geometry import so3_exp
    >>> R0 = so3_exp([0.1, -0.2, 0.3])
    >>> p = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 3.0]])
    >>> R, t = kabsch(p, p @ R0.T + [1.0, 2.0, 3.0])
    >>> bool(np.allclose(R, R0)), t.round(6).tolist()
    (True, [1.0, 2.0, 3.0])

    In the plane:

    >>> c, s = np.cos(0.5), np.sin(0.5)
    >>> R, t = kabsch(p[:3, :2], p[:3, :2] @ np.array([[c, -s], [s, c]]).T + [1.0, -1.0])
    >>> round(float(np.arctan2(R[1, 0], R[0, 0])), 6), t.round(6).tolist()
    (0.5, [1.0, -1.0])
    """
    P = check_array(source, "source", shape=(Ellipsis, None, None))
    Q = check_array(target, "target", shape=(Ellipsis, None, None))
    if P.shape[-1] not in (2, 3):
        raise ValueError(f"source: expected points of dimension 2 or 3, got {P.shape[-1]}")
    if P.shape != Q.shape:
        raise ValueError(f"target: expected the shape of source {P.shape}, got {Q.shape}")
    d = P.shape[-1]
    if P.shape[-2] < d:
        raise ValueError(f"source: need at least {d} points per set, got {P.shape[-2]}")
    if weights is None:
        w = np.ones(P.shape[:-1])
    else:
        w = check_array(weights, "weights", shape=P.shape[:-1])
        if np.any(w < 0) or np.any(w.sum(axis=-1) <= 0):
            raise ValueError("weights: expected non-negative weights with a positive sum")
    R, t, _ = weighted_kabsch(P, Q, w)
    return R, t


def weighted_kabsch(P, Q, w):
    """:func:`kabsch` on checked arrays (no validation), with the cross-covariance.

    Parameters
    ----------
    P, Q : ndarray of shape (..., K, d), d = 2 or 3
    w : ndarray of shape (..., K)
        Non-negative weights with a positive sum over ``K`` (normalised here).

    Returns
    -------
    R : ndarray of shape (..., d, d)
    t : ndarray of shape (..., d)
    H : ndarray of shape (..., d, d)
        The cross-covariance of the centred sets under the weights as given
        (not normalised), for the callers' degeneracy tests: in the plane
        all zeros when the rotation is undetermined; in space collinear
        points leave a rank-1 ``H``, not a zero one (the 3D callers test the
        points' spread instead). With a zero weight sum everything is NaN.

    Examples
    --------
    >>> P = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    >>> R, t, H = weighted_kabsch(P, P + [2.0, 3.0], np.ones(3))
    >>> R.round(12).tolist(), t.round(12).tolist()
    ([[1.0, -0.0], [0.0, 1.0]], [2.0, 3.0])
    """
    if P.shape[-1] == 2:
        if P.ndim == 2:
            return _planar(P, Q, w)
        batch, k = P.shape[:-2], P.shape[-2]
        R, t, H = np.empty((*batch, 2, 2)), np.empty((*batch, 2)), np.empty((*batch, 2, 2))
        for i in np.ndindex(batch):  # one closed form per set (the plane's sets are few)
            R[i], t[i], H[i] = _planar(P[i].reshape(k, 2), Q[i].reshape(k, 2), w[i])
        return R, t, H
    total = w.sum(axis=-1, keepdims=True)
    w = w / total
    cp = np.einsum("...k,...ki->...i", w, P)
    cq = np.einsum("...k,...ki->...i", w, Q)
    H = np.einsum("...k,...ki,...kj->...ij", w, P - cp[..., None, :], Q - cq[..., None, :])
    U, _, Vt = np.linalg.svd(H)
    V = np.swapaxes(Vt, -1, -2)
    sign = np.sign(np.linalg.det(V @ np.swapaxes(U, -1, -2)))
    sign = np.where(sign == 0, 1.0, sign)
    V[..., :, -1] *= sign[..., None]
    R = V @ np.swapaxes(U, -1, -2)
    return R, _translation(R, cp, cq), H * total[..., None]


def _planar(P, Q, w):
    """:func:`weighted_kabsch` of one planar set ``(K, 2)``: the closed-form angle."""
    total = w.sum()
    cp, cq = (w @ P) / total, (w @ Q) / total
    H = ((P - cp).T * w) @ (Q - cq)
    theta = np.arctan2(H[0, 1] - H[1, 0], H[0, 0] + H[1, 1])
    c, s = np.cos(theta), np.sin(theta)
    R = np.array([[c, -s], [s, c]])
    return R, _translation(R, cp, cq), H


def _translation(R, cp, cq):
    """``t = q_bar - R p_bar``, batched."""
    return cq - np.einsum("...ij,...j->...i", R, cp)


def pose_from_rt(R, t) -> np.ndarray:
    """Homogeneous ``(d + 1) x (d + 1)`` poses from rotations ``(..., d, d)`` and translations.

    Examples
    --------
    >>> pose_from_rt(np.eye(2), [1.0, 2.0]).tolist()
    [[1.0, 0.0, 1.0], [0.0, 1.0, 2.0], [0.0, 0.0, 1.0]]
    """
    R, t = np.asarray(R, dtype=float), np.asarray(t, dtype=float)
    d = R.shape[-1]
    T = np.zeros((*R.shape[:-2], d + 1, d + 1))
    T[..., :d, :d] = R
    T[..., :d, d] = t
    T[..., d, d] = 1.0
    return T


def transform_points(poses, points) -> np.ndarray:
    """Points ``(N, d)`` moved by each of ``H`` poses ``(H, d + 1, d + 1)``: ``(H, N, d)``.

    Examples
    --------
    >>> T = pose_from_rt(np.eye(2), [1.0, 2.0])
    >>> transform_points(T, np.array([[0.0, 0.0], [1.0, 1.0]])).tolist()
    [[[1.0, 2.0], [2.0, 3.0]]]
    """
    points = np.asarray(points, dtype=float)
    d = points.shape[-1]
    T = np.asarray(poses, dtype=float).reshape(-1, d + 1, d + 1)
    return np.einsum("hij,nj->hni", T[:, :d, :d], points) + T[:, None, :d, d]
