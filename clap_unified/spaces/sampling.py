"""Generating hypotheses: random minimal samples, or every subset when few."""

from __future__ import annotations

from itertools import combinations
from math import comb

import numpy as np

from .._validation import Checked, as_generator, check_choice, check_int, unwrap_checked
from .hypothesis_set import HypothesisSet

__all__ = ["generate_hypotheses", "enumerate_hypotheses", "sample_local_subsets",
           "sample_subsets", "unsolved_samples"]


def sample_subsets(n_data: int, size: int, n_samples: int, *, rng=None) -> np.ndarray:
    """Uniformly random subsets of distinct indices, one per row.

    Uses Floyd's algorithm vectorised over rows: exact, no rejection loop.

    Parameters
    ----------
    n_data : int
        Indices are drawn from ``range(n_data)``.
    size : int
        Indices per subset (``size <= n_data``).
    n_samples : int
        Number of subsets.
    rng : None, int or numpy.random.Generator

    Returns
    -------
    ndarray of int, shape (n_samples, size)

    Examples
    --------
    >>> s = sample_subsets(10, 3, 5, rng=0)
    >>> s.shape, bool(np.all(np.sort(s, axis=1)[:, 1:] != np.sort(s, axis=1)[:, :-1]))
    ((5, 3), True)
    """
    n_data = check_int(n_data, "n_data", minimum=1)
    size = check_int(size, "size", minimum=1)
    n_samples = check_int(n_samples, "n_samples", minimum=0)
    if size > n_data:
        raise ValueError(f"size: cannot draw {size} distinct indices from {n_data}")
    g = as_generator(rng)
    out = np.empty((size, n_samples), dtype=np.intp)  # column-major while filling
    for j in range(size):
        top = n_data - size + j  # draw from [0, top]
        r = g.integers(0, top + 1, size=n_samples)
        if j:
            taken = out[0] == r
            for k in range(1, j):
                taken |= out[k] == r
            r[taken] = top
        out[j] = r
    return out.T.copy()


def sample_local_subsets(coords, size: int, n_samples: int, neighbours: int, *,
                         rng=None) -> np.ndarray:
    """Random subsets drawn near each other: a seed, then others among its nearest data.

    NAPSAC-style local sampling (Myatt et al., BMVC 2002): structures are
    spatially coherent, so a minimal sample drawn around one datum lies on
    one structure far more often than a uniform one. Each row is a uniformly
    random seed datum and ``size - 1`` distinct others drawn uniformly from
    its ``neighbours`` nearest data (by ``coords``, on a k-d tree).

    Parameters
    ----------
    coords : ndarray of shape (N, d)
        Where each datum is (e.g. a match's coordinates in both images).
    size : int
        Indices per subset.
    n_samples : int
    neighbours : int
        Neighbourhood size, the seed excluded (at least ``size - 1``; capped
        at ``N - 1``).
    rng : None, int or numpy.random.Generator

    Returns
    -------
    ndarray of int, shape (n_samples, size)
        The seed first in each row.

    Examples
    --------
    >>> pts = np.c_[np.arange(100.0), np.zeros(100)]
    >>> s = sample_local_subsets(pts, 3, 4, neighbours=5, rng=0)
    >>> s.shape, bool(np.all(np.ptp(s, axis=1) <= 10))
    ((4, 3), True)
    """
    from scipy.spatial import cKDTree

    coords = np.asarray(coords, dtype=float)
    if coords.ndim != 2 or not np.all(np.isfinite(coords)):
        raise ValueError(f"coords: expected finite coordinates of shape (N, d), "
                         f"got shape {coords.shape}")
    n_data = len(coords)
    size = check_int(size, "size", minimum=1)
    n_samples = check_int(n_samples, "n_samples", minimum=0)
    if size > n_data:
        raise ValueError(f"size: cannot draw {size} distinct indices from {n_data}")
    neighbours = check_int(neighbours, "neighbours", minimum=size - 1)
    g = as_generator(rng)
    places, place_of = np.unique(coords, axis=0, return_inverse=True)
    if len(places) < n_data:  # repeated rows: neighbours are other places, not copies
        return _local_subsets_of_places(places, place_of.reshape(-1), size, n_samples,
                                        neighbours, g)
    neighbours = min(neighbours, n_data - 1)
    # neighbours + 1 nearest (the seed itself among them), the seed put first in every row
    _, near = cKDTree(coords).query(coords, k=neighbours + 1)
    near = np.asarray(near).reshape(n_data, neighbours + 1)
    own = near == np.arange(n_data)[:, None]
    own[~own.any(axis=1), -1] = True  # equidistant ties: the seed may not be listed
    near = np.concatenate([np.arange(n_data)[:, None],
                           near[~own].reshape(n_data, neighbours)], axis=1)
    seeds = g.integers(0, n_data, size=n_samples)
    pick = sample_subsets(neighbours, size - 1, n_samples, rng=g) + 1 if size > 1 else \
        np.empty((n_samples, 0), dtype=np.intp)
    return np.c_[seeds, near[seeds[:, None], pick]].astype(np.intp)


def _local_subsets_of_places(places, place_of, size, n_samples, neighbours, g):
    """Local subsets when rows repeat: a seed row, then rows at other nearby places.

    Each other member is a random row at one of the seed's ``neighbours``
    nearest distinct places; with fewer distinct places than ``size`` every
    sample repeats a place (and is degenerate, as the data are).
    """
    from scipy.spatial import cKDTree

    n_data, n_places = len(place_of), len(places)
    order = np.argsort(place_of, kind="stable")
    counts = np.bincount(place_of, minlength=n_places)
    starts = np.r_[0, np.cumsum(counts)[:-1]]
    seeds = g.integers(0, n_data, size=n_samples)
    if size == 1:
        return seeds[:, None].astype(np.intp)
    k = min(neighbours, n_places - 1)
    if k < size - 1:  # too few places: draw among all rows (samples repeat places)
        return np.c_[seeds, sample_subsets(n_data, size - 1, n_samples, rng=g)].astype(np.intp)
    _, near = cKDTree(places).query(places, k=k + 1)
    near = np.asarray(near).reshape(n_places, k + 1)
    own = near == np.arange(n_places)[:, None]
    own[~own.any(axis=1), -1] = True
    near = near[~own].reshape(n_places, k)
    picked = near[place_of[seeds][:, None], sample_subsets(k, size - 1, n_samples, rng=g)]
    rows = order[starts[picked] + (g.random(picked.shape) * counts[picked]).astype(np.intp)]
    return np.c_[seeds, rows].astype(np.intp)


def unsolved_samples(k: int, owner) -> int:
    """How many of ``k`` samples gave no model, from ``solve_minimal``'s ``owner`` indices.

    A sample may give several models (its index then repeats in ``owner``).

    Examples
    --------
    >>> unsolved_samples(5, np.array([0, 2, 2, 4]))
    2
    """
    return k - int(np.count_nonzero(np.bincount(np.asarray(owner, dtype=np.intp),
                                                minlength=k)))


def enumerate_hypotheses(space, data) -> HypothesisSet:
    """Solve every ``min_samples``-subset of ``data`` (use only when that is small).

    Examples
    --------
    >>> from clap_unified.spaces import LineSpace
    >>> pts = np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0], [0.0, 1.0]])
    >>> hs = enumerate_hypotheses(LineSpace(), pts)
    >>> len(hs), hs.n_draws, hs.exhaustive
    (6, 6, True)
    """
    data = unwrap_checked(data, space.check_data)
    idx = np.array(list(combinations(range(len(data)), space.min_samples)), dtype=np.intp)
    idx = idx.reshape(-1, space.min_samples)
    models, owner = space.solve_minimal(data, idx)
    n_bad = unsolved_samples(len(idx), owner)
    return HypothesisSet(models, idx[owner], len(idx), n_bad, True, space)


def generate_hypotheses(space, data, n: int = 1000, *, rng=None,
                        exhaustive="auto", max_draws: int | None = None,
                        batch_size: int | None = None, neighbours: int | None = None,
                        coords=None) -> HypothesisSet:
    """Candidate models from random minimal samples of ``data``.

    Draws minimal samples in batches, solves them all at once with
    ``space.solve_minimal`` and keeps going until ``n`` models were found or
    ``max_draws`` samples were drawn.

    Parameters
    ----------
    space : HypothesisSpace
    data : array_like
        Data in the format ``space.check_data`` accepts.
    n : int
        Number of hypotheses wanted.
    rng : None, int or numpy.random.Generator
        Seed or generator; the same seed gives the same hypotheses.
    exhaustive : {"auto", True, False}
        ``True`` enumerates every subset; ``"auto"`` does so when there are no
        more than ``n`` subsets.
    max_draws : int, optional
        Cap on minimal samples drawn (default ``10 * n``): degenerate data
        cannot loop forever.
    batch_size : int, optional
        Samples solved per batch (default ``n``).
    neighbours : int, optional
        Local sampling (:func:`~clap_unified.spaces.sampling.sample_local_subsets`):
        each sample is a seed and others among its ``neighbours`` nearest data by ``coords``
        (default the data's rows flattened). Never exhaustive.
    coords : ndarray of shape (N, d), optional

    Returns
    -------
    HypothesisSet
        May hold fewer than ``n`` models when too many samples were degenerate
        (``n_degenerate`` says how many).

    Examples
    --------
    >>> from clap_unified.spaces import LineSpace
    >>> rng = np.random.default_rng(0)
    >>> pts = rng.uniform(0, 10, size=(50, 2))
    >>> hs = generate_hypotheses(LineSpace(), pts, 200, rng=1)
    >>> hs.models.shape, hs.samples.shape, hs.exhaustive
    ((200, 2), (200, 2), False)
    """
    data = unwrap_checked(data, space.check_data)
    n = check_int(n, "n", minimum=1)
    if exhaustive not in ("auto", True, False):
        check_choice(exhaustive, "exhaustive", {"auto", True, False})
    m = space.min_samples
    n_subsets = comb(len(data), m)
    if neighbours is None and (exhaustive is True or (exhaustive == "auto" and n_subsets <= n)):
        return enumerate_hypotheses(space, Checked(data))
    if neighbours is not None:
        coords = (np.asarray(data, dtype=float).reshape(len(data), -1) if coords is None
                  else coords)
        if len(coords) != len(data):
            raise ValueError(f"coords: expected {len(data)} rows, one per datum, "
                             f"got {len(coords)}")
    max_draws = 10 * n if max_draws is None else check_int(max_draws, "max_draws", minimum=1)
    batch = n if batch_size is None else check_int(batch_size, "batch_size", minimum=1)
    g = as_generator(rng)
    models, samples = [], []
    found = drawn = bad = 0
    while found < n and drawn < max_draws:
        k = min(batch, max_draws - drawn)
        idx = (sample_subsets(len(data), m, k, rng=g) if neighbours is None else
               sample_local_subsets(coords, m, k, neighbours, rng=g))
        mod, owner = space.solve_minimal(data, idx)
        drawn += k
        bad += unsolved_samples(k, owner)
        take = min(len(mod), n - found)
        models.append(mod[:take])
        samples.append(idx[owner[:take]])
        found += take
    shape = (0, *space.model_shape)
    models = np.concatenate(models) if models else np.empty(shape)
    samples = np.concatenate(samples) if samples else np.empty((0, m), dtype=np.intp)
    return HypothesisSet(models, samples, drawn, bad, False, space)
