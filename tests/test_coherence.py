"""Spatial coherence: the Potts labelling by graph cuts and the coherent finish of ``segment``."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from clap_unified import LineSpace, segment
from clap_unified.coherence import (
    coherent_labels,
    expand_labels,
    neighbour_graph,
    potts_energy,
)
from clap_unified.partition import assign_labels, refit_partition


def _brute_force(costs, edges, weight):
    n_labels, n = costs.shape
    return min(potts_energy(costs, edges, weight, np.array(lab))
               for lab in itertools.product(range(n_labels), repeat=n))


@settings(max_examples=60, deadline=None)
@given(st.integers(2, 3), st.integers(2, 6), st.floats(0.0, 2.0), st.integers(0, 2**31 - 1))
def test_expansion_never_raises_the_energy_and_stays_within_twice_the_optimum(
        n_labels, n, weight, seed):
    rng = np.random.default_rng(seed)
    costs = rng.uniform(0, 1, (n_labels, n))
    edges = np.array([(i, j) for i in range(n) for j in range(i + 1, n)
                      if rng.uniform() < 0.6], dtype=np.intp).reshape(-1, 2)
    start = rng.integers(0, n_labels, n)
    out = expand_labels(costs, edges, weight, start)
    e_out = potts_energy(costs, edges, weight, out)
    assert e_out <= potts_energy(costs, edges, weight, start) + 1e-12
    # alpha-expansion's bound for the Potts model: within twice the optimum
    assert e_out <= 2 * _brute_force(costs, edges, weight) + 1e-9


def test_expansion_finds_the_optimum_of_a_chain():
    # a chain that prefers label 0 except one datum slightly; a strong edge weight wins
    costs = np.array([[0, 0, 0.6, 0, 0], [1, 1, 0.4, 1, 1]], float)
    edges = np.array([[0, 1], [1, 2], [2, 3], [3, 4]])
    assert expand_labels(costs, edges, 0.5, costs.argmin(axis=0)).tolist() == [0] * 5
    # with a weak one each datum keeps its own cheapest label
    assert expand_labels(costs, edges, 0.05, costs.argmin(axis=0)).tolist() == [0, 0, 1, 0, 0]


def test_neighbour_graph_is_symmetric_free_of_self_loops_and_handles_duplicates():
    pts = np.array([[0.0, 0], [0, 0], [1, 0], [5, 5]])
    edges = neighbour_graph(pts, 2)
    assert np.all(edges[:, 0] < edges[:, 1])
    assert len(np.unique(edges, axis=0)) == len(edges)
    assert [0, 1] in edges.tolist()           # the duplicates are neighbours
    assert neighbour_graph(pts[:1], 3).shape == (0, 2)
    with pytest.raises(ValueError, match="k"):
        neighbour_graph(pts, 0)


def test_zero_weight_is_the_nearest_model():
    rng = np.random.default_rng(1)
    pts = rng.uniform(-3, 3, (80, 2))
    lines = np.array([[np.pi / 2, 0.0], [0.3, 1.0], [2.0, -0.5]])
    edges = neighbour_graph(pts, 6)
    np.testing.assert_array_equal(coherent_labels(LineSpace(), lines, pts, 0.4, edges, 0.0),
                                  assign_labels(LineSpace(), lines, pts, 0.4))


def test_no_datum_joins_a_model_beyond_the_threshold():
    rng = np.random.default_rng(2)
    x = rng.uniform(-5, 5, 60)
    pts = np.c_[x, np.where(np.arange(60) < 30, 0.0, 1.0) + rng.normal(0, 0.05, 60)]
    lines = np.array([[np.pi / 2, 0.0], [np.pi / 2, 1.0]])
    labels = coherent_labels(LineSpace(), lines, pts, 0.2, neighbour_graph(pts, 8), 5.0)
    r = LineSpace().residuals(lines, pts)
    on = labels >= 0
    assert np.all(r[labels[on], np.flatnonzero(on)] < 0.2)


def _two_bands():
    """Two horizontal lines 0.3 apart; points of each line come in a region of their own."""
    rng = np.random.default_rng(3)
    x0, x1 = rng.uniform(-5, 0, 60), rng.uniform(0, 5, 60)
    pts = np.r_[np.c_[x0, 0.0 + rng.normal(0, 0.08, 60)],
                np.c_[x1, 0.3 + rng.normal(0, 0.08, 60)]]
    truth = np.r_[np.zeros(60, int), np.ones(60, int)]
    return pts, truth


def test_coherence_repairs_labels_that_the_nearest_model_mixes():
    pts, truth = _two_bands()
    lines = np.array([[np.pi / 2, 0.0], [np.pi / 2, 0.3]])
    near = refit_partition(LineSpace(), lines, pts, 0.3, 10)[1]
    coh = refit_partition(LineSpace(), lines, pts, 0.3, 10, coherence=0.5,
                          edges=neighbour_graph(pts, 8))[1]
    assert np.mean(coh == truth) > np.mean(near == truth) + 0.05
    assert np.mean(coh == truth) > 0.95


def test_refit_partition_needs_the_graph_for_coherence():
    pts, _ = _two_bands()
    with pytest.raises(ValueError, match="edges"):
        refit_partition(LineSpace(), np.array([[np.pi / 2, 0.0]]), pts, 0.3, 10, coherence=0.1)


def test_segment_coherence_is_deterministic_and_checked():
    pts, truth = _two_bands()
    space = LineSpace.for_data(pts)
    a = segment(space, pts, "ransac", threshold=0.3, rng=0, coherence=0.5)
    b = segment(space, pts, "ransac", threshold=0.3, rng=0, coherence=0.5)
    np.testing.assert_array_equal(a.labels, b.labels)
    np.testing.assert_array_equal(a.models, b.models)
    assert a.diagnostics["coherence"] == 0.5
    with pytest.raises(ValueError, match="coherence"):
        segment(space, pts, "ransac", threshold=0.3, coherence=-1)
    with pytest.raises(ValueError, match="coherence_neighbours"):
        segment(space, pts, "ransac", threshold=0.3, coherence=0.5, coherence_neighbours=0)
