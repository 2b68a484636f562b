"""Consensus building blocks checked against plain references.

Density counts and bandwidths (``clap/density.py``), trimming around the medoid
(``clap/rejection.py``), RANSAC scoring and sparse Hough peaks: the floor below
the strategies, compared with dense or loop-based references on random input.
Each docstring names the fast path and the reference.
"""

import math
from unittest import mock

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import clap_unified.clap.density as density
from clap_unified.clap.density import auto_bandwidth, knn_distance, neighbour_counts
from clap_unified.clap.rejection import trimmed_centre, trimmed_medoid_index
from clap_unified.geometry import SE2, SE3, Line2D
from clap_unified.hough.peaks import sparse_peaks
from clap_unified.ransac.ransac import score_hypotheses

REFERENCE = settings(derandomize=True, max_examples=20, deadline=None,
                     suppress_health_check=[HealthCheck.too_slow])
seeds = st.integers(0, 2**32 - 1)

MANIFOLDS = {
    "line": Line2D(length_scale=3.0),
    "SE2": SE2(angle_weight=2.0),
    "SE3-relative": SE3(angle_weight=2.0, metric="relative"),
}


def clustered(name, n, rng):
    """Points with a few tight clusters among scattered ones."""
    g = MANIFOLDS[name]
    if name == "line":
        pts = np.c_[rng.uniform(0, np.pi, n), rng.uniform(-5, 5, n)]
        k = n // 3
        pts[:k] = pts[0] + rng.normal(0, 0.02, (k, 2))
        return pts
    pts = g.random(n, rng=rng, scale=1.0)
    k = n // 3
    pts[:k] = g.exp(0.03 * rng.standard_normal((k, g.dim)), pts[0])
    pts[k:k + n // 6] = g.exp(0.05 * rng.standard_normal((n // 6, g.dim)), pts[k])
    return pts


def dense_distances(g, pts):
    """Reference distance matrix: ``distance`` one pair at a time."""
    n = len(pts)
    D = np.zeros((n, n))
    for i in range(n):
        for j in range(n):
            if i != j:
                D[i, j] = float(g.distance(pts[i], pts[j]))
    return D


@pytest.mark.parametrize("name", list(MANIFOLDS))
@REFERENCE
@given(seed=seeds, n=st.integers(2, 40), block=st.sampled_from([1, 30, 250_000]))
def test_neighbour_counts_and_knn_match_dense_reference(name, seed, n, block):
    """Fast paths: ``neighbour_counts`` and ``knn_distance`` (row blocks of
    ``pairwise_distance``; small ``PAIRWISE_BLOCK`` forces one row per block).
    Reference: the dense matrix of single-pair distances; a count of entries
    ``<= bandwidth`` per row, and the k-th smallest of each sorted row.
    Bandwidths are taken halfway between two distinct distances so rounding
    (~1e-12) cannot move an entry across; knn atol 1e-10."""
    g = MANIFOLDS[name]
    rng = np.random.default_rng(seed)
    pts = clustered(name, n, rng)
    D = dense_distances(g, pts)
    values = np.unique(D)
    cut = rng.integers(0, len(values))
    bw = values[cut] if cut + 1 == len(values) else 0.5 * (values[cut] + values[cut + 1])
    with mock.patch.object(density, "PAIRWISE_BLOCK", block):
        counts = neighbour_counts(g, pts, bw)
        k = int(rng.integers(1, max(2, n)))
        knn = knn_distance(g, pts, k)
    np.testing.assert_array_equal(counts, [sum(D[i, j] <= bw for j in range(n))
                                           for i in range(n)])
    kk = min(k, n - 1)
    np.testing.assert_allclose(knn, [sorted(row)[kk] for row in D], rtol=0, atol=1e-10)


@REFERENCE
@given(seed=seeds, n=st.integers(64, 300), quantile=st.sampled_from([0.02, 0.05, 0.1, 0.2]),
       k=st.one_of(st.none(), st.integers(1, 12)))
def test_auto_bandwidth_low_quantile_shortcut_matches_full_quantile(seed, n, quantile, k):
    """Fast path: ``auto_bandwidth(..., distances=D)`` with the low-quantile shortcut
    (``_low_quantile_of_knn``: one counting pass, only the rows that matter
    partitioned). Reference: ``np.quantile`` of the k-th smallest of every sorted
    row, with the fallback to the smallest positive k-NN distance when that is 0.
    Exact equality (the docstring promises the same value)."""
    g = MANIFOLDS["SE2"]
    rng = np.random.default_rng(seed)
    pts = clustered("SE2", n, rng)
    D = g.pairwise_distance(pts)
    kk = max(3, math.ceil(0.01 * n)) if k is None else k
    kk = min(kk, n - 1)
    knn = np.sort(D, axis=1)[:, kk]
    ref = float(np.quantile(knn, quantile))
    if not ref > 0:
        ref = float(np.min(knn[knn > 0], initial=np.inf))
    assert auto_bandwidth(g, pts, k=k, quantile=quantile, distances=D) == ref
    assert auto_bandwidth(g, pts, k=k, quantile=quantile) == pytest.approx(ref, rel=1e-12)


def test_auto_bandwidth_shortcut_with_duplicates_matches_full_quantile():
    """Fast path: the low-quantile shortcut when many k-NN distances are exactly 0
    (duplicate hypotheses). Reference: the smallest positive k-NN distance of the
    sorted rows (the documented fallback)."""
    g = MANIFOLDS["SE2"]
    rng = np.random.default_rng(3)
    pts = clustered("SE2", 200, rng)
    pts[:60] = pts[0]
    D = g.pairwise_distance(pts)
    knn = np.sort(D, axis=1)[:, 3]
    ref = float(np.quantile(knn, 0.1))
    ref = ref if ref > 0 else float(np.min(knn[knn > 0]))
    assert auto_bandwidth(g, pts, k=3, quantile=0.1, distances=D) == ref


def ref_trimmed_medoid(D, rounds, frac, min_members):
    """Plain trimming loop: medoid = member with the least summed distance to the
    members (lowest index on ties); each round keep the ceil((1 - frac) |members|)
    members nearest to the medoid (by distance, then index)."""
    n = len(D)
    members = list(range(n))
    best = min(members, key=lambda i: (sum(D[i][j] for j in members), i))
    for _ in range(rounds):
        keep = max(min_members, math.ceil(len(members) * (1.0 - frac)))
        if keep >= len(members):
            break
        members = sorted(sorted(members, key=lambda j: (D[best][j], j))[:keep])
        best = min(members, key=lambda i: (sum(D[i][j] for j in members), i))
    mask = np.zeros(n, bool)
    mask[members] = True
    return best, mask


@REFERENCE
@given(seed=seeds, n=st.integers(1, 60), rounds=st.integers(0, 6),
       frac=st.sampled_from([0.0, 0.1, 0.2, 0.5, 0.9]), min_members=st.integers(1, 5))
def test_trimmed_medoid_index_matches_plain_trimming_loop(seed, n, rounds, frac, min_members):
    """Fast path: ``trimmed_medoid_index`` (index arrays, one matrix-vector product
    per round). Reference: the plain trimming loop above on Python lists.
    Distances are random Euclidean (no ties beyond the zero diagonal): exact
    equality of the medoid and the member mask."""
    rng = np.random.default_rng(seed)
    x = rng.normal(size=(n, 3))
    x[: n // 2] *= 0.05
    D = np.linalg.norm(x[:, None] - x[None], axis=-1)
    best, members = trimmed_medoid_index(D, rounds=rounds, discard_fraction=frac,
                                         min_members=min_members)
    ref_best, ref_members = ref_trimmed_medoid(D.tolist(), rounds, frac, min_members)
    assert best == ref_best
    np.testing.assert_array_equal(members, ref_members)


@REFERENCE
@given(seed=seeds, n=st.integers(2, 50))
def test_trimmed_centre_with_distances_matches_manifold_route(seed, n):
    """Fast path: ``trimmed_centre(..., distances=D)`` (the precomputed-matrix
    medoid route). Reference: ``trimmed_centre`` without ``distances`` (medoid by
    the manifold, distances to the centre by ``manifold.distance`` each round).
    Same centre and members (exact; random SE(2) poses have no ties)."""
    g = MANIFOLDS["SE2"]
    rng = np.random.default_rng(seed)
    pts = clustered("SE2", n, rng)
    D = g.pairwise_distance(pts)
    c1, m1 = trimmed_centre(g, pts, rounds=5, discard_fraction=0.2, distances=D)
    c2, m2 = trimmed_centre(g, pts, rounds=5, discard_fraction=0.2)
    np.testing.assert_array_equal(m1, m2)
    np.testing.assert_array_equal(c1, c2)


@REFERENCE
@given(seed=seeds, h=st.integers(0, 20), n=st.integers(0, 30))
def test_score_hypotheses_matches_loop(seed, h, n):
    """Fast path: ``ransac.score_hypotheses`` (``inliers`` and ``msac``, vectorised
    over the residual matrix). Reference: per row a Python loop counting
    ``r < t`` and summing ``min(r^2, t^2)``. Counts exact; MSAC rtol 1e-12
    (summation order)."""
    rng = np.random.default_rng(seed)
    r = rng.exponential(1.0, (h, n))
    if r.size:
        r[rng.random(r.shape) < 0.1] = np.inf
    t = float(rng.uniform(0.1, 2.0))
    inl = score_hypotheses(r, t, "inliers")
    msac = score_hypotheses(r, t, "msac")
    for i in range(h):
        assert inl[i] == sum(1 for v in r[i] if v < t)
        ref = -sum(min(v * v, t * t) for v in r[i])
        assert msac[i] == pytest.approx(ref, rel=1e-12, abs=1e-12)


def ref_sparse_peaks(cells, counts, min_distance, num_peaks, min_count):
    """Plain greedy suppression: take the fullest remaining cell (lowest index on
    ties), drop every cell within Chebyshev distance ``min_distance`` of it."""
    alive = [i for i in range(len(cells)) if counts[i] >= min_count]
    out = []
    while alive and len(out) < num_peaks:
        best = max(alive, key=lambda i: (counts[i], -i))
        out.append(best)
        alive = [i for i in alive
                 if max(abs(int(a) - int(b)) for a, b in zip(cells[i], cells[best], strict=True))
                 > min_distance]
    return out


@REFERENCE
@given(seed=seeds, c=st.integers(0, 80), d=st.integers(1, 6), min_distance=st.integers(0, 3),
       num_peaks=st.integers(1, 10), min_count=st.integers(1, 4))
def test_sparse_peaks_matches_plain_greedy_search(seed, c, d, min_distance, num_peaks,
                                                  min_count):
    """Fast path: ``hough.peaks.sparse_peaks`` (masked argmax and vectorised
    Chebyshev suppression). Reference: the plain greedy loop above over Python
    lists, ties to the lowest index. Exact equality of the peak indices."""
    rng = np.random.default_rng(seed)
    cells = rng.integers(-4, 5, (c, d))
    counts = rng.integers(1, 8, c)
    out = sparse_peaks(cells, counts, min_distance=min_distance, num_peaks=num_peaks,
                       min_count=min_count)
    ref = ref_sparse_peaks(cells.tolist(), counts.tolist(), min_distance, num_peaks, min_count)
    assert out.tolist() == ref


@REFERENCE
@given(seed=seeds, n=st.integers(2, 120), min_count=st.integers(1, 8))
def test_dense_candidates_matches_dense_chordal_count(seed, n, min_count):
    """Fast path: ``density.dense_candidates`` (k-d tree on the SE(3) chordal
    embedding). Reference: the dense matrix of Euclidean distances between the
    embeddings counted per row, and, by the documented bound (chordal <= relative),
    every pose with ``min_count`` poses within ``radius`` in the ``relative``
    metric (single-pair ``distance`` loop) must be returned. Radius taken halfway
    between two distinct chordal distances (no rounding ties)."""
    dense_candidates = getattr(density, "dense_candidates", None)
    if dense_candidates is None:
        pytest.skip("density.dense_candidates not present in this version")
    g = MANIFOLDS["SE3-relative"]
    rng = np.random.default_rng(seed)
    pts = clustered("SE3-relative", n, rng)
    emb = g.chordal_embedding(pts)
    E = np.array([[np.sqrt(sum((a - b) ** 2)) for b in emb] for a in emb])
    values = np.unique(E)
    cut = int(rng.integers(0, len(values) - 1))
    radius = 0.5 * (values[cut] + values[cut + 1])
    fast = dense_candidates(g, pts, radius, min_count)
    ref = [i for i in range(n) if sum(E[i] <= radius) >= min_count]
    np.testing.assert_array_equal(fast, ref)
    D = dense_distances(g, pts)
    must = {i for i in range(n) if sum(D[i] <= radius * (1 - 1e-9)) >= min_count}
    assert must <= set(fast.tolist())
