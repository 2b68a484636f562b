"""Compiled kernels of the homography polish (numba), tested against the numpy path.

The reweighted DLT of :func:`~clap_unified.spaces.homography_polish.polish_checked`
runs a handful of small solves on a few hundred matches; in numpy each one
costs tens of calls whose overhead is most of its time. The kernels here do
the same arithmetic in one compiled loop:

* :func:`symmetric_transfer_error` -- the symmetric transfer error of one
  homography on every match, as
  :func:`~clap_unified.spaces.homography.symmetric_transfer_error`;
* :func:`weighted_dlt` -- the Hartley-normalised weighted DLT of a subset of
  the matches, as :func:`~clap_unified.spaces.homography.dlt`;
* :func:`irls` -- the reweighted DLT loop of the polish, with the same
  stopping rules.

The numpy functions stay the reference: ``tests/test_homography_compiled.py``
checks that both paths agree, and :data:`AVAILABLE` is False (the polish then
runs in numpy) where numba cannot be imported. The first call compiles (about
a second per kernel); the machine code is cached beside this file.
"""

from __future__ import annotations

import numpy as np

try:
    from numba import njit
except ImportError:  # pragma: no cover - numba is a dependency; the numpy path remains
    njit = None

__all__ = ["AVAILABLE", "irls", "symmetric_transfer_error", "weighted_dlt"]

#: True when numba is importable and the compiled polish is used.
AVAILABLE = njit is not None


def _jit(fn):
    return njit(cache=True, nogil=True, error_model="numpy")(fn) if AVAILABLE else fn


@_jit
def symmetric_transfer_error(H, m):
    """Symmetric transfer error of ``H`` ``(3, 3)`` on the matches ``m`` ``(N, 4)``.

    ``inf`` where a point goes to infinity, everywhere when ``H`` is singular.
    """
    a, b, c = H[0, 0], H[0, 1], H[0, 2]
    d, e, f = H[1, 0], H[1, 1], H[1, 2]
    g, h, i = H[2, 0], H[2, 1], H[2, 2]
    j00, j01, j02 = e * i - f * h, c * h - b * i, b * f - c * e
    j10, j11, j12 = f * g - d * i, a * i - c * g, c * d - a * f
    j20, j21, j22 = d * h - e * g, b * g - a * h, a * e - b * d
    n = m.shape[0]
    out = np.empty(n)
    if a * j00 + b * j10 + c * j20 == 0.0:
        out[:] = np.inf
        return out
    for k in range(n):
        x1, y1, x2, y2 = m[k, 0], m[k, 1], m[k, 2], m[k, 3]
        pz = g * x1 + h * y1 + i
        px = (a * x1 + b * y1 + c) / pz - x2
        py = (d * x1 + e * y1 + f) / pz - y2
        qz = j20 * x2 + j21 * y2 + j22
        qx = (j00 * x2 + j01 * y2 + j02) / qz - x1
        qy = (j10 * x2 + j11 * y2 + j12) / qz - y1
        r = np.sqrt(0.5 * ((px * px + py * py) + (qx * qx + qy * qy)))
        out[k] = r if np.isfinite(r) else np.inf
    return out


@_jit
def _centre_scale(p, w):
    """Weighted centroid and Hartley scale of the points ``p`` ``(N, 2)``."""
    wsum = w.sum()
    cx = (w * p[:, 0]).sum() / wsum
    cy = (w * p[:, 1]).sum() / wsum
    mean_d = (w * np.sqrt((p[:, 0] - cx) ** 2 + (p[:, 1] - cy) ** 2)).sum() / wsum
    s = np.sqrt(2.0) / (mean_d if mean_d > 0 else 1.0)
    return cx, cy, s


@_jit
def weighted_dlt(m, w):
    """Weighted normalised DLT of the matches ``m`` ``(N, 4)``, ``N >= 4``: ``H`` with unit norm.

    ``w`` are the weights ``(N,)``. From 8 matches on, the eigenvector of
    the smallest eigenvalue of ``A^T A``; below, the last right singular
    vector of the weighted ``A``, as :func:`~clap_unified.spaces.homography.dlt`.
    """
    n = m.shape[0]
    csx, csy, ss = _centre_scale(m[:, :2], w)
    cdx, cdy, sd = _centre_scale(m[:, 2:], w)
    x = (m[:, 0] - csx) * ss
    y = (m[:, 1] - csy) * ss
    u = (m[:, 2] - cdx) * sd
    v = (m[:, 3] - cdy) * sd
    if n < 8:
        A = np.zeros((max(2 * n, 9), 9))
        for k in range(n):
            sw = np.sqrt(w[k])
            r1 = np.array([-x[k], -y[k], -1.0, 0.0, 0.0, 0.0, u[k] * x[k], u[k] * y[k], u[k]])
            r2 = np.array([0.0, 0.0, 0.0, -x[k], -y[k], -1.0, v[k] * x[k], v[k] * y[k], v[k]])
            A[2 * k] = sw * r1
            A[2 * k + 1] = sw * r2
        _, _, vt = np.linalg.svd(A)
        hn = vt[-1].copy()
    else:
        ata = np.zeros((9, 9))
        for k in range(n):
            p = np.array([x[k], y[k], 1.0])
            wk, uk, vk = w[k], u[k], v[k]
            for r in range(3):
                for c in range(3):
                    pp = wk * p[r] * p[c]
                    ata[r, c] += pp
                    ata[3 + r, 3 + c] += pp
                    ata[r, 6 + c] -= uk * pp
                    ata[6 + r, c] -= uk * pp
                    ata[3 + r, 6 + c] -= vk * pp
                    ata[6 + r, 3 + c] -= vk * pp
                    ata[6 + r, 6 + c] += (uk * uk + vk * vk) * pp
        _, vecs = np.linalg.eigh(ata)
        hn = vecs[:, 0].copy()
    Hn = hn.reshape(3, 3)
    left = np.array([[1.0, 0.0, sd * cdx], [0.0, 1.0, sd * cdy], [0.0, 0.0, sd]])
    right = np.array([[1.0, 0.0, -csx], [0.0, 1.0, -csy], [0.0, 0.0, 1.0 / ss]])
    G = left @ Hn @ right
    return G / np.sqrt((G * G).sum())


@_jit
def irls(H, m, t, iterations):
    """The reweighted DLT loop of the polish: ``(H, r, inliers)`` after at most ``iterations``.

    ``H`` has ``H[2, 2] = 1``; ``t`` is the polish threshold. Each round
    refits on the inliers with Tukey weights ``(1 - (r / t)^2)^2`` and stops
    on a degenerate or non-finite solve, when the inliers fall below
    ``max(4, n / 2)``, or once the inliers repeat and their residuals move by
    at most 1e-9 (the rules of the numpy loop).
    """
    r = symmetric_transfer_error(H, m)
    inl = r < t
    n_inl = inl.sum()
    if n_inl < 4:
        return H, r, inl
    for _ in range(iterations):
        x = m[inl]
        wt = 1.0 - (r[inl] / t) ** 2
        cand = weighted_dlt(x, wt * wt)
        if not np.all(np.isfinite(cand)) or abs(cand[2, 2]) < 1e-12:
            break
        cand = cand / cand[2, 2]
        r_new = symmetric_transfer_error(cand, m)
        inl_new = r_new < t
        n_new = inl_new.sum()
        if n_new < max(4, n_inl // 2):
            break
        done = n_new == n_inl and np.array_equal(inl_new, inl)
        if done:
            done = np.max(np.abs(r_new[inl] - r[inl])) <= 1e-9
        H, r, inl, n_inl = cand, r_new, inl_new, n_new
        if done:
            break
    return H, r, inl
