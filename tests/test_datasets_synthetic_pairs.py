"""The synthetic hard pairs: deterministic, as asked, and their truth never reaches an estimator."""

import dataclasses

import numpy as np
import pytest
from split_checks import assert_rows_disjoint, assert_split

from clap_unified.imaging import estimate
from clap_unified.imaging.datasets import (
    HomographyPair,
    HomographyTruth,
    SyntheticTruth,
    synthetic_pair,
    synthetic_pairs,
)
from clap_unified.imaging.datasets.synthetic_pairs import DECOY_SHARES, INLIER_RATIOS
from clap_unified.imaging.evaluation import compare_peers, estimate_error, shuffled_pair
from clap_unified.imaging.metrics import symmetric_reprojection_error


def _transfer(H, m):
    q = np.c_[m[:, :2], np.ones(len(m))] @ H.T
    return np.linalg.norm(q[:, :2] / q[:, 2:] - m[:, 2:], axis=1)


@pytest.fixture(scope="module")
def pairs():
    return synthetic_pairs()


def test_the_fixed_set_is_deterministic_and_complete(pairs):
    again = synthetic_pairs()
    assert len(pairs) == len(INLIER_RATIOS) * len(DECOY_SHARES) == 12
    for p, q in zip(pairs, again, strict=True):
        assert p.name == q.name and p.dataset == "synthetic"
        for a, b in [(p.input.matches, q.input.matches), (p.input.quality, q.input.quality),
                     (p.truth.H, q.truth.H), (p.truth.inliers, q.truth.inliers),
                     (p.truth.validation, q.truth.validation), (p.truth.decoys, q.truth.decoys)]:
            np.testing.assert_array_equal(a, b)
    assert not np.array_equal(synthetic_pairs(seed=1)[0].input.matches, pairs[0].input.matches)
    got = {(round(p.inlier_ratio, 2), round(float(p.truth.decoys.mean()), 2)) for p in pairs}
    assert got == {(r, round(f * r, 2)) for r in INLIER_RATIOS for f in DECOY_SHARES}
    assert all(p.truth.decoys.sum() < p.truth.inliers.sum() for p in pairs)
    assert [p.name for p in pairs][:2] == ["synthetic r=0.08 decoy=0 #0",
                                           "synthetic r=0.08 decoy=0.04 #1"]


def test_shapes_and_ratios():
    p = synthetic_pair(0.12, decoy_ratio=0.2, n_matches=400, rng=5)
    assert isinstance(p, HomographyPair) and isinstance(p.truth, SyntheticTruth)
    assert isinstance(p.truth, HomographyTruth)
    assert p.input.matches.shape == (400, 4) and p.input.quality.shape == (400,)
    assert p.truth.H.shape == p.truth.decoy_H.shape == (3, 3) and p.truth.H[2, 2] == 1.0
    assert p.truth.inliers.sum() == 48 and p.truth.decoys.sum() == 80
    assert not np.any(p.truth.inliers & p.truth.decoys)
    assert 8 <= len(p.truth.validation) <= 20 and p.truth.validation.shape[1] == 4
    assert np.all((p.input.quality > 0) & (p.input.quality < 1))
    w, h = 640, 480
    m = p.input.matches
    assert np.all(m[:, [0, 2]] > -5) and np.all(m[:, [0, 2]] < w + 5)
    assert np.all(m[:, [1, 3]] > -5) and np.all(m[:, [1, 3]] < h + 5)
    assert synthetic_pair(0.3, rng=0).name == "synthetic r=0.3 decoy=0"


def test_truth_inliers_fit_H_and_decoys_fit_the_decoy_H(pairs):
    for p in pairs:
        m, t = p.input.matches, p.truth
        e = _transfer(t.H, m[t.inliers])
        assert np.sqrt(np.mean(e ** 2)) < 1.0 * np.sqrt(2) * 1.3 and e.max() < 6.0, p.name
        if t.decoys.any():
            d = _transfer(t.decoy_H, m[t.decoys])
            assert d.max() < 6.0, p.name
            # a different motion: the decoys do not fit the true H
            assert np.median(_transfer(t.H, m[t.decoys])) > 20.0, p.name
        # the uniform outliers fit neither
        rest = ~t.inliers & ~t.decoys
        assert np.mean(_transfer(t.H, m[rest]) < 3.0) < 0.05
        # validation points are exact under H and spread over the view
        assert np.max(symmetric_reprojection_error(t.H, t.validation)) < 1e-6
        # inliers spread over the image, the decoys in a smaller region
        spread = np.ptp(m[t.inliers, :2], axis=0)
        assert spread[0] > 0.5 * 640 and spread[1] > 0.5 * 480, p.name
        if t.decoys.any():
            assert np.prod(np.ptp(m[t.decoys, :2], axis=0)) < 0.5 * np.prod(spread)


def test_exact_without_noise_and_quality_helps_but_is_no_oracle(pairs):
    p = synthetic_pair(0.2, decoy_ratio=0.1, noise=0.0, rng=3)
    assert _transfer(p.truth.H, p.input.matches[p.truth.inliers]).max() < 1e-6
    assert _transfer(p.truth.decoy_H, p.input.matches[p.truth.decoys]).max() < 1e-6
    q = np.concatenate([x.input.quality for x in pairs])
    inl = np.concatenate([x.truth.inliers for x in pairs])
    out = np.concatenate([~x.truth.inliers & ~x.truth.decoys for x in pairs])
    assert np.median(q[inl]) < np.median(q[out])
    # overlapping: many outliers are better than the median inlier
    assert np.mean(q[out] < np.median(q[inl])) > 0.1


def test_bad_arguments_name_themselves():
    for kw, name in [({"inlier_ratio": 0.0}, "inlier_ratio"),
                     ({"inlier_ratio": 0.005}, "inlier_ratio"),
                     ({"inlier_ratio": 0.6, "decoy_ratio": 0.5}, "decoy_ratio"),
                     ({"inlier_ratio": 0.2, "n_matches": 3}, "n_matches"),
                     ({"inlier_ratio": 0.2, "noise": -1.0}, "noise"),
                     ({"inlier_ratio": 0.2, "size": (0, 10)}, "size")]:
        with pytest.raises(ValueError, match=name):
            synthetic_pair(**kw)


def test_evaluation_data_never_reaches_an_estimator(pairs, monkeypatch):
    """Estimators are called with pair.input only; the validation points are not input rows."""
    for p in pairs:
        assert_split(p)
        assert_rows_disjoint(p.input.matches, p.truth.validation, atol=1e-6)
        # the input holds the matches and their quality only: no label, no model
        assert {f.name for f in dataclasses.fields(p.input)} == {"matches", "quality",
                                                                   "image_a", "image_b"}
    seen = []
    real = estimate.estimate_homography

    def spy(matches, method="clap", **kw):
        seen.append((np.asarray(matches), kw.get("quality")))
        return real(matches, method, **kw)

    import clap_unified.imaging.evaluation as evaluation

    monkeypatch.setattr(evaluation, "estimate_homography", spy)
    p = pairs[9]
    rows = compare_peers([p], {"CLAP quality": ("clap", True), "cv2.RANSAC": ("cv2_ransac",
                                                                               False)},
                         repeat=1)
    assert len(seen) == 2 and len(rows) == 2
    for matches, quality in seen:
        assert matches is p.input.matches or np.array_equal(matches, p.input.matches)
        assert quality is None or quality is p.input.quality
    assert any(q is p.input.quality for _, q in seen)


def test_shuffling_keeps_decoys_with_their_matches():
    p = synthetic_pair(0.2, decoy_ratio=0.2, noise=0.0, rng=2)
    q = shuffled_pair(p, 1)
    assert _transfer(q.truth.decoy_H, q.input.matches[q.truth.decoys]).max() < 1e-6
    assert _transfer(q.truth.H, q.input.matches[q.truth.inliers]).max() < 1e-6
    assert estimate_error(q.truth.H, q) < 1e-6
