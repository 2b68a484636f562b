"""Compiled kernels of homography estimation (numba), tested against the numpy path.

The reweighted DLT of :func:`~clap_unified.spaces.homography_polish.polish_checked`
runs a handful of small solves on a few hundred matches; in numpy each one
costs tens of calls whose overhead is most of its time. The kernels here do
the same arithmetic in one compiled loop:

* :func:`symmetric_transfer_error` -- the symmetric transfer error of one
  homography on every match, as
  :func:`~clap_unified.geometry.homography_arithmetic.symmetric_transfer_error`;
* :func:`weighted_dlt` -- the Hartley-normalised weighted DLT of a subset of
  the matches, as :func:`~clap_unified.geometry.homography_arithmetic.dlt`;
* :func:`irls` -- the reweighted DLT loop of the polish, with the same
  stopping rules;
* :func:`four_point_solve` -- the closed-form 4-point solutions of thousands
  of minimal samples and their degeneracy tests, as
  ``HomographySpace.solve_minimal`` in
  numpy (CLAP draws up to 10000 candidates on a hard pair);
* :func:`take_new_samples` -- the samples of a batch never drawn before, in
  a hash table, as the Python set of progressive sampling
  (:meth:`~clap_unified.spaces.homography.HomographySpace.hypotheses` with
  ``quality``).

The numpy functions stay the reference: ``tests/test_homography_compiled.py``
checks that both paths agree. ``clap_unified._compiled.AVAILABLE`` is the
one switch: False (or numba not importable) runs the numpy path. The first
call compiles (about a second per kernel); the machine code is cached beside
this file.
"""

from __future__ import annotations

import numpy as np

from .._compiled import jit as _jit

__all__ = ["four_point_solve", "irls", "symmetric_transfer_error", "take_new_samples",
           "weighted_dlt"]


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
    vector of the weighted ``A``, as :func:`~clap_unified.geometry.homography_arithmetic.dlt`.
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
def scale_h33(H):
    """``scale_homography`` of one ``3 x 3`` matrix: ``H33 = 1``, or (``|H33|`` at or below
    ``1e-12 max |H_ij|``) unit Frobenius norm with the first largest entry positive."""
    top = 0.0
    fro = 0.0
    for a in range(3):
        for b in range(3):
            fro += H[a, b] * H[a, b]
            if abs(H[a, b]) > abs(top):
                top = H[a, b]
    d = H[2, 2]
    if not abs(d) > 1e-12 * abs(top):
        d = np.sqrt(fro) if top > 0 else -np.sqrt(fro)
    return H / d


@_jit
def irls(H, m, t, iterations):
    """The reweighted DLT loop of the polish: ``(H, r, inliers)`` after at most ``iterations``.

    ``H`` is scaled as ``scale_homography`` scales it; ``t`` is the polish threshold. Each round
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
        cand = scale_h33(weighted_dlt(x, wt * wt))
        if not np.all(np.isfinite(cand)):
            break
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


@_jit
def four_point_solve(q, idx, s1, s2, c1x, c1y, c2x, c2y, singular_ratio, frame_test):
    """Closed-form 4-point homographies of the samples ``idx``, the usable ones only.

    The arithmetic of ``clap_unified.spaces.homography._four_point``
    and of the tests of
    ``HomographySpace.solve_minimal``,
    sample by sample, in the same order of operations (the results are the
    numpy path's, bit for bit, in the tests).

    Parameters
    ----------
    q : ndarray of shape (2, N, 2)
        Source and destination points, centred (not yet scaled).
    idx : ndarray of shape (S, 4)
        The samples.
    s1, s2, c1x, c1y, c2x, c2y : float
        Hartley scales and centroids of the source and destination points.
    singular_ratio : float
        ``SINGULAR_RATIO`` of the near-singularity test.
    frame_test : bool
        Test singularity in the Hartley frame (``T2 H T1^-1``), else in pixels.

    Returns
    -------
    H : ndarray of shape (M, 3, 3)
        The usable homographies, ``H33 = 1`` (or, when ``H33`` is zero,
        ``scale_homography``'s fallback): no three points of the sample
        (nearly) collinear on either side, not near-singular.
    owner : ndarray of shape (M,)
        The sample of each, increasing.
    """
    n_s = idx.shape[0]
    # the collinearity tolerances come from the largest coordinate of the batch
    big1 = 0.0
    big2 = 0.0
    for t in range(n_s):
        for a in range(4):
            j = idx[t, a]
            big1 = max(big1, abs(q[0, j, 0] * s1), abs(q[0, j, 1] * s1))
            big2 = max(big2, abs(q[1, j, 0] * s2), abs(q[1, j, 1] * s2))
    tol_src = 1e-9 * max(big1, 1.0) ** 2
    tol_dst = 1e-9 * max(big2, 1.0) ** 2
    H = np.empty((n_s, 3, 3))
    owner = np.empty(n_s, dtype=np.intp)
    x = np.empty(4)
    y = np.empty(4)
    u = np.empty(4)
    v = np.empty(4)
    r = np.empty((3, 3))
    rd = np.empty((3, 3))
    lam = np.empty(3)
    mu = np.empty(3)
    c = np.empty(3)
    uo = np.empty(3)
    vo = np.empty(3)
    G = np.empty((3, 3))
    m = 0
    for t in range(n_s):
        for a in range(4):
            j = idx[t, a]
            x[a] = q[0, j, 0] * s1
            y[a] = q[0, j, 1] * s1
            u[a] = q[1, j, 0] * s2
            v[a] = q[1, j, 1] * s2
        good = True
        for i in range(3):
            ia, ib = (i + 1) % 3, (i + 2) % 3
            r[i, 0] = y[ia] - y[ib]
            r[i, 1] = x[ib] - x[ia]
            r[i, 2] = x[ia] * y[ib] - x[ib] * y[ia]
            lam[i] = r[i, 0] * x[3] + r[i, 1] * y[3] + r[i, 2]
            rd[i, 0] = v[ia] - v[ib]
            rd[i, 1] = u[ib] - u[ia]
            rd[i, 2] = u[ia] * v[ib] - u[ib] * v[ia]
            mu[i] = rd[i, 0] * u[3] + rd[i, 1] * v[3] + rd[i, 2]
            if abs(lam[i]) <= tol_src or abs(mu[i]) <= tol_dst:
                good = False
        d123 = r[0, 0] * x[0] + r[0, 1] * y[0] + r[0, 2]
        e123 = rd[0, 0] * u[0] + rd[0, 1] * v[0] + rd[0, 2]
        if not good or abs(d123) <= tol_src or abs(e123) <= tol_dst:
            continue
        for i in range(3):
            r[i, 2] = r[i, 2] / s1 - c1x * r[i, 0] - c1y * r[i, 1]  # r_i^T T1 / s1
            c[i] = mu[i] * (lam[(i + 1) % 3] * lam[(i + 2) % 3])
            uo[i] = u[i] / s2 + c2x  # T2^-1 q_i
            vo[i] = v[i] / s2 + c2y
        big = 0.0
        for b in range(3):  # H = sum_i (uo_i, vo_i, 1) c_i r_i^T, summed in the order of i
            cr = c[0] * r[0, b]
            h0, h1, h2 = uo[0] * cr, vo[0] * cr, cr
            for i in range(1, 3):
                cr = c[i] * r[i, b]
                h0 += uo[i] * cr
                h1 += vo[i] * cr
                h2 += cr
            H[m, 0, b] = h0
            H[m, 1, b] = h1
            H[m, 2, b] = h2
            big = max(big, abs(h0), abs(h1), abs(h2))
        h33 = H[m, 2, 2]
        if not abs(h33) > 1e-12 * big:
            # H33 = 0 (the origin maps to infinity): scale_homography's fallback, unit
            # Frobenius norm with the first largest entry positive
            top = 0.0
            fro = 0.0
            for a in range(3):
                for b in range(3):
                    fro += H[m, a, b] * H[m, a, b]
                    if abs(H[m, a, b]) > abs(top):
                        top = H[m, a, b]
            h33 = np.sqrt(fro) if top > 0 else -np.sqrt(fro)
            if not (abs(h33) > 0.0 and abs(h33) < np.inf):
                continue
        for a in range(3):
            for b in range(3):
                H[m, a, b] = H[m, a, b] / h33
        if frame_test:
            for a in range(3):  # K = s1 H T1^-1
                G[a, 0] = H[m, a, 0]
                G[a, 1] = H[m, a, 1]
                G[a, 2] = H[m, a, 0] * (c1x * s1) + H[m, a, 1] * (c1y * s1) + H[m, a, 2] * s1
            for b in range(3):  # G = T2 K / s2 (rows 0 and 1 use K's third row first)
                G[0, b] = G[0, b] - c2x * G[2, b]
                G[1, b] = G[1, b] - c2y * G[2, b]
                G[2, b] = G[2, b] / s2
        else:
            for a in range(3):
                for b in range(3):
                    G[a, b] = H[m, a, b]
        det = (G[0, 0] * (G[1, 1] * G[2, 2] - G[1, 2] * G[2, 1])
               - G[0, 1] * (G[1, 0] * G[2, 2] - G[1, 2] * G[2, 0])
               + G[0, 2] * (G[1, 0] * G[2, 1] - G[1, 1] * G[2, 0]))
        rows = (G[0, 0] * G[0, 0] + G[0, 1] * G[0, 1] + G[0, 2] * G[0, 2]) * (
            G[1, 0] * G[1, 0] + G[1, 1] * G[1, 1] + G[1, 2] * G[1, 2]) * (
            G[2, 0] * G[2, 0] + G[2, 1] * G[2, 1] + G[2, 2] * G[2, 2])
        if det * det > singular_ratio ** 2 * rows:
            owner[m] = t
            m += 1
    return H[:m].copy(), owner[:m].copy()


@_jit
def take_new_samples(rows, n, table, used, want):
    """The rows of ``rows`` not taken before, in order, until ``want`` are taken in all.

    ``rows`` ``(B, 4)`` are samples of sorted match indices below ``n``;
    ``table`` ``(T, 2)`` and ``used`` ``(T,)`` are the open-addressing hash
    table of the samples taken so far (``T`` a power of two, more than twice
    the samples that will ever be taken), updated in place.

    Returns the indices of the rows taken: a row is taken when no equal row
    was taken before (in this batch or an earlier one) and fewer than
    ``want`` rows of this batch were taken.
    """
    mask = table.shape[0] - 1
    out = np.empty(rows.shape[0], dtype=np.intp)
    m = 0
    for j in range(rows.shape[0]):
        if m >= want:
            break
        hi = rows[j, 0] * n + rows[j, 1]
        lo = rows[j, 2] * n + rows[j, 3]
        h = (hi * 1000003 + lo) & mask
        while True:
            if not used[h]:
                used[h] = True
                table[h, 0] = hi
                table[h, 1] = lo
                out[m] = j
                m += 1
                break
            if table[h, 0] == hi and table[h, 1] == lo:
                break
            h = (h + 1) & mask
    return out[:m].copy()
