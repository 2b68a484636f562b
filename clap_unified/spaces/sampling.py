"""Generating hypotheses: random minimal samples, or every subset when few."""

from __future__ import annotations

from itertools import combinations
from math import comb

import numpy as np

from .._validation import as_generator, check_choice, check_int
from .base import HypothesisSet, HypothesisSpace

__all__ = ["generate_hypotheses", "enumerate_hypotheses", "sample_subsets",
           "unsolved_samples"]


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


def enumerate_hypotheses(space: HypothesisSpace, data) -> HypothesisSet:
    """Solve every ``min_samples``-subset of ``data`` (use only when that is small).

    Examples
    --------
    >>> from clap_unified.spaces import LineSpace
    >>> pts = np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0], [0.0, 1.0]])
    >>> hs = enumerate_hypotheses(LineSpace(), pts)
    >>> len(hs), hs.n_draws, hs.exhaustive
    (6, 6, True)
    """
    data = space.check_data(data)
    idx = np.array(list(combinations(range(len(data)), space.min_samples)), dtype=np.intp)
    idx = idx.reshape(-1, space.min_samples)
    models, owner = space.solve_minimal(data, idx)
    n_bad = unsolved_samples(len(idx), owner)
    return HypothesisSet(models, idx[owner], len(idx), n_bad, True, space)


def generate_hypotheses(space: HypothesisSpace, data, n: int = 1000, *, rng=None,
                        exhaustive="auto", max_draws: int | None = None,
                        batch_size: int | None = None) -> HypothesisSet:
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
    data = space.check_data(data)
    n = check_int(n, "n", minimum=1)
    if exhaustive not in ("auto", True, False):
        check_choice(exhaustive, "exhaustive", {"auto", True, False})
    m = space.min_samples
    n_subsets = comb(len(data), m)
    if exhaustive is True or (exhaustive == "auto" and n_subsets <= n):
        return enumerate_hypotheses(space, data)
    max_draws = 10 * n if max_draws is None else check_int(max_draws, "max_draws", minimum=1)
    batch = n if batch_size is None else check_int(batch_size, "batch_size", minimum=1)
    g = as_generator(rng)
    models, samples = [], []
    found = drawn = bad = 0
    while found < n and drawn < max_draws:
        k = min(batch, max_draws - drawn)
        idx = sample_subsets(len(data), m, k, rng=g)
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
