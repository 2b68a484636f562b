"""The arithmetic of planar homographies, on the geometry floor: every module's one copy.

Convention: ``x2 ~ H x1`` for correspondences ``(x1, y1, x2, y2)``.

* :func:`normalise_points`: Hartley normalisation;
* :func:`dlt`: the (weighted) normalised direct linear transform, from the
  9 x 9 normal equations;
* :func:`four_point_homography`: the closed-form 4-point minimal solver in
  the Hartley frame of the data, batched with cofactors (no per-sample solve
  or inverse);
* :func:`transfer`, :func:`transfer_error`, :func:`symmetric_transfer_error`:
  points mapped by ``H``, the forward transfer error of many homographies,
  and the symmetric transfer error (the paper's SRE).

:class:`~clap_unified.spaces.HomographySpace` (its minimal solver and
refits), the polish, the fundamental-matrix arithmetic and the imaging
metrics use them from here.
"""

from __future__ import annotations

import numpy as np

__all__ = ["H33_ZERO", "SINGULAR_RATIO", "dlt", "four_point_homography", "normalise_points",
           "scale_homography", "symmetric_transfer_error", "transfer", "transfer_error"]


#: Minimal-sample homographies with ``|det H| / prod_i |row_i|`` at or below this are rejected.
SINGULAR_RATIO = 1e-10

#: ``|H[2, 2]|`` at or below this fraction of ``max |H_ij|`` counts as zero (the image
#: origin maps to infinity): such a homography is scaled by :func:`scale_homography`'s
#: fallback instead of ``H[2, 2] = 1``.
H33_ZERO = 1e-12


def scale_homography(H) -> np.ndarray:
    """The representative of homographies ``(..., 3, 3)`` the library reports.

    ``H / H[2, 2]`` (``H33 = 1``, the usual convention) unless ``|H[2, 2]|`` is
    at or below :data:`H33_ZERO` times the largest ``|H_ij|``; then (the
    homography sends the image origin to infinity, a valid homography that has
    no ``H33 = 1`` form) unit Frobenius norm, the largest entry (the first in
    row-major order) positive. Non-finite or all-zero matrices give non-finite
    entries (callers reject them).

    Examples
    --------
    >>> scale_homography(np.diag([2.0, 2.0, 4.0])).diagonal().tolist()
    [0.5, 0.5, 1.0]
    >>> H = scale_homography([[0.0, -2.0, 0.0], [0.0, 0.0, 2.0], [2.0, 0.0, 0.0]])
    >>> H.tolist()[0], H[2, 2]  # H33 = 0: unit norm, the first largest entry positive
    ([-0.0, 0.5773502691896258, -0.0], np.float64(0.0))
    """
    H = np.asarray(H, dtype=float)
    with np.errstate(all="ignore"):
        flat = H.reshape(*H.shape[:-2], 9)
        k = np.argmax(np.abs(flat), axis=-1)
        top = np.take_along_axis(flat, k[..., None], axis=-1)[..., 0]
        fro = flat[..., 0] * flat[..., 0]
        for i in range(1, 9):  # summed in row-major order, as the compiled solver sums
            fro = fro + flat[..., i] * flat[..., i]
        fallback = np.where(top > 0, np.sqrt(fro), -np.sqrt(fro))
        h33 = H[..., 2, 2]
        d = np.where(np.abs(h33) > H33_ZERO * np.abs(top), h33, fallback)
        return H / d[..., None, None]


def normalise_points(points, weights=None):
    """Hartley normalisation of point sets, batched.

    Parameters
    ----------
    points : ndarray of shape (..., N, 2)
    weights : ndarray of shape (..., N), optional

    Returns
    -------
    normalised : ndarray of shape (..., N, 2)
        Centroid at the origin, mean distance sqrt(2).
    T : ndarray of shape (..., 3, 3)
        The similarity with ``normalised = T @ points`` (homogeneous).
    """
    q, centre, s = _centre_scale(np.asarray(points, dtype=float), weights)
    q *= s[..., None, None]
    return q, _similarity(centre, s)


def _similarity(centre, s) -> np.ndarray:
    """``[[s, 0, -s cx], [0, s, -s cy], [0, 0, 1]]``, batched over ``s`` ``(...)``."""
    T = np.zeros((*np.shape(s), 3, 3))
    T[..., 0, 0] = T[..., 1, 1] = s
    T[..., 0, 2] = -s * centre[..., 0]
    T[..., 1, 2] = -s * centre[..., 1]
    T[..., 2, 2] = 1.0
    return T


def _centre_scale(p, weights=None):
    """Centred points, centroid and Hartley scale of ``p`` ``(..., N, 2)``.

    Sums are products with the weights (BLAS) rather than reductions over
    the short last axes, which cost more in numpy than the arithmetic.
    """
    if weights is None:
        n = p.shape[-2]
        w, wsum = np.full(n, 1.0 / max(n, 1)), 1.0
    else:
        w = np.asarray(weights, dtype=float)
        wsum = w.sum(axis=-1)
    centre = (w[..., None, :] @ p)[..., 0, :]
    if weights is not None:
        centre /= wsum[..., None]
    q = p - centre[..., None, :]
    mean_d = (w[..., None, :] @ np.sqrt(q[..., 0] * q[..., 0] + q[..., 1] * q[..., 1])[..., None]
              )[..., 0, 0] / wsum
    s = np.sqrt(2.0) / np.where(mean_d > 0, mean_d, 1.0)
    return q, centre, s


def dlt(src, dst, weights=None) -> np.ndarray:
    """Normalised direct linear transform, batched: ``dst ~ H src``.

    After Hartley normalisation of both point sets, ``H`` is the eigenvector
    of the smallest eigenvalue of the 9 x 9 matrix ``A^T A`` (built from
    weighted moments of the points, never forming the ``2N x 9`` ``A``), as
    in OpenCV; fewer than 8 correspondences take the SVD of ``A``.

    Parameters
    ----------
    src, dst : ndarray of shape (..., N, 2), N >= 4
    weights : ndarray of shape (..., N), optional

    Returns
    -------
    ndarray of shape (..., 3, 3)
        Homographies scaled to unit Frobenius norm (not yet ``H33 = 1``).

    Examples
    --------
    >>> H = np.array([[1.0, 0.2, 3.0], [0.1, 0.9, -2.0], [1e-3, 2e-3, 1.0]])
    >>> src = np.array([[0.0, 0.0], [100.0, 0.0], [100.0, 80.0], [0.0, 80.0], [50.0, 30.0]])
    >>> h = np.c_[src, np.ones(5)] @ H.T
    >>> est = dlt(src, h[:, :2] / h[:, 2:])
    >>> np.allclose(est / est[2, 2], H)
    True
    """
    return _dlt(np.stack([np.asarray(src, dtype=float), np.asarray(dst, dtype=float)]), weights)


def _dlt(points, weights=None) -> np.ndarray:
    """:func:`dlt` of ``points = [src, dst]`` ``(2, ..., N, 2)``, both normalised in one pass."""
    q, centre, s = _centre_scale(points, weights)
    q *= s[..., None, None]
    x, y, u, v = q[0, ..., 0], q[0, ..., 1], q[1, ..., 0], q[1, ..., 1]
    if x.shape[-1] < _NORMAL_EQUATIONS_MIN:
        one, zero = np.ones_like(x), np.zeros_like(x)
        r1 = np.stack([-x, -y, -one, zero, zero, zero, u * x, u * y, u], axis=-1)
        r2 = np.stack([zero, zero, zero, -x, -y, -one, v * x, v * y, v], axis=-1)
        A = np.concatenate([r1, r2], axis=-2)  # (..., 2N, 9)
        if weights is not None:
            sw = np.sqrt(np.asarray(weights, dtype=float))
            A = A * np.concatenate([sw, sw], axis=-1)[..., None]
        # the null vector is the last right singular vector (of the full V when
        # there are fewer than 9 rows)
        _, _, vt = np.linalg.svd(A, full_matrices=A.shape[-2] < 9)
        Hn = vt[..., -1, :]
    else:
        # A^T A from four weighted moments of the monomials of p p^T, p = (x, y, 1):
        # one (4, N) @ (N, 6) product instead of the (2N, 9) matrix and its SVD
        w = np.ones_like(x) if weights is None else np.asarray(weights, dtype=float)
        mono = np.stack([x * x, x * y, x, y * y, y, np.ones_like(x)], axis=-1)
        wm = np.stack([w, w * u, w * v, w * (u * u + v * v)], axis=-2)
        m = (wm @ mono).reshape(*x.shape[:-1], 24)
        _, V = np.linalg.eigh(m[..., _NORMAL_INDEX] * _NORMAL_SIGN)
        Hn = V[..., :, 0]  # eigenvector of the smallest eigenvalue
    # back to pixels: T_dst^-1 Hn T_src
    Hn = Hn.reshape(*x.shape[:-1], 3, 3)
    if Hn.ndim == 2:  # one problem: the frames from floats cost less than array arithmetic
        (csx, csy), (cdx, cdy) = centre.tolist()
        ss, sd = s.tolist()
        G = (np.array([[1.0, 0.0, sd * cdx], [0.0, 1.0, sd * cdy], [0.0, 0.0, sd]]) @ Hn
             @ np.array([[1.0, 0.0, -csx], [0.0, 1.0, -csy], [0.0, 0.0, 1.0 / ss]]))
    else:
        G = _similarity_inverse(_similarity(centre[1], s[1])) @ Hn @ _similarity(centre[0], s[0])
    return G / np.sqrt(np.sum(G * G, axis=(-2, -1), keepdims=True))


def _normal_tables():
    """Gather table and signs building the 9 x 9 ``A^T A`` of the DLT from its moments.

    With ``r1 = (-p, 0, u p)`` and ``r2 = (0, -p, v p)`` the rows of a match,
    ``A^T A`` has 3 x 3 blocks ``[[P, 0, -Pu], [0, P, -Pv], [-Pu, -Pv, Puuvv]]``
    (``P = sum w p p^T``, ``Pu = sum w u p p^T``, ...), each symmetric and
    stored as the 6 moments of ``xx, xy, x, yy, y, 1``.
    """
    sym = np.array([[0, 1, 2], [1, 3, 4], [2, 4, 5]])
    moment = [[0, None, 1], [None, 0, 2], [1, 2, 3]]
    sign = [[1.0, 0.0, -1.0], [0.0, 1.0, -1.0], [-1.0, -1.0, 1.0]]
    index, signs = np.zeros((9, 9), dtype=np.intp), np.zeros((9, 9))
    for bi in range(3):
        for bj in range(3):
            if moment[bi][bj] is not None:
                index[3 * bi:3 * bi + 3, 3 * bj:3 * bj + 3] = 6 * moment[bi][bj] + sym
                signs[3 * bi:3 * bi + 3, 3 * bj:3 * bj + 3] = sign[bi][bj]
    return index, signs


_NORMAL_INDEX, _NORMAL_SIGN = _normal_tables()

#: From this many correspondences on, :func:`dlt` solves the 9 x 9 normal
#: equations (``eigh``) instead of taking the SVD of the ``2N x 9`` matrix.
_NORMAL_EQUATIONS_MIN = 8


def _similarity_inverse(T) -> np.ndarray:
    """Inverse of the similarities ``(..., 3, 3)`` made by :func:`normalise_points`."""
    s = T[..., 0, 0]
    out = np.zeros_like(T)
    out[..., 0, 0] = out[..., 1, 1] = 1.0 / s
    out[..., 0, 2] = -T[..., 0, 2] / s
    out[..., 1, 2] = -T[..., 1, 2] / s
    out[..., 2, 2] = 1.0
    return out


def _four_point(x, y, u, v, frames=None):
    """Closed-form 4-point homographies, unnormalised, component-major.

    ``x, y`` (source) and ``u, v`` (destination) have shape ``(4, S)``. With
    ``M = [p1 p2 p3]`` (homogeneous columns), the rows of ``adj(M)`` are the
    cross products ``r1 = p2 x p3``, ``r2 = p3 x p1``, ``r3 = p1 x p2`` and
    ``lam = adj(M) p4`` holds the determinants of the other three triples:
    ``A = M diag(lam)`` maps the projective basis onto the points (up to
    scale), ``A^-1 ~ diag(1 / lam) adj(M)``, and ``H = B A^-1`` is
    ``sum_i mu_i lam_j lam_k q_i r_i^T`` (``mu`` the destination's ``lam``,
    ``{i, j, k} = {1, 2, 3}``): no solve, no inverse.

    ``frames = (centre1, scale1, centre2, scale2)`` says the points are
    ``(p - centre) * scale`` of the original ones (Hartley normalisation):
    ``H`` is then returned in the original frame, ``T2^-1 H T1``, by mapping
    the ``q_i`` and ``r_i`` (one step each, no 3 x 3 products).

    Returns
    -------
    H : ndarray of shape (3, 3, S)
        ``H[a, b]`` over the samples, arbitrary scale and sign.
    dets_src, dets_dst : ndarray of shape (4, S)
        The determinants of the four point triples of each sample (twice the
        signed triangle areas; up to sign): near zero for collinear triples.
    """
    def adjugate(x, y):
        xa, xb, ya, yb = x[[1, 2, 0]], x[[2, 0, 1]], y[[1, 2, 0]], y[[2, 0, 1]]
        r = np.stack([ya - yb, xb - xa, xa * yb - xb * ya], axis=1)  # (3 rows, 3, S)
        lam = r[:, 0] * x[3] + r[:, 1] * y[3] + r[:, 2]
        d123 = r[0, 0] * x[0] + r[0, 1] * y[0] + r[0, 2]
        return r, lam, np.concatenate([d123[None], lam])

    r, lam, dets_src = adjugate(x, y)
    _, mu, dets_dst = adjugate(u, v)
    c = mu * (lam[[1, 2, 0]] * lam[[2, 0, 1]])
    u, v = u[:3], v[:3]
    if frames is not None:
        (c1x, c1y), s1, (c2x, c2y), s2 = frames
        r[:, 2] = r[:, 2] / s1 - c1x * r[:, 0] - c1y * r[:, 1]  # r_i^T T1 / s1
        u, v = u / s2 + c2x, v / s2 + c2y  # T2^-1 q_i
    cr = c[:, None] * r  # (3 rows i, 3, S)
    H = np.stack([(u[:, None] * cr).sum(axis=0), (v[:, None] * cr).sum(axis=0),
                  cr.sum(axis=0)])
    return H, dets_src, dets_dst


def four_point_homography(src, dst) -> np.ndarray:
    """Exact homographies through 4 correspondences, batched, in closed form.

    ``H = B A^-1`` where ``A`` (``B``) maps the projective basis onto the four
    source (destination) points, written with cofactors (cross products of
    the points) instead of solves and inverses of 3 x 3 stacks. No three
    points of a sample may be collinear (check first).

    Parameters
    ----------
    src, dst : ndarray of shape (S, 4, 2)

    Returns
    -------
    ndarray of shape (S, 3, 3)
        Scaled to unit Frobenius norm.

    Examples
    --------
    >>> H = np.array([[1.0, 0.2, 3.0], [0.1, 0.9, -2.0], [1e-3, 2e-3, 1.0]])
    >>> src = np.array([[[0.0, 0.0], [100.0, 0.0], [100.0, 80.0], [0.0, 80.0]]])
    >>> h = np.c_[src[0], np.ones(4)] @ H.T
    >>> est = four_point_homography(src, (h[:, :2] / h[:, 2:])[None])[0]
    >>> np.allclose(est / est[2, 2], H)
    True
    """
    src = np.asarray(src, dtype=float)
    dst = np.asarray(dst, dtype=float)
    H = _four_point(src[..., 0].T, src[..., 1].T, dst[..., 0].T, dst[..., 1].T)[0]
    H = np.moveaxis(H, -1, 0)
    return H / np.linalg.norm(H, axis=(-2, -1), keepdims=True)


def transfer(H, points) -> np.ndarray:
    """Points ``(N, 2)`` mapped by one homography ``H`` (``inf`` where they go to infinity).

    Examples
    --------
    >>> transfer(np.diag([2.0, 2.0, 1.0]), np.array([[1.0, 2.0]])).tolist()
    [[2.0, 4.0]]
    """
    p = np.c_[np.asarray(points, dtype=float), np.ones(len(points))] @ np.asarray(H).T
    with np.errstate(divide="ignore", invalid="ignore"):
        q = p[:, :2] / p[:, 2:]
    return np.where(np.isfinite(q), q, np.inf)


def transfer_error(H, src, dst) -> np.ndarray:
    """Forward transfer errors ``||dst - H src||`` of many homographies, shape ``(H, N)``.

    ``H`` is a stack ``(H, 3, 3)``; ``src, dst`` are ``(N, 2)``. A point sent
    to infinity has error ``inf``.
    """
    p = H[:, :, :2] @ src.T + H[:, :, 2:]  # (H, 3, N)
    with np.errstate(all="ignore"):
        d = p[:, :2] / p[:, 2:] - dst.T
        d *= d
        err = np.sqrt(d[:, 0] + d[:, 1])
    return np.where(np.isfinite(err), err, np.inf)


def symmetric_transfer_error(H, matches) -> np.ndarray:
    """Symmetric transfer error ``sqrt((|x2 - H x1|^2 + |x1 - H^-1 x2|^2) / 2)`` per match.

    ``H`` is one ``(3, 3)`` homography and ``matches`` a checked ``(N, 4)``
    array (no validation here: the hot path of the polish and the metrics).
    The backward map is the adjugate of ``H`` (``det(H) H^-1``: the same
    transfer, no inverse call), both directions in one product; a singular
    ``H`` gives ``inf`` everywhere.

    Examples
    --------
    >>> scale = np.diag([2.0, 2.0, 1.0])                   # x2 = 2 x1
    >>> symmetric_transfer_error(scale, np.array([[1.0, 1.0, 2.0, 2.0], [1, 0, 4, 0]])).tolist()
    [0.0, 1.5811388300841898]
    """
    (a, b, c), (d, e, f), (g, h, i) = H.tolist()
    adj = [[e * i - f * h, c * h - b * i, b * f - c * e],
           [f * g - d * i, a * i - c * g, c * d - a * f],
           [d * h - e * g, b * g - a * h, a * e - b * d]]
    if a * adj[0][0] + b * adj[1][0] + c * adj[2][0] == 0:
        return np.full(len(matches), np.inf)
    pts = matches.T.reshape(2, 2, -1)  # [[x1, y1], [x2, y2]]
    both = np.array([H.tolist(), adj])
    p = both[:, :, :2] @ pts + both[:, :, 2:]  # (2 directions, 3, N)
    with np.errstate(all="ignore"):
        dd = p[:, :2] / p[:, 2:] - pts[::-1]
        dd *= dd
        out = np.sqrt(0.5 * ((dd[0, 0] + dd[0, 1]) + (dd[1, 0] + dd[1, 1])))
    return np.where(np.isfinite(out), out, np.inf)
