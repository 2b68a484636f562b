"""The library's default CLAP for homographies: anchor-transfer distance, k-d tree density,
seeds by k-th neighbour distance, clusters chosen by consensus (issue 14)."""

import math

import numpy as np
import pytest

from clap_unified import fit
from clap_unified.clap.density import EmbeddedNeighbours, auto_bandwidth, knn_distance
from clap_unified.fitting import ALL_INLIER_SAMPLES
from clap_unified.geometry.homography_transfer import HomographyTransfer, region_anchors
from clap_unified.imaging import PROTOCOLS, estimate_homography
from clap_unified.imaging.estimate import method_names, strategy_of
from clap_unified.imaging.metrics import symmetric_reprojection_error
from clap_unified.spaces import HomographySpace


def _random_h(rng, n):
    H = np.eye(3) + rng.normal(0, [[0.05, 0.05, 20], [0.05, 0.05, 20], [1e-5, 1e-5, 0]],
                               (n, 3, 3))
    return H / H[:, 2:, 2:]


def test_transfer_distance_is_the_rms_anchor_distance():
    rng = np.random.default_rng(0)
    A = rng.uniform(0, 640, (5, 2))
    g = HomographyTransfer(A)
    H = _random_h(rng, 6)
    for i in range(6):
        for j in range(6):
            pa = np.c_[A, np.ones(5)] @ H[i].T
            pb = np.c_[A, np.ones(5)] @ H[j].T
            d = np.sqrt(np.mean(np.sum((pa[:, :2] / pa[:, 2:] - pb[:, :2] / pb[:, 2:]) ** 2, 1)))
            assert g.distance(H[i], H[j]) == pytest.approx(d, rel=1e-9, abs=1e-9)
    D = g.pairwise_distance(H)
    assert np.allclose(D, D.T) and np.all(np.diag(D) == 0)
    assert np.allclose(D, g.distance(H[:, None], H[None]), atol=1e-9)


def test_a_homography_sending_an_anchor_behind_the_camera_has_no_embedding():
    g = HomographyTransfer(np.array([[0.0, 0.0], [100.0, 0.0]]))
    flip = np.array([[1.0, 0, 0], [0, 1, 0], [-0.02, 0, 1]])  # w = 1 - 0.02 x < 0 at x = 100
    assert np.all(np.isnan(g.chordal_embedding(flip)))
    assert g.distance(np.eye(3), flip) == np.inf
    D = g.pairwise_distance(np.stack([np.eye(3), flip]))
    assert D[0, 0] == 0 and np.isinf(D[0, 1]) and np.isinf(D[1, 1])


def test_region_anchors_reject_bad_margins():
    with pytest.raises(ValueError, match="margin"):
        region_anchors(np.zeros((3, 2)), margin=0.5)
    with pytest.raises(ValueError, match="points"):
        region_anchors(np.zeros((0, 2)))


def test_tree_neighbours_agree_with_the_distance_matrix():
    rng = np.random.default_rng(1)
    g = HomographyTransfer(rng.uniform(0, 640, (5, 2)))
    H = _random_h(rng, 300)
    D = g.pairwise_distance(H)
    nb = EmbeddedNeighbours(g, H)
    r = float(np.quantile(D, 0.05))
    assert np.array_equal(nb.counts(r), np.count_nonzero(D <= r, axis=1))
    assert np.allclose(nb.knn(3), knn_distance(g, H, 3, distances=D))
    assert nb.auto_bandwidth(quantile=0.1) == pytest.approx(
        auto_bandwidth(g, H, quantile=0.1, distances=D))
    assert np.array_equal(nb.ball(0, r), np.flatnonzero(D[0] <= r))


def _decoy_pair(seed, inliers=120, decoys=80, outliers=200):
    rng = np.random.default_rng(seed)
    H1 = np.array([[0.95, 0.1, 30.0], [-0.08, 1.02, -12.0], [2e-5, 1e-5, 1.0]])
    H2 = np.array([[1.1, 0.0, -60.0], [0.0, 1.1, 40.0], [0.0, 0.0, 1.0]])

    def mapped(H, n, lo, hi):
        s = rng.uniform(lo, hi, (n, 2))
        p = np.c_[s, np.ones(n)] @ H.T
        return np.c_[s, p[:, :2] / p[:, 2:] + rng.normal(0, 0.5, (n, 2))]

    m = np.r_[mapped(H1, inliers, 0, 640), mapped(H2, decoys, 200, 400),
              np.c_[rng.uniform(0, 640, (outliers, 2)), rng.uniform(0, 640, (outliers, 2))]]
    return m[rng.permutation(len(m))], H1, H2


def test_the_default_finds_the_motion_and_reports_the_decoy_as_a_second_cluster():
    m, H1, H2 = _decoy_pair(0)
    res = estimate_homography(m, "clap", rng=0)
    assert res.success and res.method == "clap"
    grid = np.array([[x, y, 0, 0] for x in (50, 300, 600) for y in (50, 300, 450)], float)
    p = np.c_[grid[:, :2], np.ones(9)] @ H1.T
    grid[:, 2:] = p[:, :2] / p[:, 2:]
    assert np.median(symmetric_reprojection_error(res.model, grid)) < 1.0
    # the decoy's motion is among the clusters, behind the answer
    costs = res.diagnostics["consensus_costs"]
    assert np.all(np.diff(costs) >= 0)
    g = res.space.manifold
    d2 = [float(g.distance(c.model, H2)) for c in res.clusters[1:]]
    assert min(d2) < 3.0


def test_consensus_selection_is_deterministic_and_seeded():
    m, _, _ = _decoy_pair(1)
    a, b = estimate_homography(m, "clap", rng=3), estimate_homography(m, "clap", rng=3)
    assert np.array_equal(a.model, b.model) and np.array_equal(a.inliers, b.inliers)


def test_paper_protocol_keeps_its_own_name():
    assert strategy_of("clap_paper") == "clap" and "clap_paper" in method_names()
    m, _, _ = _decoy_pair(2)
    res = estimate_homography(m, "clap_paper", rng=0)
    assert res.method == "clap_paper" and res.space.manifold.metric == "lie"
    assert PROTOCOLS["clap"]["select"] == "consensus"


@pytest.mark.parametrize("bad", [{"select": "best"}, {"density": "kde"}, {"k": 0},
                                 {"n_refine": -1}])
def test_bad_options_are_named(bad):
    m, _, _ = _decoy_pair(3)
    key = next(iter(bad))
    with pytest.raises(ValueError, match=key):
        fit(HomographySpace.for_data(m, metric="transfer"), m, "clap", rng=0, **bad)


def test_knn_density_and_consensus_work_in_any_space():
    # Euclidean points: the densest pair of hypotheses seeds; consensus decides
    rng = np.random.default_rng(4)
    from clap_unified.spaces import LineSpace

    x = rng.uniform(-5, 5, 200)
    pts = np.c_[x, 0.3 * x + 1 + rng.normal(0, 0.01, 200)]
    pts[:150] = rng.uniform(-5, 5, (150, 2))
    res = fit(LineSpace.for_data(pts), pts, "clap", threshold=0.05, rng=0, density="knn",
              select="consensus", max_clusters=10, min_support=1)
    assert res.success and res.n_inliers >= 45


def test_adaptive_budget_draws_more_only_when_right_samples_are_rare():
    from clap_unified.imaging.datasets import synthetic_pair

    space = HomographySpace.for_data
    easy, _, _ = _decoy_pair(5)
    opts = dict(PROTOCOLS["clap"])
    for key in ("frame", "metric", "polish", "max_hypotheses"):
        opts.pop(key)
    s = space(easy, metric="transfer", polish=2.0)
    plain = fit(s, easy, "clap", rng=4, **opts)
    adaptive = fit(s, easy, "clap", rng=4, max_hypotheses=10_000, **opts)
    assert adaptive.diagnostics["adaptive_hypotheses"] == opts["n_hypotheses"]
    assert np.array_equal(plain.model, adaptive.model)
    hard = synthetic_pair(0.12, n_matches=400, rng=2)
    m = hard.input.matches
    a = estimate_homography(m, "clap", rng=1)
    b = estimate_homography(m, "clap", rng=1)
    assert a.diagnostics["adaptive_hypotheses"] > 1000
    assert np.array_equal(a.model, b.model)
    # the first estimate's inlier ratio is what sized the second set
    w = a.diagnostics["first_inlier_ratio"]
    assert 0 < w < 1
    assert a.diagnostics["adaptive_hypotheses"] == min(
        PROTOCOLS["clap"]["max_hypotheses"], math.ceil(ALL_INLIER_SAMPLES / w**4))


def test_adaptive_budget_needs_hypotheses_fit_draws():
    m, _, _ = _decoy_pair(6)
    s = HomographySpace.for_data(m, metric="transfer")
    with pytest.raises(ValueError, match="max_hypotheses"):
        fit(s, m, "ransac", max_hypotheses=5000)
    hyps = s.hypotheses(m, 200, rng=0)
    with pytest.raises(ValueError, match="max_hypotheses"):
        fit(s, m, "clap", hypotheses=hyps, max_hypotheses=5000)
    with pytest.raises(ValueError, match="max_hypotheses"):
        fit(s, m, "clap", n_hypotheses=500, max_hypotheses=100)
    # given hypotheses: the protocol's adaptive budget steps aside
    assert estimate_homography(m, "clap", hypotheses=hyps, rng=0).success


def test_a_budget_above_the_protocols_cap_raises_the_cap():
    m, _, _ = _decoy_pair(7)
    res = estimate_homography(m, "clap", n_hypotheses=12_000, rng=0)
    assert res.success and res.diagnostics["adaptive_hypotheses"] == 12_000


@pytest.mark.parametrize("metric", ["transfer", "lie", "lie_linear", "frobenius"])
def test_answers_merge_when_their_distance_is_exactly_the_bandwidth(metric):
    # refined cluster centres within the bandwidth of a better one are one answer; the
    # rule uses the manifold's distance itself, so a distance that equals the bandwidth
    # merges (pairwise_distance may differ from it in the last bits)
    from clap_unified.clap.clap import _by_consensus, _msac_cost
    from clap_unified.imaging.datasets import synthetic_pair
    from clap_unified.result import Cluster

    m = np.asarray(synthetic_pair(0.3, n_matches=100, rng=0).input.matches, dtype=float)
    space = HomographySpace.for_data(m, metric=metric)
    man = space.manifold
    g = np.random.default_rng(0)
    for _ in range(200):  # prefer a pair where the two arithmetics disagree
        Hs = np.eye(3) + g.normal(0, [[0.01, 0.01, 3], [0.01, 0.01, 3], [1e-5, 1e-5, 0]],
                                  (2, 3, 3))
        a, b = np.argsort(_msac_cost(space, Hs, m, 3.0), kind="stable")
        d = float(man.distance(Hs[b], Hs[a]))
        if man.pairwise_distance(Hs)[b, a] != d:
            break
    clusters = [Cluster(Hs[0], 5.0, 0.0, np.array([0, 1])), Cluster(Hs[1], 3.0, 0.0,
                                                                     np.array([2]))]
    kept, costs = _by_consensus(space, m, clusters, 3.0, 0, bandwidth=d)
    assert len(kept) == 1 and kept[0].support == 8.0
    assert kept[0].members.tolist() == [0, 1, 2] and len(costs) == 1
    kept, _ = _by_consensus(space, m, clusters, 3.0, 0, bandwidth=np.nextafter(d, 0))
    assert len(kept) == 2


def test_neighbourhood_all_trims_over_every_hypothesis():
    """``neighbourhood="all"``: one cluster, the trimmed medoid of all the hypotheses."""
    from clap_unified.clap.rejection import trimmed_medoid_index
    from clap_unified.spaces import LineSpace

    rng = np.random.default_rng(7)
    x = rng.uniform(-5, 5, 120)
    pts = np.c_[x, 0.5 * x + 1 + rng.normal(0, 0.01, 120)]
    pts[:40] = rng.uniform(-5, 5, (40, 2))
    space = LineSpace.for_data(pts)
    hyps = space.hypotheses(pts, 200, rng=1)
    res = fit(space, pts, "clap", hypotheses=hyps, threshold=0.05, neighbourhood="all",
              rounds=5, discard_fraction=0.2, refine=False, bandwidth=1e-9)
    assert res.success and len(res.clusters) == 1 and res.clusters[0].support == len(hyps)
    assert res.diagnostics["neighbourhood"] == "all" and "bandwidth" not in res.diagnostics
    best, keep = trimmed_medoid_index(space.manifold.pairwise_distance(hyps.models),
                                      rounds=5, discard_fraction=0.2)
    np.testing.assert_array_equal(res.model, hyps.models[best])
    np.testing.assert_array_equal(np.sort(res.clusters[0].members), np.flatnonzero(keep))
    # a tiny bandwidth finds no cluster at min_support 3: the bandwidth plays no part above
    assert not fit(space, pts, "clap", hypotheses=hyps, threshold=0.05, bandwidth=1e-9,
                   refine=False).success
    # another robust centre over all of them; and too few hypotheses is a failed estimate
    mad = fit(space, pts, "clap", hypotheses=hyps, threshold=0.05, neighbourhood="all",
              rejection="mad", refine=False)
    assert mad.success and mad.clusters[0].support == len(hyps)
    few = fit(space, pts, "clap", hypotheses=space.hypotheses(pts, 2, rng=1), threshold=0.05,
              neighbourhood="all")
    assert not few.success and "min_support" in few.reason
    with pytest.raises(ValueError, match="neighbourhood"):
        fit(space, pts, "clap", threshold=0.05, neighbourhood="everything")


def test_reused_distances_equal_fresh_ones_and_stay_in_their_thread():
    import threading

    from clap_unified.geometry.homography_frame import HomographyInFrame, reuse_pairwise_distances

    m, _, _ = _decoy_pair(4)
    space = HomographySpace.for_data(m, metric="lie")
    models = space.hypotheses(m, 60, rng=0).models
    g = space.manifold
    fresh = g.pairwise_distance(models)
    with reuse_pairwise_distances(size=1):
        kept = g.pairwise_distance(models)
        np.testing.assert_array_equal(kept, fresh)
        assert g.pairwise_distance(models.copy()) is kept and not kept.flags.writeable
        linear = HomographyInFrame(g.T1, g.T2, metric="lie_linear").pairwise_distance(models)
        assert not np.array_equal(linear, kept)  # another metric, another matrix
        assert g.pairwise_distance(models) is not kept  # evicted (size 1)
        seen = []
        worker = threading.Thread(
            target=lambda: seen.append(g.pairwise_distance(models).flags.writeable))
        worker.start()
        worker.join()
        assert seen == [True]  # another thread is outside the block
    assert g.pairwise_distance(models).flags.writeable
