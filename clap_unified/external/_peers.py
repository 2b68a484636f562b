"""Shared by the wrappers of other libraries' homography estimators (PoseLib, COLMAP)."""

from __future__ import annotations

import numpy as np

from .._validation import as_generator

__all__ = ["degenerate_reason", "seed_of"]


def seed_of(rng) -> int:
    """The integer seed a peer library receives: the first draw of ``as_generator(rng)``.

    Parameters
    ----------
    rng : None, int or numpy.random.Generator

    Returns
    -------
    int
        In ``[0, 2**31 - 1)``; the same for the same int ``rng``.

    Examples
    --------
    >>> seed_of(0) == seed_of(0)
    True
    """
    return int(as_generator(rng).integers(0, 2**31 - 1))


def degenerate_reason(data) -> str | None:
    """Why the matches determine no homography, or None when they may.

    The points of either image all identical or all on one line leave a
    homography undetermined: a peer may still return one that fits them
    (PoseLib does, for collinear points), which is no answer.

    Parameters
    ----------
    data : ndarray of shape (N, 4)
        Rows ``(x1, y1, x2, y2)``.

    Returns
    -------
    str or None

    Examples
    --------
    >>> t = np.arange(10.0)
    >>> degenerate_reason(np.c_[t, 2 * t, t, t ** 2])
    'the points of image 1 are collinear or identical'
    >>> degenerate_reason(np.c_[t, t ** 2, t, t ** 2]) is None
    True
    """
    for k, cols in ((1, slice(0, 2)), (2, slice(2, 4))):
        p = np.asarray(data[:, cols], dtype=float)
        s = np.linalg.svd(p - p.mean(0), compute_uv=False)
        if s[-1] <= 1e-9 * max(s[0], 1.0):
            return f"the points of image {k} are collinear or identical"
    return None
