"""The three strategies on lines: accuracy, determinism, failures as values."""

import numpy as np
import pytest
from scenes import line_errors, line_scene

from clap_unified import compare, fit_line
from clap_unified.clap import clap, mad_centre, trimmed_centre
from clap_unified.geometry import Line2D
from clap_unified.hough import hough_lines, randomized_hough
from clap_unified.ransac import ransac, required_trials
from clap_unified.spaces import LineSpace, generate_hypotheses


def test_clap_recovers_line_with_70_percent_outliers_within_one_degree():
    scene = line_scene(n=300, outlier_ratio=0.7, seed=11)
    pts, inlier = scene.input.points, scene.truth.is_inlier
    space = LineSpace.for_data(pts)
    res = clap(space, pts, n_hypotheses=2000, threshold=0.06, rng=5)
    assert res.success
    angle, offset = line_errors(space, res.model)
    assert angle < 1.0
    assert offset < 0.05
    # most true inliers found, few outliers accepted
    assert np.count_nonzero(res.inliers & inlier) >= 0.9 * inlier.sum()
    assert np.count_nonzero(res.inliers & ~inlier) <= 0.1 * inlier.sum()


@pytest.mark.parametrize("method", ["hough", "randomized_hough", "ransac", "clap"])
def test_every_method_fits_a_clean_line_at_50_percent_outliers(method):
    pts = line_scene(n=200, outlier_ratio=0.5, seed=2).input.points
    res = fit_line(pts, method, threshold=0.06, rng=0)
    angle, offset = line_errors(res.space, res.model)
    assert res.success and angle < 1.0 and offset < 0.05


@pytest.mark.parametrize("method", ["randomized_hough", "ransac", "clap"])
def test_same_seed_same_result_bit_for_bit(method):
    pts = line_scene(seed=4).input.points
    a = fit_line(pts, method, rng=9)
    b = fit_line(pts, method, rng=9)
    np.testing.assert_array_equal(a.model, b.model)
    np.testing.assert_array_equal(a.inliers, b.inliers)


def test_compare_uses_identical_hypotheses():
    pts = line_scene(seed=3).input.points
    out = compare(LineSpace.for_data(pts), pts, n_hypotheses=500, threshold=0.06, rng=1)
    assert set(out) == {"randomized_hough", "ransac", "clap"}
    assert all(r.success for r in out.values())
    assert {len(r.support) for r in out.values()} == {500}
    assert out["ransac"].diagnostics["hypotheses_scored"] == 500


def test_clap_reports_both_lines_as_clusters():
    a = line_scene(n=150, outlier_ratio=0.0, theta=0.3, intercept=1.0, seed=1).input.points
    b = line_scene(n=100, outlier_ratio=0.0, theta=-1.0, intercept=-2.0, seed=2).input.points
    pts = np.r_[a, b]
    space = LineSpace.for_data(pts)
    res = clap(space, pts, n_hypotheses=2000, threshold=0.06, rng=0)
    assert len(res.clusters) >= 2
    first, second = res.clusters[0].model, res.clusters[1].model
    assert line_errors(space, first, 0.3, 1.0)[0] < 1.0
    assert line_errors(space, second, -1.0, -2.0)[0] < 1.0
    assert 0.2 < res.diagnostics["runner_up_ratio"] < 1.0
    assert res.clusters[0].support > res.clusters[1].support


def test_clap_local_mode_uses_the_guess():
    a = line_scene(n=150, outlier_ratio=0.0, theta=0.3, intercept=1.0, seed=1).input.points
    b = line_scene(n=100, outlier_ratio=0.0, theta=-1.0, intercept=-2.0, seed=2).input.points
    pts = np.r_[a, b]
    space = LineSpace.for_data(pts)
    hs = generate_hypotheses(space, pts, 2000, rng=0)
    guess = np.array([-1.0 + np.pi / 2 + 0.05, -2.0 * np.cos(-1.0) + 0.1])
    res = clap(space, pts, hypotheses=hs, prior=guess, radius=0.5, threshold=0.06)
    assert line_errors(space, res.model, -1.0, -2.0)[0] < 1.0
    assert res.diagnostics["mode"] == "local"
    far = clap(space, pts, hypotheses=hs, prior=[2.5, 50.0], radius=0.1)
    assert not far.success and "within radius" in far.reason
    with pytest.raises(ValueError, match="radius"):
        clap(space, pts, hypotheses=hs, prior=guess)


@pytest.mark.parametrize("centre", ["medoid", "karcher", "log_euclidean", "split", "median"])
@pytest.mark.parametrize("rejection", ["trim", "mad", "none"])
def test_clap_centres_and_rejections(centre, rejection):
    pts = line_scene(n=200, outlier_ratio=0.4, seed=6).input.points
    space = LineSpace.for_data(pts)
    res = clap(space, pts, n_hypotheses=800, centre=centre, rejection=rejection,
               threshold=0.06, rng=2)
    assert line_errors(space, res.model)[0] < 1.0


def test_trimming_follows_the_paper_schedule():
    m = Line2D()
    pts = np.c_[np.linspace(0.1, 0.2, 400), np.zeros(400)]
    _, keep = trimmed_centre(m, pts, rounds=5, discard_fraction=0.2)
    assert keep.sum() == 132  # ceil applied each round: 400, 320, 256, 205, 164, 132
    _, keep = mad_centre(m, np.r_[pts, [[1.5, 20.0]]])
    assert not keep[-1]


def test_failures_are_values_with_reasons():
    pts = np.zeros((30, 2))
    for method in ["ransac", "clap", "randomized_hough", "hough"]:
        res = fit_line(pts, method, rng=0)
        assert not res.success and not res
        assert res.model is None and res.reason
    with pytest.raises(ValueError, match="threshold"):
        ransac(LineSpace(), np.eye(2), threshold=-1)
    with pytest.raises(ValueError, match="centre"):
        clap(LineSpace(), np.eye(2), centre="sideways")
    with pytest.raises(ValueError, match="method"):
        fit_line(np.eye(2), "magic")


def test_ransac_adaptive_stops_early_on_clean_data():
    pts = line_scene(n=200, outlier_ratio=0.1, seed=8).input.points
    res = ransac(LineSpace(), pts, n_hypotheses=1000, confidence=0.99, threshold=0.06,
                 batch_size=10, rng=0)
    fixed = ransac(LineSpace(), pts, n_hypotheses=1000, threshold=0.06, rng=0)
    assert res.diagnostics["trials"] < 100 <= fixed.diagnostics["trials"]
    assert line_errors(res.space, res.model)[0] < 1.0
    assert required_trials(0.1, 2, 0.99) == pytest.approx(458.2, abs=0.1)


def test_msac_score_prefers_tighter_fit():
    pts = line_scene(n=200, outlier_ratio=0.3, seed=5).input.points
    res = ransac(LineSpace(), pts, score="msac", threshold=0.06, rng=0)
    assert res.score <= 0 and line_errors(res.space, res.model)[0] < 1.0


def test_hough_peaks_find_two_lines_and_wrap_at_vertical():
    y = np.linspace(-5, 5, 60)
    vertical = np.c_[np.full(60, 2.0), y]
    horizontal = np.c_[y, np.full(60, -1.0)]
    res = hough_lines(np.r_[vertical, horizontal], threshold=0.05, num_peaks=4)
    thetas = sorted(round(float(c.model[0]), 2) for c in res.clusters[:2])
    assert thetas == [0.0, 1.57]
    # near-vertical line straddling theta = 0 / pi is a single peak
    tilt = np.c_[2.0 + 0.002 * y, y]
    res = hough_lines(tilt, threshold=0.05, num_peaks=3)
    assert res.clusters[0].support == 60
    assert len(res.clusters) == 1 or res.clusters[1].support < 30


def test_randomized_hough_recentre_handles_chart_seam():
    # a horizontal line has theta = pi/2, on the seam of the chart at theta = 0
    pts = line_scene(n=200, outlier_ratio=0.5, theta=0.0, intercept=0.5, seed=3).input.points
    space = LineSpace.for_data(pts)
    res = randomized_hough(space, pts, cell_size=0.1, threshold=0.06, rng=0)
    assert line_errors(space, res.model, 0.0, 0.5)[0] < 1.0


@pytest.mark.parametrize("quantile", [0.0, 0.02, 0.05, 0.1, 0.3])
@pytest.mark.parametrize("seed", range(4))
def test_auto_bandwidth_shortcut_equals_full_knn_quantile(quantile, seed):
    # the low-quantile shortcut must return exactly np.quantile of every row's k-NN
    from clap_unified.clap import auto_bandwidth
    from clap_unified.clap.density import _low_quantile_of_knn

    rng = np.random.default_rng(seed)
    n = int(rng.integers(64, 500))
    pts = np.r_[rng.normal(0, 0.01, (n // 10, 3)), rng.uniform(-1, 1, (n - n // 10, 3))]
    if seed == 3:
        pts = np.round(pts, 1)  # many ties and zero distances
    D = np.sqrt(((pts[:, None] - pts[None]) ** 2).sum(-1))
    k = max(3, int(np.ceil(0.01 * n)))
    full = float(np.quantile(np.partition(D, k, axis=1)[:, k], quantile))
    got = auto_bandwidth(None, pts, quantile=quantile, distances=D)
    if 0 < quantile <= 0.05 and seed != 3:
        # the shortcut itself is taken here (not only the full partition behind it)
        assert _low_quantile_of_knn(D, k, quantile) == full
    if full > 0:
        assert got == full
    else:
        assert got > 0
