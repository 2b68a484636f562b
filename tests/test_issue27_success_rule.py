"""Issue 27, part 2: what porting OpenCV's homography tests found, each fixed at its root.

* one success rule for every strategy of ``fit``: fewer inliers than a minimal sample fails,
  with a reason (CLAP with ``centre="karcher"``, randomized Hough and the MAGSAC wrapper
  succeeded with 0 inliers at a tiny threshold, where RANSAC failed);
* ``required_trials(w, m, 1.0)`` divided by zero;
* CLAP could not fit exactly four matches (one possible sample);
* randomized Hough raised ``ValueError`` when the mean of its fullest cell was no model,
  instead of returning a failed result;
* a homography whose ``H[2, 2]`` is 0 was "degenerate" for every method.

Each test failed before its fix (the message of each says how).
"""

import warnings

import numpy as np
import pytest

from clap_unified import fit
from clap_unified.fitting import success_rule
from clap_unified.geometry.homography import Homography
from clap_unified.hough.randomized import run_randomized_hough
from clap_unified.ransac.ransac import required_trials
from clap_unified.spaces.homography import HomographySpace
from clap_unified.spaces.lines import LineSpace

H_TRUE = np.array([[0.9, 0.1, 30.0], [-0.1, 0.9, -20.0], [1e-4, 2e-4, 1.0]])


def transfer(H, p):
    q = np.c_[p, np.ones(len(p))] @ np.asarray(H).T
    return q[:, :2] / q[:, 2:]


def noisy_matches(seed=0, n=100):
    rng = np.random.default_rng(seed)
    src = rng.uniform(0, 640, (n, 2))
    return np.c_[src, transfer(H_TRUE, src) + rng.normal(0, 1.0, (n, 2))]


# ---------------------------------------------------------------- one success rule
@pytest.mark.parametrize("method,options", [("clap", {"centre": "karcher"}),
                                            ("randomized_hough", {}), ("ransac", {})])
def test_tiny_threshold_fails_alike_for_every_strategy(method, options):
    """Before: CLAP (Karcher centre) and randomized Hough returned success with 0 inliers."""
    d = noisy_matches()
    res = fit(HomographySpace.for_data(d), d, method, threshold=1e-6, n_hypotheses=200, rng=0,
              **options)
    if res.success:  # a model through its own four matches (RANSAC's sample, refitted)
        assert res.n_inliers >= HomographySpace.min_samples
    else:
        assert res.n_inliers == 0 and res.model is None
        assert res.reason.endswith("fewer than a minimal sample (4)")


@pytest.mark.parametrize("method,options", [("clap", {"centre": "karcher"}),
                                            ("randomized_hough", {}), ("hough", {})])
def test_lines_with_no_inlier_fail(method, options):
    rng = np.random.default_rng(0)
    x = rng.uniform(-5, 5, 100)
    pts = np.c_[x, 0.5 * x + rng.normal(0, 0.01, 100)]
    res = fit(LineSpace.for_data(pts), pts, method, threshold=1e-9, rng=0, **options)
    assert not res.success
    assert res.reason == "the model has 0 inlier(s), fewer than a minimal sample (2)"


def test_magsac_wrapper_with_no_inlier_fails():
    pytest.importorskip("cv2")
    d = noisy_matches()
    res = fit(HomographySpace(), d, "magsac", threshold=1e-6, refine=False, rng=0)
    assert not res.success and res.n_inliers == 0  # before: success with 0 inliers
    assert res.reason == "the model has 0 inlier(s), fewer than a minimal sample (4)"


def test_success_rule_counts_inliers():
    assert success_rule(HomographySpace(), np.r_[np.ones(3, bool), np.zeros(5, bool)]) == \
        "the model has 3 inlier(s), fewer than a minimal sample (4)"
    assert success_rule(HomographySpace(), np.ones(4, bool)) == "ok"


def test_every_success_has_a_minimal_sample_of_inliers():
    """The rule holds across strategies and thresholds on one data set."""
    d = noisy_matches(1, 60)
    for method in ("clap", "randomized_hough", "ransac"):
        for t in (1e-3, 0.5, 3.0):
            res = fit(HomographySpace.for_data(d), d, method, threshold=t, n_hypotheses=150,
                      rng=0)
            assert res.success == (res.n_inliers >= 4), (method, t, res.reason)


# ---------------------------------------------------------------- required_trials
def test_required_trials_at_full_confidence_does_not_divide_by_zero():
    """Before: ``RuntimeWarning: divide by zero encountered in log``."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert required_trials(0.5, 4, 1.0) == np.inf
        assert required_trials(1.0, 4, 1.0) == 1.0
        assert required_trials(0.0, 4, 1.0) == np.inf
        assert required_trials(0.5, 4, 0.99) == pytest.approx(np.log(0.01) / np.log1p(-1 / 16))


# ---------------------------------------------------------------- CLAP on four matches
@pytest.mark.parametrize("metric", ["plain", "lie_linear", "transfer"])
@pytest.mark.parametrize("options", [{}, {"density": "knn", "k": 2},
                                     {"neighbourhood": "all"}])
def test_clap_fits_exactly_four_matches(metric, options):
    """OpenCV's minimal case (Calib3d_Homography.accuracy at N = 4). Before: "no cluster
    with at least 3 hypotheses" (four matches have one 4-subset)."""
    rng = np.random.default_rng(3)
    src = rng.uniform(0, 100, (4, 2))
    d = np.c_[src, transfer(H_TRUE, src)]
    space = HomographySpace() if metric == "plain" else HomographySpace.for_data(d, metric=metric)
    res = fit(space, d, "clap", threshold=1.0, rng=0, **options)
    assert res.success and res.n_inliers == 4
    np.testing.assert_allclose(res.model / res.model[2, 2], H_TRUE, rtol=1e-9, atol=1e-9)


def test_clap_still_asks_min_support_of_sampled_hypotheses():
    """The cap applies to an enumeration only: two random hypotheses are no cluster."""
    d = noisy_matches(2, 40)
    res = fit(HomographySpace.for_data(d), d, "clap", n_hypotheses=2, threshold=3.0, rng=0)
    assert not res.success and "at least 3 hypotheses" in res.reason


# ---------------------------------------------------------------- randomized Hough
class _RefusingMean(Homography):
    """A manifold whose mean is no model (as a singular mean homography)."""

    def mean(self, points, weights=None, **kwargs):
        raise ValueError("point: 1 singular matrix(es) (det = 0), not a homography")


class _Space(HomographySpace):
    @property
    def manifold(self):
        return _RefusingMean()


def test_randomized_hough_singular_mean_is_a_failed_result():
    """Before: the ``ValueError`` of the mean escaped ``fit`` (AdelaideRMF, some runs)."""
    d = noisy_matches(4, 40)
    space = _Space()
    hyps = HomographySpace().hypotheses(d, 50, rng=0)
    res = fit(space, d, "randomized_hough", hypotheses=hyps, threshold=3.0, rng=0)
    assert not res.success and res.model is None
    assert res.reason.startswith("the mean of the") and "singular" in res.reason
    # the strategy itself: a failed consensus, not an exception
    consensus = run_randomized_hough(space, d, hyps, threshold=3.0)
    assert consensus.model is None


# ---------------------------------------------------------------- H33 = 0
#: Homographies that send the image origin to infinity (OpenCV fits them).
H33_ZERO_CASES = [
    np.array([[1.0, 0.2, 5.0], [0.1, 1.1, 3.0], [0.002, 0.001, 0.0]]),
    np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 100.0], [1.0, 0.0, 0.0]]),
]


@pytest.mark.parametrize("case", range(len(H33_ZERO_CASES)))
@pytest.mark.parametrize("method", ["ransac", "clap", "randomized_hough", "clap_paper"])
def test_homography_with_zero_h33_is_fitted(case, method):
    """Before: "every minimal sample was degenerate" (the second case, exact zeros) or a
    model scaled by a rounding error (``H33 = 1`` with entries near 1e12)."""
    from clap_unified.imaging.estimate import estimate_homography

    H0 = H33_ZERO_CASES[case]
    src = np.random.default_rng(case).uniform(10, 100, (60, 2))
    d = np.c_[src, transfer(H0, src)]
    res = estimate_homography(d, method, rng=0)
    assert res.success and res.n_inliers == 60
    H = res.model
    assert np.all(np.isfinite(H)) and abs(np.linalg.norm(H) - 1.0) < 1e-12  # unit norm
    np.testing.assert_allclose(transfer(H, src), d[:, 2:], atol=1e-6)
    described = np.array(res.to_dict()["model"]["H"])
    np.testing.assert_allclose(described, H, rtol=0, atol=1e-15)


def test_scale_homography_fallback_and_usual_form():
    from clap_unified.geometry.homography_arithmetic import scale_homography

    H = np.array([[2.0, 0.0, 4.0], [0.0, 2.0, 6.0], [0.0, 0.0, 2.0]])
    assert np.array_equal(scale_homography(H), H / 2.0)  # the usual form, bit for bit
    Z = -H33_ZERO_CASES[1]
    S = scale_homography(Z)
    assert S[1, 2] > 0 and np.linalg.norm(S) == pytest.approx(1.0)
    np.testing.assert_allclose(S, scale_homography(3.0 * Z), rtol=1e-15)  # scale-free


def test_compiled_solver_agrees_on_zero_h33():
    from clap_unified import _compiled

    if not _compiled.AVAILABLE:
        pytest.skip("numba not available")
    H0 = H33_ZERO_CASES[0]
    src = np.random.default_rng(5).uniform(10, 100, (12, 2))
    d = np.c_[src, transfer(H0, src)]
    samples = np.array([[0, 1, 2, 3], [4, 5, 6, 7], [8, 9, 10, 11]])
    space = HomographySpace()
    compiled, owner = space.solve_minimal(d, samples)
    _compiled.AVAILABLE = False
    try:
        reference, owner_ref = space.solve_minimal(d, samples)
    finally:
        _compiled.AVAILABLE = True
    assert owner.tolist() == owner_ref.tolist() == [0, 1, 2]
    np.testing.assert_allclose(compiled, reference, rtol=1e-12, atol=1e-15)
