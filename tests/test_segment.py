"""``segment``: several models, the labels of the data, and the parts every segmenter shares."""

from __future__ import annotations

import json

import numpy as np
import pytest

from clap_unified import LineSpace, segment, segmenter_names
from clap_unified.partition import (
    assign_labels,
    refit_partition,
    select_by_label_cost,
    select_models,
)
from clap_unified.spaces.homography import HomographySpace

METHODS = ("clap", "ransac", "multi_ransac", "t_linkage", "randomized_hough")


def two_lines(seed=0, n1=80, n2=60, clutter=60):
    """Two lines and uniform clutter; the true labels (-1 clutter) for scoring only."""
    rng = np.random.default_rng(seed)
    x = rng.uniform(-5, 5, n1 + n2)
    y = np.where(np.arange(n1 + n2) < n1, 0.5 * x + 1, -x)
    pts = np.c_[x, y] + rng.normal(0, 0.01, (n1 + n2, 2))
    pts = np.r_[pts, rng.uniform(-5, 5, (clutter, 2))]
    truth = np.r_[np.zeros(n1, int), np.ones(n2, int), -np.ones(clutter, int)]
    return pts, truth


def agreement(labels, truth):
    """Share of data whose label matches the truth under the best matching of labels."""
    from scipy.optimize import linear_sum_assignment

    a, b = labels + 1, truth + 1
    table = np.zeros((a.max() + 1, b.max() + 1))
    np.add.at(table, (a, b), 1)
    cost = -table
    cost[0, 1:] = cost[1:, 0] = 1e9  # outliers only match outliers
    r, c = linear_sum_assignment(cost)
    return sum(table[i, j] for i, j in zip(r, c, strict=True) if cost[i, j] < 1e9) / len(a)


def test_every_segmenter_is_registered():
    assert set(METHODS) <= set(segmenter_names(LineSpace()))


@pytest.mark.parametrize("method", METHODS)
def test_two_lines_found_and_labelled(method):
    pts, truth = two_lines()
    opts = {"cell_size": 0.05} if method == "randomized_hough" else {}
    res = segment(LineSpace.for_data(pts), pts, method, threshold=0.05, rng=1, **opts)
    assert res.success and res.n_models == 2, res
    assert agreement(res.labels, truth) > 0.95
    assert res.labels.shape == (len(pts),) and res.labels.min() >= -1


@pytest.mark.parametrize("method", METHODS)
def test_same_seed_same_answer(method):
    pts, _ = two_lines(3)
    a = segment(LineSpace.for_data(pts), pts, method, threshold=0.05, rng=7)
    b = segment(LineSpace.for_data(pts), pts, method, threshold=0.05, rng=7)
    np.testing.assert_array_equal(a.labels, b.labels)
    np.testing.assert_array_equal(a.models, b.models)


@pytest.mark.parametrize("method", METHODS)
def test_pure_noise_gives_no_model(method):
    pts = np.random.default_rng(2).uniform(-5, 5, (150, 2))
    res = segment(LineSpace.for_data(pts), pts, method, threshold=0.01, rng=0)
    assert not res.success and res.n_models == 0
    assert np.all(res.labels == -1) and res.reason
    assert json.loads(json.dumps(res.to_dict()))["models"] == []


def test_to_dict_is_the_common_json_form():
    pts, _ = two_lines()
    res = segment(LineSpace.for_data(pts), pts, "clap", threshold=0.05, rng=0)
    d = json.loads(json.dumps(res.to_dict()))
    assert set(d) == {"method", "success", "reason", "models", "labels", "selection", "data",
                      "threshold", "seconds"}
    assert len(d["labels"]) == len(pts) and len(d["models"]) == res.n_models
    assert sorted(m["support"] for m in d["models"]) == sorted(res.support.tolist())
    assert {"normal", "offset"} <= set(d["models"][0]["model"])


def test_result_is_frozen():
    pts, _ = two_lines()
    res = segment(LineSpace.for_data(pts), pts, "clap", threshold=0.05, rng=0)
    with pytest.raises(ValueError):
        res.labels[0] = 5
    with pytest.raises(ValueError, match="k: expected a model index"):
        res.inliers(res.n_models)


@pytest.mark.parametrize("bad, match", [
    (dict(data=np.full((20, 2), np.nan)), "points"),
    (dict(data=np.zeros((20, 3))), "points"),
    (dict(method="nope"), "method"),
    (dict(threshold=-1.0), "threshold"),
    (dict(min_support=1), "min_support"),
    (dict(n_hypotheses=0), "n_hypotheses"),
    (dict(bogus=3), "bogus"),
    (dict(space="line"), "space"),
])
def test_bad_input_names_the_argument(bad, match):
    pts, _ = two_lines()
    args = dict(space=LineSpace(), data=pts, method="clap", threshold=0.05)
    args.update(bad)
    with pytest.raises(ValueError, match=match):
        segment(args.pop("space"), args.pop("data"), args.pop("method"), **args)


def test_two_planes_of_matches():
    rng = np.random.default_rng(4)
    h1 = np.array([[1.0, 0.02, 5], [0.01, 1.0, -3], [0, 0, 1]])
    h2 = np.array([[0.9, -0.1, 40], [0.05, 1.1, 10], [1e-4, 0, 1]])
    src = rng.uniform(0, 640, (160, 2))
    dst = np.empty_like(src)
    for h, part in ((h1, slice(0, 80)), (h2, slice(80, 160))):
        q = np.c_[src[part], np.ones(80)] @ h.T
        dst[part] = q[:, :2] / q[:, 2:]
    data = np.c_[src, dst + rng.normal(0, 0.5, dst.shape)]
    data = np.r_[data, rng.uniform(0, 640, (60, 4))]
    truth = np.r_[np.zeros(80, int), np.ones(80, int), -np.ones(60, int)]
    for method in ("clap", "ransac", "t_linkage"):
        res = segment(HomographySpace(), data, method, threshold=3.0, rng=0)
        assert res.n_models == 2, (method, res)
        assert agreement(res.labels, truth) > 0.95, method


def test_local_sampling_is_shared_and_seeded():
    pts, _ = two_lines()
    a = segment(LineSpace.for_data(pts), pts, "clap", threshold=0.05, rng=0,
                sampling={"neighbours": 10})
    assert a.n_models == 2
    with pytest.raises(ValueError, match="sampling"):
        segment(LineSpace(), pts, "clap", threshold=0.05, sampling={"quality": 1})


def test_assign_labels_nearest_within_threshold():
    lines = np.array([[np.pi / 2, 0.0], [np.pi / 2, 1.0]])
    pts = np.array([[0.0, 0.3], [0.0, 0.7], [0.0, 5.0]])
    assert assign_labels(LineSpace(), lines, pts, 0.5).tolist() == [0, 1, -1]
    assert assign_labels(LineSpace(), lines[:0], pts, 0.5).tolist() == [-1, -1, -1]


def test_select_models_drops_a_model_whose_data_is_explained():
    x = np.linspace(-5, 5, 30)
    pts = np.r_[np.c_[x, 0 * x], np.c_[x, 0 * x + 1]]
    cands = np.array([[np.pi / 2, 0.0], [np.pi / 2, 0.01], [np.pi / 2, 1.0]])
    assert select_models(LineSpace(), cands, pts, 0.1, 10).tolist() == [0, 2]


def test_label_cost_prefers_two_models_to_a_bridge_and_one_to_two():
    x = np.linspace(-5, 5, 30)
    pts = np.r_[np.c_[x, 0 * x], np.c_[x, 0 * x + 0.1]]
    bridge = np.array([[np.pi / 2, 0.05], [np.pi / 2, 0.0], [np.pi / 2, 0.1]])
    # cheap labels: two exact lines beat the bridge that half-explains both
    assert sorted(select_by_label_cost(LineSpace(), bridge, pts, 0.2, 1e-4).tolist()) == [1, 2]
    # a label worth more than what the second line saves: one model
    assert select_by_label_cost(LineSpace(), bridge, pts, 0.2, 1.0).tolist() == [0]


def test_refit_partition_drops_weak_models_and_refits():
    pts, _ = two_lines()
    space = LineSpace()
    rough = np.array([[np.pi / 2 + np.arctan(0.5) + 0.01, 0.9], [np.pi / 4 + 0.01, 0.0],
                      [0.3, 3.0]])
    models, labels, kept = refit_partition(space, rough, pts, 0.05, 20)
    assert kept.tolist() == [0, 1] and len(models) == 2
    assert np.bincount(labels[labels >= 0]).min() >= 20


def _plane_matches(rng, n=100):
    src = rng.uniform(0, 640, (n, 2))
    return np.c_[src, src + 5.0]


@pytest.mark.parametrize("kind", ["homography", "fundamental"])
@pytest.mark.parametrize("method", ["clap", "ransac", "multi_ransac", "t_linkage",
                                    "randomized_hough", "magsac"])
def test_bad_matches_give_an_error_or_no_model(kind, method):
    """Issue 26's bad input: a clear error naming the argument, or no model and a reason."""
    import warnings

    from clap_unified.imaging.segment_matches import segment_matches

    rng = np.random.default_rng(0)
    one = _plane_matches(rng)
    for data, match in ((one[:3], "matches"), (np.r_[one, [[np.nan] * 4]], "matches"),
                        (one[:, :3], "matches"), (one[:0], "matches")):
        with pytest.raises(ValueError, match=match):
            segment_matches(data, kind, method, rng=0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no RuntimeWarning escapes either
        for data in (rng.uniform(0, 640, (150, 4)),          # pure noise
                     np.repeat(one[:1], 50, axis=0)):         # one match fifty times
            res = segment_matches(data, kind, method, rng=0)
            assert res.n_models == 0 and not res.success and res.reason, (kind, method)
            assert np.all(res.labels == -1) and len(res.labels) == len(data)
        # ten matches of one plane, each ten times: that plane or nothing, never two
        res = segment_matches(np.repeat(one[:10], 10, axis=0), kind, method, rng=0)
        assert res.n_models <= 1 and (res.n_models == 0 or np.all(res.labels == 0)), res


@pytest.mark.parametrize("scale", [1e-6, 1e6])
def test_two_planes_at_any_scale_with_a_threshold_in_their_units(scale):
    from clap_unified.imaging.segment_matches import segment_matches

    rng = np.random.default_rng(1)
    src = rng.uniform(0, 640, (200, 2))
    dst = np.where(np.arange(200)[:, None] < 100, src + 20.0, 1.1 * src)
    res = segment_matches(np.c_[src, dst] * scale, threshold=2.0 * scale, rng=0)
    assert res.n_models == 2 and sorted(res.support.tolist()) == [100, 100]


def adelaidermf_and_spy(monkeypatch, name):
    """The AdelaideRMF sequence ``name`` (skip when absent) and the (data, kwargs) of every
    segment() call segment_matches makes from now on."""
    from clap_unified.imaging import segment_matches as sm
    from clap_unified.imaging.datasets.adelaidermf import load_adelaidermf

    try:
        pair = load_adelaidermf(name, images=False)
    except OSError:
        pytest.skip("AdelaideRMF is not here")
    seen = []
    real = sm.segment

    def spy(space, data, method, **kw):
        # checked once by segment_matches and handed down wrapped: the matches inside
        seen.append((np.array(getattr(data, "data", data)), kw))
        return real(space, data, method, **kw)

    monkeypatch.setattr(sm, "segment", spy)
    return pair, seen


def test_the_experiment_never_hands_labels_to_an_estimator(monkeypatch):
    """AdelaideRMF's labels reach only the score: segment() sees the matches and nothing else."""
    from clap_unified.imaging import segment_matches as sm

    pair, seen = adelaidermf_and_spy(monkeypatch, "bonython")
    rows = sm.evaluate_adelaidermf("homography", ("clap", "ransac"), seeds=(0,),
                                   names=["bonython"])
    assert len(rows) == 2 and len(seen) == 2
    labels = np.asarray(pair.truth.labels)
    order = sm.trial_order(len(labels), 0)  # the trial's order of the matches
    for data, kw in seen:
        np.testing.assert_array_equal(data, np.asarray(pair.input.matches)[order])
        assert all(not (isinstance(v, np.ndarray) and v.shape == labels.shape)
                   for v in kw.values())


def test_every_seed_is_another_order_of_the_matches_for_every_method(monkeypatch):
    """OpenCV's MAGSAC++ loop is deterministic for one list of matches: a seed that changed
    only the library's random numbers gave it one run where the others had five."""
    from clap_unified.imaging import segment_matches as sm

    pair, seen = adelaidermf_and_spy(monkeypatch, "bonython")
    sm.evaluate_adelaidermf("homography", ("clap", "ransac"), seeds=(0, 1), names=["bonython"])
    assert len(seen) == 4
    orders = [sm.trial_order(len(pair.truth.labels), s) for s in (0, 1)]
    assert not np.array_equal(orders[0], orders[1])
    matches = np.asarray(pair.input.matches)
    for data, _ in seen:  # each call gets one of the two trials' orders, both methods alike
        assert sum(np.array_equal(data, matches[o]) for o in orders) == 1


def test_local_samples_take_other_places_when_rows_repeat():
    from clap_unified.spaces.sampling import sample_local_subsets

    pts = np.random.default_rng(0).uniform(0, 100, (30, 2))
    rows = np.repeat(pts, 5, axis=0)                     # every point five times
    s = sample_local_subsets(rows, 4, 300, 10, rng=0)
    places = np.unique(rows, axis=0, return_inverse=True)[1].reshape(-1)[s]
    assert np.all(np.sort(places, axis=1)[:, 1:] != np.sort(places, axis=1)[:, :-1])
    np.testing.assert_array_equal(s, sample_local_subsets(rows, 4, 300, 10, rng=0))
    # without repeats: the seed first, the others among its 10 nearest
    s = sample_local_subsets(pts, 3, 50, 10, rng=1)
    d = np.linalg.norm(pts[:, None] - pts[None], axis=2)
    tenth = np.sort(d, axis=1)[:, 10]
    assert np.all(d[s[:, :1], s[:, 1:]] <= tenth[s[:, :1]] + 1e-12)


def test_compare_segmenters_runs_every_method_on_one_hypothesis_set():
    from clap_unified import compare_segmenters
    from clap_unified.fitting import check_problem, draw_hypotheses

    pts, truth = two_lines(5)
    space = LineSpace.for_data(pts)
    out = compare_segmenters(space, pts, methods=("t_linkage", "clap", "ransac"),
                             threshold=0.05, rng=3, n_hypotheses=500)
    assert list(out) == ["t_linkage", "clap", "ransac"]
    hyps, _, _ = draw_hypotheses(check_problem(space, pts, 0.05), 500, 3)
    for name in ("t_linkage", "clap"):  # the same hypotheses as one draw with the seed
        alone = segment(space, pts, name, threshold=0.05, hypotheses=hyps, n_hypotheses=500)
        np.testing.assert_array_equal(out[name].labels, alone.labels)
    assert all(agreement(r.labels, truth) > 0.95 for r in out.values())
    with pytest.raises(ValueError, match="options"):
        compare_segmenters(space, pts, methods=("clap",), options={"ransac": {}})


def test_t_linkage_distances_ignore_the_last_bits_of_the_preferences():
    """Another BLAS kernel changes the dot products' last bits; the distances the merges
    compare must not follow them (a flip seen on AdelaideRMF bonhall under
    OPENBLAS_CORETYPE=SandyBridge), and the clusters stay the same."""
    from clap_unified.preference.tlinkage import _tanimoto, t_linkage_clusters

    rng = np.random.default_rng(0)
    base = np.where(rng.uniform(size=(12, 40)) < 0.3, rng.uniform(0.2, 1.0, (12, 40)), 0.0)
    P = np.repeat(base, 4, axis=0)          # every datum four times: exact ties everywhere

    def distances(Q):
        sq = np.einsum("ij,ij->i", Q, Q)
        return _tanimoto(Q @ Q.T, sq[:, None], sq[None, :])

    labels = t_linkage_clusters(P)
    for k in range(5):
        wobbled = P * (1 + 1e-14 * np.random.default_rng(k).standard_normal(P.shape))
        np.testing.assert_array_equal(distances(wobbled), distances(P))
        np.testing.assert_array_equal(t_linkage_clusters(wobbled), labels)


def test_label_cost_energy_is_what_the_selection_minimises():
    """The chosen set's energy is at most that of the empty set and of every single candidate."""
    from clap_unified.partition import label_cost_energy

    x = np.linspace(-5, 5, 30)
    pts = np.r_[np.c_[x, 0 * x], np.c_[x, 0 * x + 0.1], [[0.0, 3.0], [1.0, -2.0]]]
    cands = np.array([[np.pi / 2, 0.05], [np.pi / 2, 0.0], [np.pi / 2, 0.1], [0.3, 1.0]])
    space = LineSpace()
    for cost in (1e-4, 1e-2, 1.0):
        chosen = select_by_label_cost(space, cands, pts, 0.2, cost)
        e = label_cost_energy(space, cands[chosen], pts, 0.2, cost)
        assert e <= label_cost_energy(space, cands[:0], pts, 0.2, cost) + 1e-12
        for c in range(len(cands)):
            assert e <= label_cost_energy(space, cands[c:c + 1], pts, 0.2, cost) + 1e-12
    # no model: every datum pays t^2
    assert label_cost_energy(space, cands[:0], pts, 0.2, 5.0) == pytest.approx(0.04 * len(pts))
    # y = 0: its 30 points pay 0, the 30 at y = 0.1 pay 0.1^2, the two far ones t^2; one label
    assert label_cost_energy(space, cands[1:2], pts, 0.2, 5.0) == pytest.approx(
        0.01 * 30 + 0.04 * 2 + 5.0)


def test_explain_errors_scores_clap_against_the_annotated_planes(monkeypatch):
    """The oracle's planes come from the labels; CLAP still sees only the matches."""
    from clap_unified.imaging import segment_matches as sm

    pair, seen = adelaidermf_and_spy(monkeypatch, "elderhallb")
    (row,) = sm.explain_errors(threshold=7.0, seed=0, names=["elderhallb"])
    assert len(seen) == 1
    n = len(pair.truth.labels)
    np.testing.assert_array_equal(seen[0][0],
                                  np.asarray(pair.input.matches)[sm.trial_order(n, 0)])
    assert all(not (isinstance(v, np.ndarray) and len(v) == n) for v in seen[0][1].values())
    assert row["true_models"] == 3 and row["cause"] in {"objective", "search", "floor"}
    # the annotated planes through the same finish err less than a method can be expected to
    assert 0.0 <= row["oracle_error"] <= row["error"] + 1e-12
    assert row["energy"] > 0 and row["oracle_energy"] > 0


@pytest.mark.parametrize("options", [{"select": "cover"}, {"refine": False}])
def test_explain_errors_refuses_answers_the_energy_does_not_judge(options):
    from clap_unified.imaging.segment_matches import explain_errors

    with pytest.raises(ValueError, match="^options"):
        explain_errors(threshold=5.0, options=options, names=[])


def test_a_datum_on_two_models_goes_to_the_first_whatever_the_last_bits():
    # a point of two models' minimal samples has a residual of rounding size on both:
    # which is smaller is the last bit of a float (it differs between BLAS builds) and
    # must not decide its label; ties within TIE_TOLERANCE * threshold go to the first
    lines = np.array([[np.pi / 2, 1e-13], [np.pi / 4, 0.0]])   # y = 1e-13 and x + y = 0
    pts = np.array([[0.0, 0.0], [3.0, 0.0], [-2.0, 2.0]])
    r = LineSpace().residuals(lines, pts)
    assert r[1, 0] < r[0, 0] < 1e-12                          # the second is nearer by 1e-13
    assert assign_labels(LineSpace(), lines, pts, 0.5).tolist() == [0, 0, 1]
    nan = np.array([[np.nan, np.nan]])
    assert assign_labels(LineSpace(), nan, pts, 0.5).tolist() == [-1, -1, -1]


def test_the_coherent_labelling_starts_from_the_same_tie_rule():
    # with no coherence (weight 0) the labelling is its start: it must break the
    # last-bit tie as assign_labels does, not by whichever residual is smaller
    from clap_unified.coherence import coherent_labels, neighbour_graph

    lines = np.array([[np.pi / 2, 1e-13], [np.pi / 4, 0.0]])
    pts = np.array([[0.0, 0.0], [3.0, 0.0], [-2.0, 2.0]])
    edges = neighbour_graph(pts, 1)
    assert coherent_labels(LineSpace(), lines, pts, 0.5, edges, 0.0).tolist() == [0, 0, 1]


def test_a_model_with_no_residual_does_not_take_the_data_of_another():
    # a non-finite residual explains nothing: it must not hide the nearer model
    lines = np.array([[np.pi / 2, 0.0], [np.pi / 2, 5.0]])
    pts = np.array([[0.0, 4.9], [1.0, 0.1]])

    class Half(LineSpace):
        def residuals(self, models, data):
            r = super().residuals(models, data)
            r[0, 0] = np.nan
            return r

    assert assign_labels(Half(), lines, pts, 0.5).tolist() == [1, 0]
