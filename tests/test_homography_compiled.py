"""The compiled homography kernels agree with the numpy reference they replace."""

import numpy as np
import pytest

from clap_unified import _compiled
from clap_unified.geometry.homography_transfer import HomographyTransfer, region_anchors
from clap_unified.imaging.datasets import synthetic_pair
from clap_unified.imaging.estimate import estimate_homography
from clap_unified.spaces import HomographySpace
from clap_unified.spaces import homography_compiled as hc
from clap_unified.spaces.homography import dlt, symmetric_transfer_error
from clap_unified.spaces.homography_polish import polish_checked
from clap_unified.spaces.sampling import sample_subsets


def _same_up_to_sign(a, b, atol=1e-10):
    return np.allclose(a * np.sign(a[2, 2]), b * np.sign(b[2, 2]), rtol=0, atol=atol)


def test_numba_is_used():
    assert _compiled.AVAILABLE, "numba is a dependency: the compiled path should be in use"


@pytest.fixture
def numpy_path():
    """Run a block with the kernels switched off (the numpy reference), then on again."""
    was = _compiled.AVAILABLE

    class Switch:
        def __enter__(self):
            _compiled.AVAILABLE = False

        def __exit__(self, *exc):
            _compiled.AVAILABLE = was

    yield Switch()
    _compiled.AVAILABLE = was


def _hard_matches(seed, unit=1.0):
    """Matches with outliers, repeated points and collinear runs (degenerate samples)."""
    m = np.array(synthetic_pair(0.3, n_matches=120, rng=seed).input.matches, dtype=float)
    m[10:20] = m[10]  # repeated matches
    m[20:30, :2] = np.c_[np.linspace(0, 100, 10), np.linspace(5, 205, 10)]  # collinear sources
    m[30:40, 2:] = np.c_[np.linspace(0, 50, 10), np.full(10, 7.0)]  # collinear destinations
    return m * unit


@pytest.mark.parametrize("unit", [1e-4, 1.0, 1e6])
@pytest.mark.parametrize("frame", [True, False])
@pytest.mark.parametrize("seed", range(3))
def test_four_point_solve_is_the_numpy_solver_bit_for_bit(seed, frame, unit, numpy_path):
    m = _hard_matches(seed, unit)
    space = HomographySpace.for_data(m, metric="transfer") if frame else HomographySpace()
    idx = sample_subsets(len(m), 4, 3000, rng=seed)
    H, owner = space.solve_minimal(m, idx)
    with numpy_path:
        H_ref, owner_ref = space.solve_minimal(m, idx)
    assert len(owner_ref) < len(idx)  # some samples are degenerate
    # the plain space tests singularity in pixels, where at 1e6 units every model fails
    assert len(owner_ref) > len(idx) // 2 or (not frame and unit != 1.0)
    assert np.array_equal(owner, owner_ref)
    assert np.array_equal(H, H_ref)
    assert H.flags.c_contiguous and H.shape == (len(owner), 3, 3)


def _solve_both(space, m, idx, numpy_path):
    H, owner = space.solve_minimal(m, idx)
    with numpy_path:
        H_ref, owner_ref = space.solve_minimal(m, idx)
    assert np.array_equal(owner, owner_ref)
    assert np.array_equal(H, H_ref)
    return owner


def test_four_point_solve_scales_h33_near_zero_like_numpy(numpy_path):
    # exact correspondences of homographies whose H33 is 1e-16 .. 1e-8 of the largest
    # entry: the source origin goes (nearly) to infinity; below 1e-12 both paths scale
    # them to unit norm instead of H33 = 1 (issue 27: they were refused), bit for bit alike
    g = np.random.default_rng(3)
    src = g.uniform(10, 500, (40, 2))
    ratios = np.logspace(-16, -8, 40)
    m = []
    for r in ratios:
        H = np.array([[1.0, 0.1, 5.0], [0.05, 1.0, -3.0], [1e-3, 2e-3, r]])
        p = np.c_[src[:4], np.ones(4)] @ H.T
        m.append(np.c_[src[:4], p[:, :2] / p[:, 2:]])
    m = np.concatenate(m)
    idx = np.arange(len(m)).reshape(-1, 4)
    owner = _solve_both(HomographySpace(), m, idx, numpy_path)
    assert len(owner) == len(ratios)  # none refused any more
    H, _ = HomographySpace().solve_minimal(m, idx)
    usual = H[:, 2, 2] == 1.0
    assert usual.any() and (~usual).any()  # the test is on the edge
    np.testing.assert_allclose(np.linalg.norm(H[~usual], axis=(1, 2)), 1.0, rtol=1e-15)
    assert np.all(np.abs(H[~usual][:, 2, 2]) <= 1e-12 * np.abs(H[~usual]).max(axis=(1, 2)))


def test_four_point_solve_collinearity_tolerance_of_each_side(numpy_path):
    # destinations nearly collinear by 1e-12 .. 1e-3 of their spread, and one far
    # destination point: the two sides' tolerances differ by orders of magnitude
    g = np.random.default_rng(4)
    n = 400
    src = g.uniform(0, 400, (n, 2))
    t = g.uniform(0, 400, n)
    eps = np.logspace(-12, -3, n) * 400 * g.choice([-1, 1], n)
    dst = np.c_[t, 0.5 * t + 7 + eps]
    dst[-1] = [4e4, -3e4]  # far away: the destination's largest normalised coordinate
    m = np.c_[src, dst]
    idx = sample_subsets(n - 1, 4, 20000, rng=0)
    owner = _solve_both(HomographySpace.for_data(m, metric="transfer"), m, idx, numpy_path)
    assert 0 < len(owner) < len(idx)


def test_transfer_embedding_sign_test_at_the_edge(numpy_path):
    # w at an anchor just below and just above 1e-12 of the largest entry
    man = HomographyTransfer(np.array([[100.0, 0.0], [0.0, 0.0]]))
    w = np.repeat(np.logspace(-14, -10, 50), 2)
    H = np.zeros((100, 3, 3))
    H[:, 0, 0] = H[:, 1, 1] = 1.0
    H[:, 2, 2] = 1.0
    H[:, 2, 0] = (w - 1.0) / 100.0  # w = 100 g + 1 at the first anchor
    ours = man.chordal_embedding(H)
    with numpy_path:
        ref = man.chordal_embedding(H)
    assert np.array_equal(np.isnan(ours), np.isnan(ref))
    assert np.array_equal(np.nan_to_num(ours), np.nan_to_num(ref))
    valid = ~np.isnan(ours[:, 0])
    assert 0 < valid.sum() < len(H)  # some rows on each side of the edge


@pytest.mark.parametrize("samples", [[[0, 1, 2, 21]], [[0, 1, 2, 3_000_000]],
                                     [[0, 1, 2], [3, 4, 5]], [[0.0, 1.0, 2.0, 3.0]]])
def test_solve_minimal_refuses_bad_samples_on_both_paths(samples, numpy_path):
    m = np.random.default_rng(0).uniform(0, 600, (20, 4))
    space = HomographySpace()
    with pytest.raises(IndexError):
        space.solve_minimal(m, np.array(samples))
    with numpy_path, pytest.raises(IndexError):
        space.solve_minimal(m, np.array(samples))


@pytest.mark.parametrize("shape", [(100, 3, 4), (100, 4, 3), (100, 2, 2)])
def test_transfer_embedding_refuses_other_shapes_like_numpy(shape, numpy_path):
    man = HomographyTransfer(np.array([[1.0, 2.0], [3.0, 4.0]]))
    H = np.ones(shape)
    with numpy_path, pytest.raises((ValueError, IndexError)):
        man.chordal_embedding(H)
    with pytest.raises((ValueError, IndexError)):
        man.chordal_embedding(H)


def test_transfer_embedding_is_the_numpy_embedding_bit_for_bit(numpy_path):
    g = np.random.default_rng(0)
    H = np.eye(3) + g.normal(0, [[0.1, 0.1, 30], [0.1, 0.1, 30], [1e-4, 1e-4, 0.1]],
                             (500, 3, 3))
    H[0, 0, 0] = np.nan
    H[1, 2] = [-0.01, 0.0, 1.0]  # w < 0 beyond x = 100: behind the camera there
    H[2, 2] = [0.01, 0.0, -1.0]  # the same with H33 < 0
    H[3] = 0.0
    H[4, 0, 2] = np.inf
    H[5] *= -1  # the same homography, scaled by -1: embedded all the same
    man = HomographyTransfer(region_anchors(g.uniform(0, 640, (50, 2))))
    ours = man.chordal_embedding(H)
    with numpy_path:
        ref = man.chordal_embedding(H)
        one = man.chordal_embedding(H[7])
    assert np.array_equal(np.isnan(ours), np.isnan(ref))
    assert np.isnan(ours[:5]).all(axis=1).all() and not np.isnan(ours[5:]).any()
    assert np.array_equal(np.nan_to_num(ours), np.nan_to_num(ref))
    assert np.array_equal(ours[7], one)


@pytest.mark.parametrize("quality", [False, True])
def test_a_whole_clap_estimate_is_the_same_without_numba(quality, numpy_path):
    pair = synthetic_pair(0.15, n_matches=400, decoy_ratio=0.05, rng=3)
    q = pair.input.quality if quality else None
    res = estimate_homography(pair.input.matches, "clap", rng=0, quality=q)
    with numpy_path:
        ref = estimate_homography(pair.input.matches, "clap", rng=0, quality=q)
    assert res.success and ref.success
    assert np.array_equal(res.inliers, ref.inliers)
    assert [c.support for c in res.clusters] == [c.support for c in ref.clusters]
    np.testing.assert_allclose(res.model, ref.model, rtol=1e-8, atol=1e-8)


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


@pytest.mark.parametrize("n_matches", [12, 60, 400])
@pytest.mark.parametrize("n", [30, 500, 3000])
def test_progressive_samples_are_the_numpy_ones(n_matches, n, numpy_path):
    # the hash table of new samples takes exactly the rows the Python set takes:
    # small pools (12 matches: 495 4-subsets) are exhausted long before n
    pair = synthetic_pair(0.3, n_matches=n_matches, rng=n)
    m, q = pair.input.matches, pair.input.quality
    space = HomographySpace.for_data(m, metric="transfer")
    ours = space.hypotheses(m, n, rng=1, quality=q)
    with numpy_path:
        ref = space.hypotheses(m, n, rng=1, quality=q)
    assert np.array_equal(ours.samples, ref.samples)
    assert np.array_equal(ours.models, ref.models)
    assert (ours.n_draws, ours.n_degenerate) == (ref.n_draws, ref.n_degenerate)
    keys = {tuple(r) for r in np.sort(ours.samples, axis=1).tolist()}
    assert len(keys) == len(ours.samples)  # no sample twice


def test_take_new_samples_counts_and_order():
    rows = np.array([[0, 1, 2, 3], [0, 1, 2, 4], [0, 1, 2, 3], [1, 2, 3, 4], [0, 1, 2, 5]])
    table, used = np.zeros((16, 2), dtype=np.int64), np.zeros(16, dtype=bool)
    assert hc.take_new_samples(rows, 6, table, used, 10).tolist() == [0, 1, 3, 4]
    assert hc.take_new_samples(rows, 6, table, used, 10).tolist() == []  # all seen
    table, used = np.zeros((16, 2), dtype=np.int64), np.zeros(16, dtype=bool)
    assert hc.take_new_samples(rows, 6, table, used, 2).tolist() == [0, 1]  # at most 2
    assert hc.take_new_samples(rows, 6, table, used, 5).tolist() == [3, 4]
