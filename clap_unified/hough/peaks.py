"""Peak finding by non-maximum suppression, on dense grids and sparse bins."""

from __future__ import annotations

import numpy as np
from skimage.feature import peak_local_max

from .._validation import check_int

__all__ = ["accumulator_peaks", "sparse_peaks"]


def accumulator_peaks(votes, *, min_distance: int = 5, threshold: float | None = None,
                      num_peaks: int = 5, wrap_theta: bool = True) -> np.ndarray:
    """Local maxima of a ``(theta, rho)`` accumulator, strongest first.

    Uses :func:`skimage.feature.peak_local_max`. With ``wrap_theta`` the
    accumulator is padded across ``theta = 0 / pi`` (where ``rho`` changes
    sign), so a line near vertical is one peak, not two.

    Returns
    -------
    ndarray of int, shape (K, 2)
        ``(theta_index, rho_index)`` rows, ``K <= num_peaks``.
    """
    votes = np.asarray(votes)
    min_distance = check_int(min_distance, "min_distance", minimum=1)
    num_peaks = check_int(num_peaks, "num_peaks", minimum=1)
    thr = 1 if threshold is None else threshold
    pad = min_distance if wrap_theta else 0
    n_theta = votes.shape[0]
    if pad:
        flipped = votes[:, ::-1]
        padded = np.concatenate([flipped[-pad:], votes, flipped[:pad]], axis=0)
    else:
        padded = votes
    peaks = peak_local_max(padded, min_distance=min_distance, threshold_abs=thr,
                           exclude_border=False, num_peaks=np.inf)
    peaks = peaks[(peaks[:, 0] >= pad) & (peaks[:, 0] < pad + n_theta)]
    peaks[:, 0] -= pad
    order = np.argsort(-votes[peaks[:, 0], peaks[:, 1]], kind="stable")
    return peaks[order][:num_peaks]


def sparse_peaks(cells, counts, *, min_distance: int = 1, num_peaks: int = 5,
                 min_count: int = 1) -> np.ndarray:
    """Greedy non-maximum suppression over occupied cells of a sparse grid.

    Repeatedly takes the fullest remaining cell and suppresses every cell
    within ``min_distance`` (Chebyshev, in cells) of it. Works in any
    dimension, which a dense accumulator cannot (SE(3) has 6, homographies 8).

    Parameters
    ----------
    cells : ndarray of int, shape (C, d)
    counts : ndarray of int, shape (C,)

    Returns
    -------
    ndarray of int
        Indices into ``cells`` of the peaks, strongest first.

    Examples
    --------
    >>> cells = np.array([[0, 0], [0, 1], [5, 5]]); counts = np.array([4, 3, 2])
    >>> sparse_peaks(cells, counts).tolist()
    [0, 2]
    """
    cells = np.asarray(cells)
    counts = np.asarray(counts)
    num_peaks = check_int(num_peaks, "num_peaks", minimum=1)
    alive = counts >= min_count
    out = []
    while len(out) < num_peaks and np.any(alive):
        i = int(np.flatnonzero(alive)[np.argmax(counts[alive])])
        out.append(i)
        alive &= np.max(np.abs(cells - cells[i]), axis=1) > min_distance
    return np.array(out, dtype=np.intp)
