import numpy as np
import pytest

from clap_unified.ransac import ransac
from clap_unified.spaces import generate_hypotheses
from clap_unified.spaces.homography import HomographySpace, dlt

H_TRUE = np.array([[0.9, 0.05, 20.0], [-0.03, 1.05, -10.0], [2e-4, -1e-4, 1.0]])
CORNERS = np.array([[0, 0], [640, 0], [640, 480], [0, 480.0]])


def transfer(H, p):
    q = np.c_[p, np.ones(len(p))] @ H.T
    return q[:, :2] / q[:, 2:]


def matches(n=300, outliers=0.5, noise=0.5, seed=0):
    rng = np.random.default_rng(seed)
    src = rng.uniform([0, 0], [640, 480], (n, 2))
    dst = transfer(H_TRUE, src) + rng.normal(0, noise, (n, 2))
    k = int(outliers * n)
    dst[:k] = rng.uniform([0, 0], [640, 480], (k, 2))
    return np.c_[src, dst]


def test_batched_dlt_is_exact_on_noise_free_samples():
    data = matches(noise=0.0, outliers=0.0)
    hs = generate_hypotheses(HomographySpace(), data, 200, rng=0)
    assert len(hs) == 200
    np.testing.assert_allclose(hs.models, np.broadcast_to(H_TRUE, hs.models.shape), atol=1e-8)
    H = dlt(data[:, :2], data[:, 2:])
    np.testing.assert_allclose(H / H[2, 2], H_TRUE, atol=1e-10)


def test_collinear_and_repeated_samples_are_rejected():
    src = np.array([[0, 0], [1, 1], [2, 2], [0, 5.0], [3, 1], [3, 1]])
    data = np.c_[src, src + 1.0]
    models, owner = HomographySpace().solve_minimal(data, np.array([[0, 1, 2, 3], [0, 3, 4, 5],
                                                                    [0, 1, 3, 4]]))
    assert owner.tolist() == [2]


def test_residuals_transfer_and_symmetric():
    data = matches(noise=0.0, outliers=0.0, n=20)
    for kind in ["transfer", "symmetric"]:
        r = HomographySpace(residual=kind).residuals(H_TRUE[None], data)
        assert r.shape == (1, 20) and np.all(r < 1e-9)
    shifted = H_TRUE.copy()
    shifted[0, 2] += 3.0
    r = HomographySpace().residuals(shifted, data)
    assert r.shape == (1, 20) and np.all(r > 0.5)


def test_ransac_recovers_homography_with_half_outliers():
    res = ransac(HomographySpace(), matches(), rng=0)
    err = np.linalg.norm(transfer(res.model, CORNERS) - transfer(H_TRUE, CORNERS), axis=1).mean()
    assert res.success and err < 2.0 and 140 <= res.n_inliers <= 160


def test_bad_matches_are_named():
    with pytest.raises(ValueError, match="matches: expected shape"):
        HomographySpace().check_data(np.zeros((10, 3)))
    with pytest.raises(ValueError, match="matches: need at least 4"):
        HomographySpace().check_data(np.zeros((3, 4)))
    assert HomographySpace().refit(np.zeros((10, 4))) is None


def test_hypotheses_are_never_singular():
    hs = generate_hypotheses(HomographySpace(), matches(outliers=0.8), 400, rng=0)
    H = hs.models
    ratio = np.abs(np.linalg.det(H)) / np.prod(np.linalg.norm(H, axis=-1), axis=-1)
    assert len(hs) == 400 and ratio.min() > 1e-10


def test_polish_scale_widens_the_weights_not_the_inliers():
    rng = np.random.default_rng(3)
    src = rng.uniform(0, 640, (200, 2))
    dst = src + [5.0, -2.0] + rng.normal(0, 1.5, (200, 2))
    data = np.c_[src, dst]
    H0 = np.array([[1.0, 0, 5.5], [0, 1, -1.5], [0, 0, 1]])
    model, inliers = HomographySpace(polish=2.0).refine(H0, data, 3.0)
    from clap_unified.spaces.homography import symmetric_transfer_error
    assert np.array_equal(inliers, symmetric_transfer_error(model, data) < 3.0)
    assert HomographySpace(polish=2.0).polish == 2.0 and HomographySpace(polish=True).polish is True
    for bad in (0, -1.0, np.nan, "yes"):
        with pytest.raises(ValueError, match="polish"):
            HomographySpace(polish=bad)


def test_reading_the_manifold_does_not_change_the_answer():
    """The minimal solver screens samples in the Hartley frame only on a framed space
    (for_data / for_images); reading a plain space's manifold (built on first use) once
    switched the screen, and let singular samples through to a ValueError in fit."""
    rng = np.random.default_rng(2)
    H = np.array([[1.1, 0.05, 12], [0.02, 0.95, -7], [1e-4, 2e-4, 1]])
    p = rng.uniform(0, 640, (200, 2))
    q = np.c_[p, np.ones(200)] @ H.T
    m = np.c_[p, q[:, :2] / q[:, 2:] + rng.normal(0, 0.5, (200, 2))]
    m[:120, 2:] = rng.uniform(0, 640, (120, 2))
    samples = np.array([rng.choice(200, 4, replace=False) for _ in range(20000)])
    untouched = HomographySpace().solve_minimal(m, samples)
    read = HomographySpace()
    read.manifold  # noqa: B018 - the read under test
    after = read.solve_minimal(m, samples)
    np.testing.assert_array_equal(after[1], untouched[1])
    np.testing.assert_array_equal(after[0], untouched[0])
