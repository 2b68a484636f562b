"""The compiled homography kernels agree with the numpy reference they replace."""

import numpy as np
import pytest

from clap_unified.imaging.datasets import synthetic_pair
from clap_unified.imaging.estimate import estimate_homography
from clap_unified.spaces import HomographySpace
from clap_unified.spaces import homography_compiled as hc
from clap_unified.spaces.homography import dlt, symmetric_transfer_error
from clap_unified.spaces.homography_polish import polish_checked


def _same_up_to_sign(a, b, atol=1e-10):
    return np.allclose(a * np.sign(a[2, 2]), b * np.sign(b[2, 2]), rtol=0, atol=atol)


def test_numba_is_used():
    assert hc.AVAILABLE, "numba is a dependency: the compiled path should be in use"


@pytest.mark.parametrize("seed", range(5))
def test_symmetric_transfer_error_matches_numpy(seed):
    g = np.random.default_rng(seed)
    H = np.eye(3) + g.normal(0, [[0.1, 0.1, 10], [0.1, 0.1, 10], [1e-3, 1e-3, 0.1]])
    m = g.uniform(-50, 700, (200, 4))
    ours, ref = hc.symmetric_transfer_error(H, m), symmetric_transfer_error(H, m)
    finite = np.isfinite(ref)
    assert np.array_equal(np.isfinite(ours), finite)
    np.testing.assert_allclose(ours[finite], ref[finite], rtol=1e-10)


def test_symmetric_transfer_error_singular_and_infinite():
    m = np.array([[1.0, 2.0, 3.0, 4.0], [0.0, 0.0, 1.0, 1.0]])
    singular = np.array([[1.0, 2, 3], [2, 4, 6], [0, 0, 1]])
    assert np.all(np.isinf(hc.symmetric_transfer_error(singular, m)))
    # the line x = 0 goes to infinity: the match at the origin has an infinite error
    to_infinity = np.array([[1.0, 0, 0], [0, 1, 0], [1, 0, 0]])
    out = hc.symmetric_transfer_error(to_infinity, m)
    ref = symmetric_transfer_error(to_infinity, m)
    assert np.isinf(out[1]) and np.isinf(ref[1])


@pytest.mark.parametrize("n", [4, 5, 7, 8, 9, 50])
def test_weighted_dlt_matches_numpy(n):
    g = np.random.default_rng(n)
    H = np.array([[1.1, 0.1, 20.0], [-0.05, 0.95, -10.0], [1e-4, -2e-4, 1.0]])
    src = g.uniform(0, 640, (n, 2))
    p = np.c_[src, np.ones(n)] @ H.T
    m = np.c_[src, p[:, :2] / p[:, 2:] + g.normal(0, 0.5, (n, 2))]
    w = g.uniform(0.1, 1.0, n)
    assert _same_up_to_sign(hc.weighted_dlt(m, w), dlt(m[:, :2], m[:, 2:], w))
    assert _same_up_to_sign(hc.weighted_dlt(m, np.ones(n)), dlt(m[:, :2], m[:, 2:]))


@pytest.mark.parametrize("ratio", [0.3, 0.6, 1.0])
@pytest.mark.parametrize("seed", range(4))
def test_polish_matches_numpy(ratio, seed):
    pair = synthetic_pair(ratio, n_matches=300, rng=seed)
    m = np.asarray(pair.input.matches, dtype=float)
    start = estimate_homography(m, "cv2_ransac", rng=seed, refine=False).model
    for t in (3.0, 6.0):
        H_c, inl_c = polish_checked(start, m, t, compiled=True)
        H_n, inl_n = polish_checked(start, m, t, compiled=False)
        assert np.array_equal(inl_c, inl_n)
        np.testing.assert_allclose(H_c, H_n, rtol=1e-8, atol=1e-10)


def test_polish_without_enough_inliers_returns_the_start():
    m = np.random.default_rng(0).uniform(0, 100, (20, 4))
    start = np.diag([1.0, 1.0, 1.0])
    for compiled in (True, False):
        H, inl = polish_checked(start, m, 0.01, compiled=compiled)
        assert np.array_equal(H, start) and not inl.any()


def test_refit_uses_the_same_dlt():
    pair = synthetic_pair(1.0, n_matches=40, rng=3)
    m = np.asarray(pair.input.matches, dtype=float)
    H = HomographySpace().refit(m)
    ref = dlt(m[:, :2], m[:, 2:])
    np.testing.assert_allclose(H, ref / ref[2, 2], rtol=1e-9, atol=1e-12)


def test_point_mapped_to_infinity_is_an_infinite_error_not_an_exception():
    # a match on the line that H sends to infinity (pz = 0): numpy gives inf, so must the kernel
    H = np.array([[1.0, 0, 0], [0, 1, 0], [1, 0, 1]])
    m = np.array([[-1.0, 5.0, 3.0, 4.0], [2.0, 1.0, 0.7, 0.3], [0.5, 0.5, 0.3, 0.3]])
    with np.errstate(all="ignore"):
        ref = symmetric_transfer_error(H, m)
    out = hc.symmetric_transfer_error(H, m)
    assert np.isinf(out[0]) and np.isinf(ref[0])
    np.testing.assert_allclose(out[1:], ref[1:], rtol=1e-12)
    H_c, inl_c = polish_checked(H, m, 1.0, compiled=True)
    H_n, inl_n = polish_checked(H, m, 1.0, compiled=False)
    assert np.array_equal(inl_c, inl_n)
