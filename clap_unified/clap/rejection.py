"""Robust single centres: iterative trimming and MAD rejection.

The paper's protocol for homographies: 5 rounds, each discarding the 20 %
of hypotheses farthest from the current centre.
"""

from __future__ import annotations

import math

import numpy as np

from .._validation import check_fraction, check_int, check_positive
from .centres import cluster_centre

__all__ = ["trimmed_centre", "trimmed_medoid_index", "mad_centre"]


def trimmed_centre(manifold, points, *, rounds: int = 5, discard_fraction: float = 0.2,
                   centre: str = "medoid", min_members: int = 1, distances=None):
    """Centre by iterative trimming.

    Each round computes the centre of the current members, then keeps the
    ``1 - discard_fraction`` nearest to it. Stops after ``rounds`` rounds or
    when ``min_members`` would be crossed.

    Returns
    -------
    centre : ndarray
    members : ndarray of bool, shape (N,)
        Hypotheses kept in the last round.

    Examples
    --------
    >>> from clap_unified.geometry import Line2D
    >>> pts = np.array([[0.5, 1.0]] * 8 + [[0.1, 5.0], [1.2, -3.0]])
    >>> c, keep = trimmed_centre(Line2D(), pts, rounds=2, discard_fraction=0.2)
    >>> c.tolist(), int(keep.sum())
    ([0.5, 1.0], 7)
    """
    pts = np.asarray(points)
    rounds = check_int(rounds, "rounds", minimum=0)
    frac = check_fraction(discard_fraction, "discard_fraction")
    members = np.ones(len(pts), bool)
    if centre == "medoid" and distances is not None:
        return _trimmed_medoid(pts, np.asarray(distances, dtype=float), rounds, frac, min_members)
    c = cluster_centre(manifold, pts, centre)
    for _ in range(rounds):
        idx = np.flatnonzero(members)
        keep = max(min_members, int(np.ceil(len(idx) * (1.0 - frac))))
        if keep >= len(idx):
            break
        d = manifold.distance(c, pts[idx])
        members = np.zeros(len(pts), bool)
        members[idx[np.argsort(d, kind="stable")[:keep]]] = True
        c = cluster_centre(manifold, pts[members], centre)
    return c, members


def _trimmed_medoid(pts, dist, rounds, frac, min_members):
    best, members = trimmed_medoid_index(dist, rounds=rounds, discard_fraction=frac,
                                         min_members=min_members, n=len(pts))
    return pts[best], members


def trimmed_medoid_index(distances, *, rounds: int = 5, discard_fraction: float = 0.2,
                         min_members: int = 1, n: int | None = None):
    """Iterative trimming around the medoid, on a precomputed distance matrix.

    Parameters
    ----------
    distances : ndarray of shape (N, N)
        Pairwise distances of the points.

    Returns
    -------
    index : int
        Row of the final medoid.
    members : ndarray of bool, shape (N,)

    Examples
    --------
    >>> d = np.abs(np.subtract.outer([0.0, 0.1, 0.2, 5.0], [0.0, 0.1, 0.2, 5.0]))
    >>> i, keep = trimmed_medoid_index(d, rounds=1, discard_fraction=0.25)
    >>> i, keep.tolist()
    (1, [True, True, True, False])
    """
    dist = np.asarray(distances, dtype=float)
    n = len(dist) if n is None else n
    if dist.shape != (n, n):
        raise ValueError(f"distances: expected shape ({n}, {n}), got {dist.shape}")
    idx = np.arange(n)
    members = np.ones(n, bool)
    best = int((dist @ np.full(n, 1.0 / n)).argmin())
    for _ in range(rounds):
        keep = max(min_members, math.ceil(len(idx) * (1.0 - discard_fraction)))
        if keep >= len(idx):
            break
        idx = idx[dist[best, idx].argsort(kind="stable")[:keep]]
        idx.sort()  # the new members in index order
        members[:] = False
        members[idx] = True
        # mean distance of each member to the members (non-members weigh zero)
        best = int(idx[(dist[idx] @ (members / keep)).argmin()])
    return best, members


def mad_centre(manifold, points, *, k: float = 3.0, centre: str = "medoid", max_iter: int = 10):
    """Centre by median-absolute-deviation rejection.

    Repeatedly keeps hypotheses whose distance to the centre is at most
    ``median + k * 1.4826 * MAD`` and recomputes the centre, until the member
    set stops changing or ``max_iter`` rounds.

    Returns
    -------
    centre : ndarray
    members : ndarray of bool, shape (N,)
    """
    pts = np.asarray(points)
    k = check_positive(k, "mad_k")
    max_iter = check_int(max_iter, "max_iter", minimum=1)
    members = np.ones(len(pts), bool)
    c = cluster_centre(manifold, pts, centre)
    for _ in range(max_iter):
        d = manifold.distance(c, pts)
        med = np.median(d[members])
        mad = np.median(np.abs(d[members] - med))
        new = d <= med + k * 1.4826 * mad
        if not np.any(new) or np.array_equal(new, members):
            break
        members = new
        c = cluster_centre(manifold, pts[members], centre)
    return c, members
