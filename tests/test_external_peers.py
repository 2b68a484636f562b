"""PoseLib and COLMAP behind the same call as the library's strategies (issue 14)."""

import builtins

import numpy as np
import pytest

from clap_unified import compare, fit, strategy_names
from clap_unified.imaging import estimate_homography
from clap_unified.imaging.datasets import synthetic_pair
from clap_unified.imaging.estimate import PROTOCOLS, method_names
from clap_unified.imaging.evaluation import PEERS, estimate_error
from clap_unified.registry import get_strategy
from clap_unified.spaces import HomographySpace

PEER_NAMES = ("poselib", "colmap")


def _transfer(H, m):
    q = np.c_[m[:, :2], np.ones(len(m))] @ H.T
    return np.linalg.norm(q[:, :2] / q[:, 2:] - m[:, 2:], axis=1)


@pytest.fixture(scope="module")
def pair():
    """A known homography, 40 % inliers with 0.5 px noise, 10 % decoys, uniform outliers."""
    return synthetic_pair(0.4, decoy_ratio=0.1, n_matches=300, noise=0.5, rng=4)


@pytest.mark.parametrize("method", PEER_NAMES)
def test_recovers_a_known_homography_with_outliers(pair, method):
    res = fit(HomographySpace(), pair.input.matches, method, threshold=3.0, rng=0,
              refine=False)
    assert res.success, res.reason
    assert res.model[2, 2] == pytest.approx(1.0)
    assert estimate_error(res.model, pair) < 0.5
    mask = res.diagnostics[f"{method}_mask"]
    assert mask.shape == (len(pair.input.matches),) and mask.dtype == bool
    assert np.mean(mask[pair.truth.inliers]) > 0.95 and not mask[pair.truth.decoys].any()


def test_convention_x2_is_H_x1():
    """Each peer's H maps the first point of a row to the second, as the library's."""
    rng = np.random.default_rng(0)
    H = np.array([[0.9, 0.1, 30.0], [-0.1, 1.1, -20.0], [2e-4, 1e-4, 1.0]])
    src = rng.uniform(0, 640, (60, 2))
    q = np.c_[src, np.ones(60)] @ H.T
    m = np.c_[src, q[:, :2] / q[:, 2:]]
    for method in PEER_NAMES:
        res = fit(HomographySpace(), m, method, threshold=1.0, rng=0, refine=False)
        np.testing.assert_allclose(res.model, H, rtol=1e-6, atol=1e-6)


@pytest.mark.parametrize("method", PEER_NAMES)
@pytest.mark.parametrize("kind", ["identical", "collinear", "collinear in image 2"])
def test_degenerate_input_fails_with_a_reason(method, kind):
    t = np.arange(20.0)
    data = {"identical": np.tile([[10.0, 20.0, 30.0, 40.0]], (20, 1)),
            "collinear": np.c_[t, 2 * t, t + 3, 2 * t + 1],
            "collinear in image 2": np.c_[t, t ** 2, t, 3 * t]}[kind]
    res = fit(HomographySpace(), data, method, threshold=3.0, rng=0)
    assert not res.success and res.model is None
    assert isinstance(res.reason, str) and res.reason not in ("", "ok")
    assert not res.inliers.any()


@pytest.mark.parametrize("method", PEER_NAMES)
def test_threshold_is_respected(method):
    p = synthetic_pair(0.5, n_matches=300, noise=1.5, rng=7)
    counts = []
    for threshold in (1.0, 6.0):
        res = fit(HomographySpace(), p.input.matches, method, threshold=threshold, rng=0,
                  refine=False)
        assert res.success, res.reason
        e = _transfer(res.model, p.input.matches)
        # the result's inliers: the matches within the threshold of the returned model
        np.testing.assert_array_equal(res.inliers, e < threshold)
        # the peer's own inliers are within the threshold too (up to its final refinement)
        mask = res.diagnostics[f"{method}_mask"]
        assert np.all(e[mask] < 1.2 * threshold)
        counts.append(res.n_inliers)
    assert counts[0] < counts[1]


@pytest.mark.parametrize("method", PEER_NAMES)
def test_same_rng_same_result(method):
    p = synthetic_pair(0.15, decoy_ratio=0.1, n_matches=300, rng=2)
    a, b = (fit(HomographySpace(), p.input.matches, method, threshold=3.0, rng=5,
                refine=False) for _ in range(2))
    assert np.array_equal(a.model, b.model) and np.array_equal(a.inliers, b.inliers)
    g = (fit(HomographySpace(), p.input.matches, method, threshold=3.0,
             rng=np.random.default_rng(5), refine=False) for _ in range(2))
    c, d = g
    assert np.array_equal(c.model, d.model)
    assert a.diagnostics["seed"] == c.diagnostics["seed"]


def test_options_reach_the_peer():
    p = synthetic_pair(0.3, n_matches=200, rng=3)
    res = fit(HomographySpace(), p.input.matches, "poselib", threshold=3.0, rng=0,
              n_hypotheses=50, refine=False)
    assert res.diagnostics["poselib_iterations"] <= 50
    res = fit(HomographySpace(), p.input.matches, "poselib", threshold=3.0, rng=0,
              n_hypotheses=200, min_iterations=150, refine=False)
    assert res.diagnostics["poselib_iterations"] >= 150
    for method in PEER_NAMES:
        with pytest.raises(ValueError, match="confidence"):
            fit(HomographySpace(), p.input.matches, method, threshold=3.0, confidence=1.0)
        with pytest.raises(ValueError, match="min_iterations"):
            fit(HomographySpace(), p.input.matches, method, threshold=3.0, min_iterations=-1)


def test_through_compare_and_estimate_homography(pair):
    out = compare(HomographySpace(), pair.input.matches, methods=("ransac", *PEER_NAMES),
                  threshold=3.0, rng=0, n_hypotheses=300)
    for method in PEER_NAMES:
        assert out[method].success and out[method].method == method
        assert estimate_error(out[method].model, pair) < 1.0
        res = estimate_homography(pair.input.matches, method, rng=0)
        assert res.success and res.method == method and res.threshold == 3.0
        assert estimate_error(res.model, pair) < 0.5
        # the protocol: reported as the peer returns it (no refinement of ours)
        assert PROTOCOLS[method]["refine"] is False and method in method_names()


def test_registered_as_baselines():
    names = strategy_names(HomographySpace())
    for method in (*PEER_NAMES, "cv2_ransac", "magsac", "usac_accurate", "usac_ransac_fixed"):
        assert method in names
        s = get_strategy(method)
        assert s.baseline and not s.uses_hypotheses
        assert s.applies_to == ("homography", "fundamental")
    assert get_strategy("open3d").baseline
    for own in ("clap", "ransac", "randomized_hough"):
        assert not get_strategy(own).baseline
    assert {name for name, _ in PEERS.values()} == {"cv2_ransac", "magsac", "usac_accurate",
                                                   "poselib", "colmap"}


@pytest.mark.parametrize(("method", "package"), [("poselib", "poselib"), ("colmap", "pycolmap")])
def test_a_missing_package_is_named(method, package, monkeypatch):
    real = builtins.__import__

    def no_peer(name, *args, **kwargs):
        if name == package:
            raise ImportError(f"No module named {package!r}")
        return real(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_peer)
    with pytest.raises(ImportError, match=package):
        fit(HomographySpace(), np.random.default_rng(0).uniform(0, 100, (20, 4)), method,
            threshold=3.0)
