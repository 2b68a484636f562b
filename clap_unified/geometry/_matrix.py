"""Batched matrix exponential and principal matrix logarithm for small matrices.

Both functions work on stacks ``(..., n, n)`` and are vectorised over the
leading axes. The logarithm is the hot path of the homography distances
(hundreds of thousands of 3 x 3 relative matrices per pairwise matrix), so it
is computed in three tiers, each used only for the matrices the previous tier
could not handle accurately:

1. ``n == 3``: closed-form spectral formula. The eigenvalues are the roots of
   the characteristic cubic (shifted by the mean eigenvalue, scaled, one
   Newton polish), and the logarithm is the Newton divided-difference form
   ``log(A) = f[a] I + f[a, b] (A - a I) + f[a, b, c] (A - a I)(A - b I)``
   with the divided differences of ``log`` evaluated by series where the
   eigenvalues are close. It is exact for defective matrices (a pure
   translation homography is a Jordan block) and needs no eigenvectors.
   A matrix is passed on when the estimated amplification of rounding exceeds
   ``1e5`` (cancellation in the sum, times the grading ``max|l| / min|l|`` of
   the spectrum, times the squared departure from normality), when two close
   eigenvalues lie on opposite sides of the branch cut of ``log``, or when the
   computed eigenvalues fail a backward check (Vieta's formulas against the
   characteristic polynomial).
2. Any ``n``: batched :func:`numpy.linalg.eig`, ``V diag(log w) V^-1``. A
   matrix is passed on when ``cond(V) > 1e4`` (near-defective), when
   ``min|w| <= 1e-12 max|w|`` (near-singular), or when the reconstruction
   ``V diag(w) V^-1`` is off by more than ``1e-10`` relative.
3. :func:`scipy.linalg.logm` (inverse scaling and squaring), one matrix at a
   time; a matrix with condition number above ``1 / eps`` raises ``ValueError``.

Checking every result with ``expm(logm(A))`` costs a matrix exponential per
matrix on top of the logarithm, so it is opt-in (``verify=True``); the cheap
checks above bound the error instead.

Matrices with real negative eigenvalues have no real logarithm. As in SciPy,
the principal logarithm is then complex: an eigenvalue ``-r`` (``r > 0``)
contributes ``log(r) + i pi``; tiers 1 and 2 put eigenvalues whose imaginary
part is at rounding level on the upper side of the cut. Its Frobenius norm
``sqrt(sum |L_ij|**2)`` is still defined and is what the distances use. For a
real matrix it does not depend on which side of the cut rounding puts such an
eigenvalue (the imaginary part is ``+-pi`` times a real spectral projector), so
the fast tiers and the SciPy fallback agree on it.
"""

from __future__ import annotations

import warnings

import numpy as np
import scipy.linalg

from .._validation import check_array

__all__ = ["expm", "logm"]

_EPS = np.finfo(float).eps
#: Tier 1 hands a matrix on when rounding may be amplified more than this.
_MAX_AMPLIFICATION = 1e5
#: Tier 2 hands a matrix on when its eigenvector matrix is worse conditioned.
_MAX_COND_V = 1e4
#: A real input has a real logarithm when ``||Im L|| <= _REAL_TOL max(1, ||L||)``.
#: A genuinely complex principal log of a real matrix has ``||Im L|| >= pi``.
_REAL_TOL = 1e-8


def _square_stack(A, name: str) -> np.ndarray:
    arr = np.asarray(A)
    dtype = complex if np.iscomplexobj(arr) else float
    arr = check_array(arr, name, shape=(Ellipsis, None, None), dtype=dtype)
    if arr.shape[-1] != arr.shape[-2]:
        raise ValueError(f"{name}: expected square matrices (..., n, n), got {arr.shape}")
    return arr


def expm(A) -> np.ndarray:
    """Matrix exponential of a stack of square matrices.

    Parameters
    ----------
    A : ndarray of shape (..., n, n)
        Real or complex.

    Returns
    -------
    ndarray of shape (..., n, n)
        ``exp(A)``, same dtype kind as ``A``.

    Examples
    --------
    >>> A = np.array([[[0.0, -1.0], [1.0, 0.0]]]) * np.array([0.0, np.pi / 2])[:, None, None]
    >>> (expm(A).round(6) + 0.0).tolist()
    [[[1.0, 0.0], [0.0, 1.0]], [[0.0, -1.0], [1.0, 0.0]]]
    """
    arr = _square_stack(A, "A")
    if arr.size == 0:
        return arr.copy()
    return scipy.linalg.expm(arr)


def logm(A, *, verify: bool = False) -> np.ndarray:
    """Principal matrix logarithm of a stack of square matrices.

    Parameters
    ----------
    A : ndarray of shape (..., n, n)
        Real or complex, non-singular.
    verify : bool
        Also check ``||expm(L) - A|| <= 1e-8 ||A||`` for every matrix and
        recompute the failures with :func:`scipy.linalg.logm` (slow; the cheap
        checks described in the module docstring are always done).

    Returns
    -------
    ndarray of shape (..., n, n)
        Real when ``A`` is real and every logarithm is real to rounding (no
        eigenvalue on the closed negative real axis); complex otherwise, with
        the imaginary part of the real-to-rounding matrices set to zero.

    Raises
    ------
    ValueError
        If ``A`` is not a stack of finite square matrices, or one matrix is
        singular to working precision (it has no logarithm).

    Examples
    --------
    A Jordan block (defective) and a rotation by 90 degrees:

    >>> J = np.array([[1.0, 1.0, 0.0], [0.0, 1.0, 1.0], [0.0, 0.0, 1.0]])
    >>> R = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    >>> L = logm(np.stack([J, R]))
    >>> (L[0].round(6) + 0.0).tolist()
    [[0.0, 1.0, -0.5], [0.0, 0.0, 1.0], [0.0, 0.0, 0.0]]
    >>> f"{L[1, 1, 0]:.6f}"
    '1.570796'

    A negative eigenvalue gives a complex logarithm (``log 2 + i pi``):

    >>> complex(logm(np.diag([-2.0, 1.0, 1.0]))[0, 0]).__format__(".6f")
    '0.693147+3.141593j'
    """
    arr = _square_stack(A, "A")
    n = arr.shape[-1]
    flat = arr.reshape(-1, n, n)
    real_input = not np.iscomplexobj(flat)
    out = np.zeros(flat.shape, dtype=complex)
    todo = np.ones(len(flat), dtype=bool)
    if len(flat) == 0:
        return np.zeros(arr.shape, dtype=float if real_input else complex)

    if n == 3:
        L, ok = _logm3(flat, real_input)
        out[ok] = L[ok]
        todo = ~ok
    if np.any(todo):
        idx = np.flatnonzero(todo)
        L, ok = _logm_eig(flat[idx], real_input)
        out[idx[ok]] = L[ok]
        todo[idx[ok]] = False
    if verify:
        done = np.flatnonzero(~todo)
        err = np.linalg.norm(scipy.linalg.expm(out[done]) - flat[done], axis=(-2, -1))
        scale = np.linalg.norm(flat[done], axis=(-2, -1))
        todo[done[~(err <= 1e-8 * scale)]] = True
    for i in np.flatnonzero(todo):
        out[i] = _logm_scipy(flat[i], np.unravel_index(i, arr.shape[:-2]))

    if real_input:
        imag = np.linalg.norm(out.imag, axis=(-2, -1))
        size = np.linalg.norm(out.real, axis=(-2, -1))
        real = imag <= _REAL_TOL * np.maximum(1.0, size)
        if np.all(real):
            return out.real.reshape(arr.shape)
        out.imag[real] = 0.0
    return out.reshape(arr.shape)


# ------------------------------------------------------------------ tier 3
def _logm_scipy(a: np.ndarray, index) -> np.ndarray:
    cond = np.linalg.cond(a)
    if not np.isfinite(cond) or cond * _EPS > 1.0:
        raise ValueError(
            f"A: matrix at index {tuple(int(i) for i in index)} is singular to working "
            "precision and has no logarithm"
        )
    with warnings.catch_warnings():
        # scipy warns when its own error estimate exceeds 1000 eps; near-defective
        # matrices are exactly the ones routed here, and the result is still the
        # best available, so the warning is not useful to callers.
        warnings.simplefilter("ignore", RuntimeWarning)
        return scipy.linalg.logm(a)


# ------------------------------------------------------------------ tier 2
def _snap_negative_real(w: np.ndarray, real_input: bool) -> np.ndarray:
    """Put eigenvalues that are real to rounding on the real axis (upper side of the cut)."""
    w = w.astype(complex)
    if real_input:
        snap = np.abs(w.imag) <= 1e-14 * np.abs(w)
        w = np.where(snap, w.real + 0j, w)
    return w


def _logm_eig(A: np.ndarray, real_input: bool):
    """Eigendecomposition tier: returns ``(L, ok)`` for a stack ``(k, n, n)``."""
    n = A.shape[-1]
    L = np.zeros(A.shape, dtype=complex)
    w, V = np.linalg.eig(A)
    w = _snap_negative_real(w, real_input)
    with np.errstate(all="ignore"):
        cond = np.linalg.cond(V)
        absw = np.abs(w)
        # near-singular matrices (log of a rounding-level eigenvalue) go to tier 3,
        # which raises for the singular ones
        ok = (np.isfinite(cond) & (cond <= _MAX_COND_V)
              & (absw.min(axis=-1) > 1e-12 * absw.max(axis=-1)))
        if not np.any(ok):
            return L, ok
        Vg, wg = V[ok], w[ok]
        Vi = np.linalg.inv(Vg)
        Lg = (Vg * np.log(wg)[:, None, :]) @ Vi
        recon = (Vg * wg[:, None, :]) @ Vi
        resid = np.linalg.norm(recon - A[ok], axis=(-2, -1))
        scale = np.linalg.norm(A[ok], axis=(-2, -1))
        good = (resid <= 1e-10 * scale * np.sqrt(n)) & np.all(np.isfinite(Lg), axis=(-2, -1))
    L[ok] = Lg
    ok[np.flatnonzero(ok)[~good]] = False
    return L, ok


# ------------------------------------------------------------------ tier 1
_OMEGA = np.exp(2j * np.pi * np.arange(3) / 3)
#: Row k: order (a, b, c) of the eigenvalues when c = k is farthest from the closest pair.
_ORDER = np.array([[1, 2, 0], [0, 2, 1], [0, 1, 2]])


def _log(z: np.ndarray) -> np.ndarray:
    """Principal complex log, ``log|z| + i arg z`` (same branch as ``np.log``, faster)."""
    out = np.empty(z.shape, dtype=complex)
    out.real = np.log(np.abs(z))
    out.imag = np.arctan2(z.imag, z.real)
    return out


def _cubic_roots(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Roots ``(N, 3)`` of ``t^3 + p t + q`` (complex Cardano with the stable sign)."""
    s = np.sqrt((q / 2) ** 2 + (p / 3) ** 3)
    w1, w2 = -q / 2 + s, -q / 2 - s
    w = np.where(np.abs(w1) >= np.abs(w2), w1, w2)
    u = (w ** (1 / 3))[:, None] * _OMEGA
    t = np.where(u != 0, u - p[:, None] / (3 * np.where(u != 0, u, 1)), 0)
    # one Newton polish, kept only where it lowers the residual (not at multiple roots)
    P, Q = p[:, None], q[:, None]
    f = (t * t + P) * t + Q
    df = 3 * t * t + P
    t_new = t - f / np.where(df != 0, df, 1)
    better = (df != 0) & (np.abs((t_new * t_new + P) * t_new + Q) < np.abs(f))
    return np.where(better, t_new, t)


def _series_terms(ratio: float, cap: int) -> int:
    """Number of terms of a series with geometric ratio ``ratio`` for double precision."""
    if not ratio > 1e-300:
        return 1
    return int(min(cap, max(1, np.ceil(np.log(1e-17) / np.log(min(ratio, 0.5))))))


def _dd_pair(a, b, la, lb):
    """Divided difference ``log[a, b]`` and a flag for close pairs across the branch cut."""
    diff = b - a
    mid = (a + b) / 2
    close = np.abs(diff) <= 0.5 * np.abs(mid)
    value = (lb - la) / np.where(close, 1, diff)
    jump = np.zeros(a.shape, dtype=bool)
    if np.any(close):
        z = diff[close] / (2 * mid[close])  # |z| <= 1/4
        z2 = z * z
        series = np.zeros_like(z)
        for j in range(_series_terms(np.abs(z2).max(), 14), -1, -1):
            # atanh(z) / z = sum_j z^(2j) / (2j + 1)
            series = series * z2 + 1.0 / (2 * j + 1)
        value[close] = series / mid[close]
        # log b - log a = 2 atanh(z) unless the pair straddles the branch cut
        jump[close] = np.abs((lb[close] - la[close]) - 2 * z * series) > 1.0
    return value, jump


def _dd_cluster(lam, loglam):
    """``log[l1, l2, l3]`` for clustered eigenvalues by a series about their mean."""
    m = lam.mean(axis=1)
    u = (lam - m[:, None]) / m[:, None]
    e1 = u.sum(axis=1)
    e2 = u[:, 0] * u[:, 1] + u[:, 0] * u[:, 2] + u[:, 1] * u[:, 2]
    e3 = u.prod(axis=1)
    # log(1 + x) = sum (-1)^(k+1) x^k / k; the divided difference of x^k on three
    # nodes is the complete homogeneous polynomial h_{k-2}(u1, u2, u3) (|u| <= 0.2).
    h_prev2, h_prev1, h = np.zeros_like(m), np.zeros_like(m), np.ones_like(m)
    total = np.zeros_like(m)
    for k in range(2, 2 + _series_terms(np.abs(u).max(), 40)):
        total += (-1) ** (k + 1) / k * h
        h_prev2, h_prev1, h = h_prev1, h, e1 * h - e2 * h_prev1 + e3 * h_prev2
    # the series is the principal branch unless the cluster straddles the cut (Re m < 0)
    jump = np.zeros(m.shape, dtype=bool)
    left = m.real < 0
    if np.any(left):
        jump[left] = np.any(np.abs(loglam[left] - _log(m[left])[:, None]
                                   - np.log1p(u[left])) > 1.0, axis=1)
    return total / m**2, jump


def _fro(M: np.ndarray) -> np.ndarray:
    """Frobenius norms of a stack of complex matrices."""
    re, im = M.real, M.imag
    return np.sqrt(np.einsum("nij,nij->n", re, re) + np.einsum("nij,nij->n", im, im))


def _balanced_fro2(A: np.ndarray) -> np.ndarray:
    """``sum_i |a_ii|^2 + sum_(i != j) |a_ij a_ji|``: squared Frobenius norm up to diagonal scaling.

    Invariant under diagonal similarity ``D^-1 A D`` and a lower bound of
    ``||D^-1 A D||_F^2`` for every ``D`` (AM-GM on each pair), so badly scaled
    but nearly normal matrices (homographies in pixels) are not mistaken for
    non-normal ones.
    """
    absA = np.abs(A)
    return np.einsum("nij,nji->n", absA, absA)


def _logm3(A: np.ndarray, real_input: bool):
    """Closed-form tier for ``(N, 3, 3)``: returns ``(L, ok)``."""
    eye = np.eye(3)
    with np.errstate(all="ignore"):
        # eigenvalues: mean eigenvalue + roots of the depressed characteristic cubic of
        # B = A - m0 I, scaled to entries <= 1 (no cancellation for near-scalar A)
        m0 = np.trace(A, axis1=-2, axis2=-1) / 3
        B = A - m0[:, None, None] * eye
        c = np.abs(B).max(axis=(-2, -1))
        c = np.where(c > 0, c, 1.0)
        Bs = B / c[:, None, None]
        b00, b01, b02 = Bs[:, 0, 0], Bs[:, 0, 1], Bs[:, 0, 2]
        b10, b11, b12 = Bs[:, 1, 0], Bs[:, 1, 1], Bs[:, 1, 2]
        b20, b21, b22 = Bs[:, 2, 0], Bs[:, 2, 1], Bs[:, 2, 2]
        p = b00 * b11 - b01 * b10 + b00 * b22 - b02 * b20 + b11 * b22 - b12 * b21
        q = -(b00 * (b11 * b22 - b12 * b21) - b01 * (b10 * b22 - b12 * b20)
              + b02 * (b10 * b21 - b11 * b20))
        p, q = p.astype(complex), q.astype(complex)
        t = _cubic_roots(p, q)
        # backward check (Vieta): the roots are those of a cubic within rounding of ours
        t0, t1, t2 = t[:, 0], t[:, 1], t[:, 2]
        vieta = (np.abs(t0 + t1 + t2) + np.abs(t0 * t1 + t0 * t2 + t1 * t2 - p)
                 + np.abs(t0 * t1 * t2 + q))
        exact = vieta <= 1e-11 * (1 + np.abs(p) + np.abs(q))
        lam = _snap_negative_real(m0[:, None] + c[:, None] * t, real_input)

        # order (a, b, c): (a, b) the closest pair, c the remaining eigenvalue
        l0, l1, l2 = lam[:, 0], lam[:, 1], lam[:, 2]
        gaps = np.stack([np.abs(l1 - l2), np.abs(l0 - l2), np.abs(l0 - l1)], axis=1)
        lam = np.take_along_axis(lam, _ORDER[np.argmin(gaps, axis=1)], axis=1)
        loglam = _log(lam)
        a, b, cc = lam[:, 0], lam[:, 1], lam[:, 2]
        la, lb, lc = loglam[:, 0], loglam[:, 1], loglam[:, 2]

        f_ab, jump_ab = _dd_pair(a, b, la, lb)
        f_bc, jump_bc = _dd_pair(b, cc, lb, lc)
        f_abc = (f_bc - f_ab) / (cc - a)
        jump = jump_ab | jump_bc
        cluster = gaps.max(axis=1) <= 0.25 * np.abs(lam).min(axis=1)
        if np.any(cluster):
            f3, jump3 = _dd_cluster(lam[cluster], loglam[cluster])
            f_abc[cluster] = f3
            jump[cluster] |= jump3

        # Newton form of the interpolating polynomial of log at the eigenvalues
        Aa = A - a[:, None, None] * eye
        Aab = Aa @ (A - b[:, None, None] * eye)
        L = la[:, None, None] * eye + f_ab[:, None, None] * Aa + f_abc[:, None, None] * Aab

        # error estimate (validated against scipy on graded, non-normal and
        # homography-like stacks): rounding in the sum is amplified by (sum of term
        # sizes) / (size of the result); the eigenvalues carry absolute errors of
        # the order of the largest one (relative error max|l| / min|l| on the
        # smallest); and non-normality amplifies both, measured by the departure
        # ||A||_F^2 / sum |l|^2 (1 when normal) with ||A||_F^2 taken up to
        # diagonal scaling, so that pixel-scaled homographies do not count as
        # non-normal
        terms = (np.abs(la) * np.sqrt(3) + np.abs(f_ab) * _fro(Aa)
                 + np.abs(f_abc) * _fro(Aab))
        absl = np.abs(lam)
        grading = absl.max(axis=1) / absl.min(axis=1)
        departure2 = _balanced_fro2(A) / np.einsum("ni,ni->n", absl, absl)
        stable = terms * grading * departure2 <= _MAX_AMPLIFICATION * _fro(L)
        # a real matrix's eigenvalue left of the origin that the snap did not put on
        # the real axis (imaginary part above 1e-14 of its modulus but at the
        # rounding level of the spectrum) may sit on either side of the cut: with
        # two such eigenvalues the sides can differ and the result is not the
        # principal logarithm; the eigendecomposition tier gets them exactly real
        if real_input:
            absl = np.abs(lam)
            jump |= np.any((lam.real < 0) & (lam.imag != 0)
                           & (np.abs(lam.imag) <= 1e-8 * absl.max(axis=1, keepdims=True)),
                           axis=1)
        ok = (stable & exact & ~jump & np.all(lam != 0, axis=1)
              & np.all(np.isfinite(L), axis=(-2, -1)))
    return L, ok
