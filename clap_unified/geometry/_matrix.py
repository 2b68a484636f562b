"""Batched exponential and principal logarithm of small matrices.

``scipy.linalg.expm`` already accepts stacks. ``scipy.linalg.logm`` does not,
and a Python loop over it is slow for thousands of 3 x 3 matrices, so
:func:`logm` diagonalises the whole stack at once with ``numpy.linalg.eig``
and falls back to ``scipy.linalg.logm`` only for matrices whose eigenvector
basis is ill-conditioned (repeated or defective eigenvalues).
"""

from __future__ import annotations

import warnings

import numpy as np
import scipy.linalg

__all__ = ["expm", "logm"]

#: Eigenvector bases with a larger condition number use the scipy fallback.
COND_LIMIT = 1e6


def expm(a) -> np.ndarray:
    """Matrix exponential of ``(..., n, n)`` arrays."""
    a = np.asarray(a)
    if a.size == 0:
        return np.empty(a.shape, dtype=a.dtype)
    return scipy.linalg.expm(a)


def logm(a) -> np.ndarray:
    """Principal matrix logarithm of ``(..., n, n)`` arrays, batched.

    The result is real where every matrix has a real principal logarithm (no
    eigenvalue on the closed negative real axis); otherwise complex, like
    ``scipy.linalg.logm``. Its Frobenius norm is defined either way.

    Examples
    --------
    >>> a = np.array([[[2.0, 1.0], [0.0, 3.0]], [[1.0, 0.0], [0.0, 1.0]]])
    >>> np.allclose(expm(logm(a)), a)
    True
    """
    a = np.asarray(a, dtype=float)
    shape = a.shape
    flat = a.reshape(-1, shape[-2], shape[-1])
    if flat.shape[0] == 0:
        return np.empty(shape)
    w, v = np.linalg.eig(flat)
    with np.errstate(all="ignore"):
        vinv = np.linalg.inv(v)
        # Frobenius-norm condition number (an upper bound of the 2-norm one), cheaper than SVD
        cond = np.linalg.norm(v, axis=(-2, -1)) * np.linalg.norm(vinv, axis=(-2, -1))
    good = np.isfinite(cond) & (cond < COND_LIMIT) & np.all(w != 0, axis=-1)
    out = np.empty(flat.shape, dtype=complex)
    if np.any(good):
        logw = np.log(w[good].astype(complex))
        out[good] = (v[good] * logw[:, None, :]) @ vinv[good]
    with warnings.catch_warnings():
        # scipy warns "logm result may be inaccurate" with its own error estimate; the
        # fallback handles exactly the ill-conditioned cases, so the estimate is expected.
        warnings.filterwarnings("ignore", "logm result may be inaccurate", RuntimeWarning)
        for i in np.flatnonzero(~good):
            out[i] = scipy.linalg.logm(flat[i])
    scale = np.maximum(1.0, np.abs(out).max(axis=(-2, -1), initial=0.0))
    if np.all(np.abs(out.imag).max(axis=(-2, -1)) <= 1e-9 * scale):
        return out.real.reshape(shape)
    return out.reshape(shape)
