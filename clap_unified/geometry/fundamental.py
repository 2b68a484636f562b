"""Epipolar arithmetic: fundamental matrices from correspondences, and their errors.

Convention: ``x2^T F x1 = 0`` for a correspondence ``x1 = (x1, y1)`` in image 1
and ``x2 = (x2, y2)`` in image 2 (rows ``(x1, y1, x2, y2)`` as for
homographies). Every ``F`` returned here has unit Frobenius norm and its
entry of largest magnitude positive
(:func:`~clap_unified.geometry.projective.normalise_projective`).

* :func:`seven_point`: the minimal solver, batched over samples: the null
  space of the 7 x 9 epipolar constraints is spanned by ``F1, F2``; the
  singular members ``x F1 + y F2`` are the real roots of the homogeneous cubic
  ``det(x F1 + y F2) = 0`` (one to three per sample, from the eigenvalues of
  a batch of 3 x 3 companion matrices);
* :func:`eight_point`: Hartley-normalised, weighted linear fit of eight or
  more correspondences, rank 2 enforced by SVD;
* :func:`sampson_error`: the square root of the Sampson distance (the
  first-order geometric error), in pixels, of many ``F`` against many
  correspondences, so a threshold in pixels means what it means for a
  homography's transfer error.

Hartley normalisation is :func:`~clap_unified.geometry.homography_arithmetic.normalise_points`,
the one copy on this floor.
"""

from __future__ import annotations

import numpy as np

from .._validation import check_array
from .homography_arithmetic import normalise_points
from .projective import normalise_projective

__all__ = ["eight_point", "sampson_denominator", "sampson_error", "seven_point"]

#: A 7 x 9 constraint matrix whose QR has a diagonal entry of ``R`` below this ratio
#: of the largest is rank-deficient: the sample does not determine ``F``.
RANK_RATIO = 1e-9
#: The same for the eigenvalues of ``A^T A`` (squared singular values) of :func:`eight_point`.
EIGEN_RATIO = 1e-12
#: Roots of the cubic whose imaginary part is below this (relative) are real.
REAL_TOL = 1e-8
#: A cubic ``det(x F1 + y F2)`` whose coefficients are all below this is identically
#: zero: every matrix of the pencil (``F1``, ``F2`` of unit norm in the normalised frame)
#: has rank 2, as when six of the seven points lie on one plane, and its "roots" are
#: rounding noise that differs between BLAS builds. Such a sample determines no ``F``.
#: (On AdelaideRMF such cubics are below 1e-14, the others above 1e-4.)
CUBIC_TOL = 1e-10


def _constraints(q1, q2):
    """Rows ``kron(x2, x1)`` of the epipolar constraints ``x2^T F x1 = 0``, ``(..., N, 9)``."""
    h1 = np.concatenate([q1, np.ones((*q1.shape[:-1], 1))], axis=-1)
    h2 = np.concatenate([q2, np.ones((*q2.shape[:-1], 1))], axis=-1)
    return (h2[..., :, None] * h1[..., None, :]).reshape(*q1.shape[:-1], 9)


def _triple(a, b, c):
    """``det([a b c])`` of stacks of 3-vectors (columns)."""
    return np.einsum("...i,...i->...", a, np.cross(b, c))


def seven_point(x1, x2):
    """Fundamental matrices through 7 correspondences, batched: 1 to 3 per sample.

    Parameters
    ----------
    x1, x2 : ndarray of shape (S, 7, 2)
        The points of each sample in image 1 and image 2 (one sample may be
        given as ``(7, 2)``).

    Returns
    -------
    F : ndarray of shape (K, 3, 3)
        Every real solution, unit Frobenius norm, rank 2.
    owner : ndarray of int, shape (K,)
        ``owner[j]`` is the sample solution ``j`` came from; a degenerate
        sample (fewer than 7 independent constraints: repeated points, too
        many points on a line) has none.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> X = np.c_[rng.uniform(-1, 1, (7, 2)), rng.uniform(4, 6, 7)]
    >>> x1 = 500 * X[:, :2] / X[:, 2:] + 320
    >>> Y = X + [0.5, 0.1, 0.0]                    # second camera moved along x
    >>> x2 = 500 * Y[:, :2] / Y[:, 2:] + 320
    >>> F, owner = seven_point(x1, x2)
    >>> bool(np.all(owner == 0)), float(np.abs(sampson_error(F, x1, x2)).max()) < 1e-6
    (True, True)
    """
    x1 = np.asarray(x1, dtype=float)
    x2 = np.asarray(x2, dtype=float)
    if x1.ndim == 2:
        x1, x2 = x1[None], x2[None]
    if x1.shape != x2.shape or x1.shape[1:] != (7, 2):
        raise ValueError(f"x1, x2: expected two arrays of shape (S, 7, 2), got {x1.shape} "
                         f"and {x2.shape}")
    n = len(x1)
    if n == 0:
        return np.empty((0, 3, 3)), np.empty(0, dtype=np.intp)
    q1, T1 = normalise_points(x1)
    q2, T2 = normalise_points(x2)
    A = _constraints(q1, q2)  # (S, 7, 9)
    # the null space of A: the last two columns of Q in the complete QR of A^T (a third
    # of the time of an SVD); a constraint dependent on the previous ones leaves a
    # (near-)zero diagonal entry of R
    with np.errstate(all="ignore"):
        Q, R = np.linalg.qr(np.swapaxes(A, 1, 2), mode="complete")
    r = np.abs(np.diagonal(R, axis1=1, axis2=2))
    ok = np.all(np.isfinite(r), axis=-1) & (r.min(axis=-1) > RANK_RATIO * r.max(axis=-1))
    # the determinant of x F1 + y F2 as a homogeneous cubic in (x, y), column by column
    a, b = Q[:, :, 7].reshape(n, 3, 3), Q[:, :, 8].reshape(n, 3, 3)
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    c3 = _triple(a0, a1, a2)
    c2 = _triple(b0, a1, a2) + _triple(a0, b1, a2) + _triple(a0, a1, b2)
    c1 = _triple(a0, b1, b2) + _triple(b0, a1, b2) + _triple(b0, b1, a2)
    c0 = _triple(b0, b1, b2)
    # roots in t = x / y when |c3| >= |c0|, else in r = y / x: the leading coefficient
    # is the larger end, so no root runs to infinity
    by_x = np.abs(c3) >= np.abs(c0)
    coef = np.where(by_x[:, None], np.stack([c3, c2, c1, c0], -1),
                    np.stack([c0, c1, c2, c3], -1))
    lead = coef[:, 0]
    ok &= np.abs(coef).max(axis=-1) > CUBIC_TOL
    ok &= np.abs(lead) > 1e-12 * np.abs(coef).max(axis=-1)
    lead = np.where(ok, lead, 1.0)
    companion = np.zeros((n, 3, 3))
    companion[:, 0] = -coef[:, 1:] / lead[:, None]
    companion[:, 1, 0] = companion[:, 2, 1] = 1.0
    companion[~ok] = 0.0
    roots = np.linalg.eigvals(companion)  # (S, 3)
    real = np.abs(roots.imag) <= REAL_TOL * (1.0 + np.abs(roots.real))
    real &= ok[:, None]
    owner, k = np.nonzero(real)
    r = roots.real[owner, k]
    x = np.where(by_x[owner], r, 1.0)
    y = np.where(by_x[owner], 1.0, r)
    Fn = x[:, None, None] * a[owner] + y[:, None, None] * b[owner]
    F = np.swapaxes(T2[owner], -1, -2) @ Fn @ T1[owner]
    F = normalise_projective(F)
    good = np.all(np.isfinite(F.reshape(-1, 9)), axis=-1)
    return F[good], owner[good].astype(np.intp)


def eight_point(x1, x2, weights=None):
    """Normalised, weighted 8-point fundamental matrix with rank 2 enforced.

    After Hartley normalisation of both point sets (weighted), ``F`` is the
    eigenvector of the smallest eigenvalue of ``A^T W A`` (``A`` the
    ``N x 9`` epipolar constraints), its smallest singular value is set to
    zero, and it is mapped back to pixels: ``F = T2^T Fn T1``.

    Parameters
    ----------
    x1, x2 : ndarray of shape (N, 2)
        Corresponding points, ``N >= 8`` with a positive weight.
    weights : ndarray of shape (N,), optional
        Non-negative weights; zero-weight correspondences play no part.

    Returns
    -------
    ndarray of shape (3, 3) or None
        ``F`` with unit Frobenius norm, or ``None`` when fewer than 8
        correspondences count or they do not determine ``F`` (a null space of
        more than one dimension: repeated points, points on a line, a planar
        scene without noise).

    Examples
    --------
    >>> rng = np.random.default_rng(1)
    >>> X = np.c_[rng.uniform(-1, 1, (20, 2)), rng.uniform(4, 6, 20)]
    >>> x1 = 500 * X[:, :2] / X[:, 2:] + 320
    >>> Y = X + [0.5, 0.1, 0.2]
    >>> x2 = 500 * Y[:, :2] / Y[:, 2:] + 320
    >>> F = eight_point(x1, x2)
    >>> float(np.abs(sampson_error(F, x1, x2)).max()) < 1e-8
    True
    >>> eight_point(x1[:7], x2[:7]) is None
    True
    """
    x1 = check_array(x1, "x1", shape=(None, 2))
    x2 = check_array(x2, "x2", shape=(len(x1), 2))
    if weights is not None:
        w = check_array(weights, "weights", shape=(len(x1),))
        if np.any(w < 0):
            raise ValueError("weights: expected non-negative weights")
        keep = w > 0
        x1, x2, w = x1[keep], x2[keep], w[keep]
    else:
        w = np.ones(len(x1))
    if len(x1) < 8:
        return None
    q1, T1 = normalise_points(x1, w)
    q2, T2 = normalise_points(x2, w)
    A = _constraints(q1, q2)
    M = A.T @ (A * (w / w.sum())[:, None])
    evals, evecs = np.linalg.eigh(M)
    # a second (near-)zero eigenvalue: a pencil of solutions, F is not determined
    if not (np.all(np.isfinite(evals)) and evals[1] > EIGEN_RATIO * evals[-1]):
        return None
    U, S, Vt = np.linalg.svd(evecs[:, 0].reshape(3, 3))
    Fn = (U[:, :2] * S[:2]) @ Vt[:2]
    F = normalise_projective(T2.T @ Fn @ T1)
    return F if np.all(np.isfinite(F)) else None


def _epipolar_terms(F, x1, x2):
    """``|x2^T F x1|`` and the Sampson denominator, ``(H, N)`` each, for ``F`` ``(H, 3, 3)``."""
    n = len(x1)
    X1, X2 = np.ones((3, n)), np.ones((3, n))
    X1[:2], X2[:2] = x1.T, x2.T
    # two plain matrix products (3H x 3 by 3 x N), not a stack of tiny ones
    a = (F.reshape(-1, 3) @ X1).reshape(len(F), 3, n)  # F x1
    b = (np.swapaxes(F[:, :, :2], 1, 2).reshape(-1, 3) @ X2).reshape(len(F), 2, n)  # F^T x2
    num = a[:, 0] * X2[0]
    num += a[:, 1] * X2[1]
    num += a[:, 2]
    np.abs(num, out=num)
    a2 = a[:, :2]
    den = np.einsum("hkn,hkn->hn", a2, a2) + np.einsum("hkn,hkn->hn", b, b)
    return num, den


def sampson_denominator(F, x1, x2) -> np.ndarray:
    """``(F x1)_1^2 + (F x1)_2^2 + (F^T x2)_1^2 + (F^T x2)_2^2`` for one ``F``, shape ``(N,)``.

    The squared gradient of ``x2^T F x1`` with respect to the four
    coordinates: ``1 / g`` weights the 8-point fit towards the Sampson error
    (Sampson's iteration).

    Examples
    --------
    >>> F = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])
    >>> sampson_denominator(F, np.array([[0.0, 1.0]]), np.array([[3.0, 1.0]])).tolist()
    [2.0]
    """
    F = np.asarray(F, dtype=float).reshape(1, 3, 3)
    return _epipolar_terms(F, np.asarray(x1, dtype=float), np.asarray(x2, dtype=float))[1][0]


def sampson_error(F, x1, x2) -> np.ndarray:
    """Square root of the Sampson distance, in pixels, of many ``F`` and correspondences.

    ``|x2^T F x1| / sqrt((F x1)_1^2 + (F x1)_2^2 + (F^T x2)_1^2 + (F^T x2)_2^2)``:
    the first-order approximation of the distance (in the 4-D space of
    ``(x1, y1, x2, y2)``) from a correspondence to the nearest one that
    satisfies ``F`` exactly. A correspondence at both epipoles has error 0;
    where the denominator vanishes otherwise the error is ``inf``.

    Parameters
    ----------
    F : ndarray of shape (H, 3, 3) or (3, 3)
    x1, x2 : ndarray of shape (N, 2)

    Returns
    -------
    ndarray of shape (H, N), or (N,) for one ``F``

    Examples
    --------
    >>> F = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])  # y2 = y1
    >>> err = sampson_error(F, np.array([[0.0, 1.0], [5.0, 2.0]]),
    ...                     np.array([[3.0, 1.0], [5.0, 4.0]]))
    >>> np.round(err, 6).tolist()                                 # |y2 - y1| / sqrt(2)
    [0.0, 1.414214]
    """
    F = np.asarray(F, dtype=float)
    single = F.ndim == 2
    F = F.reshape(-1, 3, 3)
    x1 = np.asarray(x1, dtype=float)
    x2 = np.asarray(x2, dtype=float)
    num, den = _epipolar_terms(F, x1, x2)
    with np.errstate(divide="ignore", invalid="ignore"):
        err = num / np.sqrt(den)
    err = np.where(num == 0, 0.0, np.where(np.isfinite(err), err, np.inf))
    return err[0] if single else err
