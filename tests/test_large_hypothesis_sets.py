"""CLAP on large hypothesis sets: exact neighbour queries on a k-d tree, bounded memory.

An embedding whose Euclidean distance bounds the manifold's distance below (SE(2), SE(3))
lets a k-d tree propose neighbours that the distance then checks: the answers must be those
of the distance itself. Giant clusters (every hypothesis the same) must not build an
``H x H`` matrix, and RANSAC's chunked scoring must not change its result.
"""

import importlib
import tracemalloc

import numpy as np
import pytest

from clap_unified.clap.density import EmbeddedNeighbours
from clap_unified.fitting import fit_line
from clap_unified.geometry import SE2, SE3
from clap_unified.localization.localize2d import localize2d
from clap_unified.maps.field import load_field
from clap_unified.spaces import LineSpace

clap_module = importlib.import_module("clap_unified.clap.clap")
ransac_module = importlib.import_module("clap_unified.ransac.ransac")


def _se2_poses(rng, n):
    """Poses in clumps (a few tight clusters) and scattered, headings all round."""
    centres = rng.uniform([-7, -4.5, -np.pi], [7, 4.5, np.pi], (6, 3))
    clumped = centres[rng.integers(0, 6, n // 2)] + rng.normal(0, [0.1, 0.1, 0.1], (n // 2, 3))
    spread = rng.uniform([-7, -4.5, -np.pi], [7, 4.5, np.pi], (n - n // 2, 3))
    xyt = np.r_[clumped, spread]
    return SE2.from_xytheta(xyt[:, 0], xyt[:, 1], xyt[:, 2])


@pytest.mark.parametrize("manifold", [SE2(), SE2(angle_weight=3.0), SE3(0.5),
                                      SE3(2.0, metric="relative")], ids=repr)
def test_the_chordal_embedding_never_exceeds_the_distance(manifold):
    rng = np.random.default_rng(0)
    if isinstance(manifold, SE2):
        a, b = _se2_poses(rng, 2000), _se2_poses(rng, 2000)
    else:
        a = manifold.expmap(rng.normal(0, 1.5, (2000, 6)))
        b = manifold.expmap(rng.normal(0, 1.5, (2000, 6)))
    assert manifold.embedding_bounds_distance
    emb = np.linalg.norm(manifold.chordal_embedding(a) - manifold.chordal_embedding(b), axis=1)
    d = manifold.distance(a, b)
    assert np.all(emb <= d * (1 + 1e-12))
    assert np.any(emb < 0.99 * d)  # a bound, not the distance


def test_point_set_metric_declares_no_bound():
    g = SE3(metric="point_set", reference_points=np.eye(3))
    assert not g.embedding_bounds_distance
    with pytest.raises(ValueError, match="manifold"):
        EmbeddedNeighbours(g, g.identity((3,)))


@pytest.mark.parametrize("manifold", [SE2(), SE2(angle_weight=3.0)], ids=repr)
def test_tree_answers_are_those_of_the_distance(manifold):
    rng = np.random.default_rng(1)
    T = _se2_poses(rng, 700)
    D = manifold.distance(T[:, None], T[None, :])  # d(row, col), every pair both ways
    nb = EmbeddedNeighbours(manifold, T)
    for radius in (0.05, 0.3, 1.7):
        assert np.array_equal(nb.counts(radius), np.count_nonzero(D <= radius, axis=1))
        for i in (0, 5, 400):
            assert np.array_equal(nb.ball(i, radius), np.flatnonzero(D[i] <= radius))
        centre = T[3] @ manifold.from_xytheta(0.01, -0.02, 0.03)
        assert np.array_equal(nb.ball_of(centre, radius),
                              np.flatnonzero(manifold.distance(centre, T) <= radius))
    for k in (1, 3, 20):
        assert np.allclose(nb.knn(k), np.partition(D, k, axis=1)[:, k], rtol=1e-12, atol=0)
        rows = np.array([7, 3, 600])
        assert np.array_equal(nb.knn(k, rows), nb.knn(k)[rows])
    assert np.allclose(nb.pairwise([1, 2, 9]), D[np.ix_([1, 2, 9], [1, 2, 9])], rtol=1e-12)


def test_localization_beyond_the_dense_limit_is_that_of_the_blocked_distances(monkeypatch):
    """Above ``DENSE_LIMIT`` candidates the k-d tree replaces blocks of exact distances: the
    estimate, its clusters and their support are unchanged."""
    field = load_field("adult")
    rng = np.random.default_rng(3)
    xy = rng.uniform(-5, 5, (40, 2))
    data = np.c_[np.zeros(len(xy)), xy]  # all of type L (id 0): many candidates
    monkeypatch.setattr(clap_module, "DENSE_LIMIT", 1500)
    tree = localize2d(data, field, rng=0)
    assert tree.diagnostics["hypotheses"] > 1500
    monkeypatch.setattr(SE2, "embedding_bounds_distance", False)
    blocked = localize2d(data, field, rng=0)
    assert np.array_equal(tree.model, blocked.model)
    assert [c.support for c in tree.clusters] == [c.support for c in blocked.clusters]
    assert all(np.array_equal(a.model, b.model)
               for a, b in zip(tree.clusters, blocked.clusters, strict=True))


def test_one_giant_cluster_needs_no_square_matrix():
    """Every pair of points on an exact line gives the same hypothesis (to rounding): 44850
    of them, in a few clusters of thousands. A matrix among them would take 16 GB."""
    x = np.linspace(0.0, 10.0, 300)
    pts = np.c_[x, 2 * x + 1]
    tracemalloc.start()
    try:
        res = fit_line(pts, "clap", n_hypotheses=50_000, rng=0)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert res.success and res.n_inliers == 300
    assert res.clusters[0].support > clap_module.DENSE_LIMIT  # centred on a subset
    assert peak < 400 * 2**20
    normal, offset = res.space.model_to_dict(res.model).values()
    assert -normal[0] / normal[1] == pytest.approx(2.0) and offset / normal[1] == pytest.approx(1)


def test_ransac_scores_in_chunks_without_changing_its_answer(monkeypatch):
    rng = np.random.default_rng(4)
    x = rng.uniform(-5, 5, 400)
    pts = np.c_[x, 0.5 * x + 1 + rng.normal(0, 0.02, 400)]
    pts[:250] = rng.uniform(-5, 5, (250, 2))
    space = LineSpace.for_data(pts)
    whole = ransac_module.ransac(space, pts, threshold=0.05, rng=7, n_hypotheses=300)
    monkeypatch.setattr(ransac_module, "SCORE_BLOCK", 1000)  # 2 hypotheses a chunk
    chunked = ransac_module.ransac(space, pts, threshold=0.05, rng=7, n_hypotheses=300)
    assert np.array_equal(whole.model, chunked.model)
    assert whole.score == chunked.score
    assert whole.diagnostics["best_hypothesis"] == chunked.diagnostics["best_hypothesis"]
