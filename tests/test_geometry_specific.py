"""Group-specific checks: paper distances, batched logm, SO(3) edge cases, bad input."""

import warnings

import numpy as np
import pytest
import scipy.linalg

from clap_unified.geometry import (
    SE2,
    SE3,
    Homography,
    _matrix,
    frobenius_distance,
    lie_distance,
    logm,
    so3_exp,
    so3_log,
)


def random_homographies(n, rng, *, pixels=300.0):
    """Homographies with pixel-sized translations and small perspective terms."""
    H = scipy.linalg.expm(0.3 * rng.standard_normal((n, 3, 3)))
    H[:, :2, 2] *= pixels
    H[:, 2, :2] /= pixels
    return H * rng.uniform(0.5, 3.0, (n, 1, 1))  # arbitrary scale


def scipy_logs(A):
    """Reference logarithms, one matrix at a time (scipy's accuracy warning is expected)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        return np.array([scipy.linalg.logm(a) for a in A])


# ------------------------------------------------------------------ SE(3)
def test_se3_relative_error_hand_cases():
    g = SE3()
    T1 = g.from_rt(so3_exp([0.0, 0.0, np.pi / 2]), [1.0, 0.0, 0.0])
    T2 = g.compose(T1, g.from_rt(so3_exp([0.4, 0.0, 0.0]), [0.0, 3.0, 4.0]))
    e_t, e_r = g.relative_error(T1, T2)
    assert e_t == pytest.approx(5.0) and e_r == pytest.approx(0.4)
    # batched over leading axes, and symmetric
    e_t, e_r = g.relative_error(np.stack([T1, T2]), np.stack([T2, T1]))
    np.testing.assert_allclose(e_t, [5.0, 5.0])
    np.testing.assert_allclose(e_r, [0.4, 0.4])


def test_se3_lie_log_distance_uses_angle_weight():
    g = SE3(angle_weight=2.0)
    pure_rot = g.from_rt(so3_exp([0.0, 0.0, 0.1]), np.zeros(3))
    assert float(g.distance(g.identity(), pure_rot)) == pytest.approx(0.2)  # lambda * angle
    shift = g.from_rt(np.eye(3), [0.0, 3.0, 4.0])
    assert float(g.distance(g.identity(), shift)) == pytest.approx(5.0)


def test_se3_point_set_distance_hand_cases_and_brute_force():
    g = SE3()
    P = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
    shift = g.from_rt(np.eye(3), [0.0, 0.0, 0.5])
    assert float(g.point_set_distance(g.identity(), shift, P)) == pytest.approx(0.5)
    # rotation by pi/2 about z moves (1, 0, 0) by sqrt(2) and leaves the origin: RMS = 1
    rot = g.from_rt(so3_exp([0.0, 0.0, np.pi / 2]), np.zeros(3))
    assert float(g.point_set_distance(g.identity(), rot, P)) == pytest.approx(1.0)
    rng = np.random.default_rng(0)
    A, B = g.random(4, rng=rng), g.random(5, rng=rng)
    X = rng.standard_normal((7, 3))
    D = g.point_set_distance(A[:, None], B[None], X)
    assert D.shape == (4, 5)
    for i in range(4):
        for j in range(5):
            pa = X @ A[i, :3, :3].T + A[i, :3, 3]
            pb = X @ B[j, :3, :3].T + B[j, :3, 3]
            assert D[i, j] == pytest.approx(np.sqrt(np.mean(np.sum((pa - pb) ** 2, 1))))


def test_se3_split_mean_rotation_is_karcher():
    g = SE3()
    c = so3_exp([0.3, -0.2, 1.0])
    phis = 0.3 * np.random.default_rng(1).standard_normal((4, 3))
    R = c @ so3_exp(np.r_[phis, -phis])
    T = g.from_rt(R, np.arange(24.0).reshape(8, 3))
    M = g.split_mean(T, max_iter=100, tol=1e-14)
    np.testing.assert_allclose(M[:3, :3], c, atol=1e-10)
    np.testing.assert_allclose(M[:3, 3], np.arange(24.0).reshape(8, 3).mean(0))


def test_se2_split_mean_wraps_the_angle():
    g = SE2(angle_weight=0.5)
    pts = g.from_xytheta([0.0, 2.0, 4.0], [1.0, 1.0, 1.0], [np.pi - 0.1, -np.pi + 0.1, np.pi])
    x, y, theta = g.to_xytheta(g.split_mean(pts))
    assert (x, y) == pytest.approx((2.0, 1.0))
    assert abs(abs(theta) - np.pi) < 1e-12


# ---------------------------------------------------------------- SO(3)
def test_so3_log_near_pi_and_zero():
    axis = np.array([1.0, -2.0, 0.5]) / np.linalg.norm([1.0, -2.0, 0.5])
    for angle in (np.pi, np.pi - 1e-12, np.pi - 1e-9, np.pi - 1e-4, 1.0, 1e-9, 0.0):
        R = so3_exp(angle * axis)
        phi = so3_log(R)
        np.testing.assert_allclose(so3_exp(phi), R, atol=1e-12)
        assert np.linalg.norm(phi) == pytest.approx(angle, abs=1e-12)
        if 0 < angle < np.pi - 1e-10:
            np.testing.assert_allclose(phi, angle * axis, atol=1e-12)
    # batched, mixed regimes in one call
    angles = np.array([0.0, 1e-8, 0.5, np.pi - 1e-6, np.pi])
    np.testing.assert_allclose(np.linalg.norm(so3_log(so3_exp(angles[:, None] * axis)), axis=1),
                               angles, atol=1e-12)


# -------------------------------------------------------- homography metrics
def test_lie_distance_is_the_paper_metric():
    rng = np.random.default_rng(0)
    H, Hgt = random_homographies(60, rng), random_homographies(60, rng)
    ours = lie_distance(H, Hgt)
    ref = [np.linalg.norm(scipy.linalg.logm(np.linalg.inv(Hgt[i] / Hgt[i, 2, 2])
                                            @ (H[i] / H[i, 2, 2])), "fro") for i in range(60)]
    np.testing.assert_allclose(ours, ref, rtol=1e-9)
    # the group distance with h33 is the same number, and batching broadcasts
    np.testing.assert_allclose(Homography("h33").distance(Hgt, H), ours, rtol=1e-12)
    np.testing.assert_allclose(lie_distance(H.reshape(6, 10, 3, 3), Hgt[0]),
                               lie_distance(H, Hgt[0]).reshape(6, 10), rtol=1e-12)
    assert float(lie_distance(Hgt[0], 5.0 * Hgt[0])) == pytest.approx(0.0, abs=1e-12)


def test_homography_h33_is_not_left_invariant_but_det_is():
    rng = np.random.default_rng(3)
    a, b, G = (random_homographies(10, rng) for _ in range(3))
    h33, det = Homography("h33"), Homography("det")
    d0, d1 = h33.distance(a, b), h33.distance(G @ a, G @ b)
    assert np.max(np.abs(d1 - d0) / d0) > 1e-6  # close, but not exact
    np.testing.assert_allclose(det.distance(G @ a, G @ b), det.distance(a, b), rtol=1e-8)
    # det chart: traceless logarithms (8 degrees of freedom)
    np.testing.assert_allclose(np.trace(det.hat(det.log(a, b)), axis1=-2, axis2=-1), 0,
                               atol=1e-10)


def test_frobenius_distance():
    H = np.array([[1.0, 0.0, 2.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    assert float(frobenius_distance(3.0 * H, np.eye(3))) == pytest.approx(2.0)
    rng = np.random.default_rng(2)
    A, B = random_homographies(5, rng), random_homographies(5, rng)
    np.testing.assert_allclose(frobenius_distance(A, -2.0 * A), 0.0, atol=1e-12)
    np.testing.assert_allclose(frobenius_distance(A, -2.0 * A, normalization="det"), 0.0,
                               atol=1e-12)
    ref = np.linalg.norm(A / A[:, 2:, 2:] - B / B[:, 2:, 2:], axis=(1, 2))
    np.testing.assert_allclose(frobenius_distance(A, B), ref, rtol=1e-12)


# ------------------------------------------------------------------ logm
def test_logm_fast_path_matches_scipy_on_well_conditioned():
    rng = np.random.default_rng(1)
    A = np.concatenate([scipy.linalg.expm(0.5 * rng.standard_normal((40, 3, 3))),
                        random_homographies(40, rng)])
    L = logm(A)
    assert L.dtype == float
    _, fast = _matrix._logm3(A, True)
    assert fast.all()  # these never leave the closed-form tier
    np.testing.assert_allclose(L, scipy_logs(A), rtol=1e-9, atol=1e-10)
    # leading axes are kept
    assert logm(A.reshape(8, 10, 3, 3)).shape == (8, 10, 3, 3)


def test_logm_near_defective_and_fallback_match_scipy(monkeypatch):
    J = np.array([[2.0, 1.0, 0.0], [0.0, 2.0, 1.0], [0.0, 0.0, 2.0]])
    cases = np.stack([
        J,  # Jordan block: exact in the closed form
        J + 1e-9 * np.random.default_rng(4).standard_normal((3, 3)),
        [[1.5, 1e-9, 0.0], [0.0, 1.5, 0.0], [0.0, 0.0, 0.7]],  # repeated eigenvalue
        np.eye(3) + np.diag([1e-7, 0.0], 1),
        [[-1.0, 1.0, 0.0], [-1e-14, -1.0, 0.0], [0.0, 0.0, 1.0]],  # near-defective at -1
        -J,  # exactly defective at -2: still exact in the closed form
    ])
    calls = []
    original = _matrix._logm_scipy
    monkeypatch.setattr(_matrix, "_logm_scipy", lambda a, i: calls.append(i) or original(a, i))
    L = logm(cases)
    assert [c[0] for c in calls] == [4]  # only the matrix the fast tiers cannot do
    ref = scipy_logs(cases)
    np.testing.assert_allclose(L, ref, atol=1e-8)
    np.testing.assert_allclose(np.linalg.norm(L, axis=(1, 2)), np.linalg.norm(ref, axis=(1, 2)),
                               rtol=1e-10)


def test_logm_negative_eigenvalues_consistent_norm_across_tiers():
    rng = np.random.default_rng(5)
    Q = rng.standard_normal((20, 3, 3))
    D = np.einsum("nij,nj,njk->nik", Q, rng.uniform(0.3, 2.0, (20, 3)) * [-1, 1, 1],
                  np.linalg.inv(Q))
    L = logm(D)
    assert np.iscomplexobj(L)
    ref = scipy_logs(D)
    np.testing.assert_allclose(np.linalg.norm(L, axis=(1, 2)), np.linalg.norm(ref, axis=(1, 2)),
                               rtol=1e-8)
    eig_tier, ok = _matrix._logm_eig(D, True)
    assert ok.all()
    np.testing.assert_allclose(np.linalg.norm(eig_tier, axis=(1, 2)),
                               np.linalg.norm(ref, axis=(1, 2)), rtol=1e-8)
    B = np.diag([-1.0, 2.0, 1.0])
    np.testing.assert_allclose(logm(B), scipy.linalg.logm(B), atol=1e-14)


def test_logm_two_negative_eigenvalues_is_the_principal_log():
    # the cubic's roots put -0.0747 at -3e-15j (below the cut) and -32.6 on it: the
    # closed-form tier must not mix the sides (it gave a norm of 18.3 instead of 14.1)
    X = np.array([[-35.55927248339908, 38.60401043093029, -17.74566693866319],
                  [-11.759268227377852, 12.408125324028022, -5.34462174607001],
                  [-19.53938081589188, 20.84839396842319, -9.139903917940572]])
    rng = np.random.default_rng(6)
    Q = rng.standard_normal((20, 3, 3))
    D = np.einsum("nij,nj,njk->nik", Q, rng.uniform(0.05, 30.0, (20, 3)) * [-1, -1, 1],
                  np.linalg.inv(Q))
    A = np.concatenate([X[None], D])
    np.testing.assert_allclose(np.linalg.norm(logm(A), axis=(1, 2)),
                               np.linalg.norm(scipy_logs(A), axis=(1, 2)), rtol=1e-8)


def test_logm_other_sizes_complex_input_and_verify():
    rng = np.random.default_rng(6)
    for n in (1, 2, 4):
        A = scipy.linalg.expm(0.4 * rng.standard_normal((10, n, n)))
        np.testing.assert_allclose(logm(A), scipy_logs(A), atol=1e-10)
    C = np.eye(3) + 0.3 * (rng.standard_normal((10, 3, 3)) + 1j * rng.standard_normal((10, 3, 3)))
    np.testing.assert_allclose(logm(C), scipy_logs(C), atol=1e-10)
    A = random_homographies(10, rng)
    np.testing.assert_allclose(logm(A, verify=True), logm(A), atol=1e-12)
    np.testing.assert_allclose(scipy.linalg.expm(logm(A)), A, rtol=1e-9)


# ------------------------------------------------------------ bad input
def test_invalid_input_is_named():
    singular = np.array([[1.0, 2.0, 3.0], [2.0, 4.0, 6.0], [0.0, 1.0, 1.0]])
    with pytest.raises(ValueError, match=r"H: H\[2, 2\] is zero"):
        lie_distance(np.array([[1.0, 0, 0], [0, 1, 0], [0, 0, 0]]), np.eye(3))
    with pytest.raises(ValueError, match="H_gt: expected shape"):
        lie_distance(np.eye(3), np.eye(2))
    with pytest.raises(ValueError, match="H_gt: contains 1 non-finite"):
        lie_distance(np.eye(3), np.diag([1.0, np.nan, 1.0]))
    with pytest.raises(ValueError, match="H: contains 1 non-finite"):
        Homography().projection(np.array([[1.0, 0, 0], [0, np.nan, 0], [0, 0, 1]]))
    with pytest.raises(ValueError, match="H: 1 singular"):
        Homography("det").projection(singular)
    with pytest.raises(ValueError, match="point: 1 singular"):
        Homography("h33").log(singular, np.eye(3))
    with pytest.raises(ValueError, match="base_point: H\\[2, 2\\] is zero"):
        Homography("h33").log(np.eye(3), np.diag([1.0, 1.0, 0.0]) + np.eye(3)[[1, 2, 0]])
    with pytest.raises(ValueError, match="A: expected square"):
        logm(np.zeros((2, 3)))
    with pytest.raises(ValueError, match="A: matrix at index \\(1,\\) is singular"):
        logm(np.stack([np.eye(3), np.diag([1.0, 1.0, 0.0])]))
    with pytest.raises(ValueError, match="reference_points"):
        SE3().point_set_distance(np.eye(4), np.eye(4), np.zeros((3, 2)))
    with pytest.raises(ValueError, match="T2: expected shape"):
        SE3().relative_error(np.eye(4), np.eye(3))
    with pytest.raises(ValueError, match="theta: contains 1 non-finite"):
        SE2.from_xytheta(0.0, 0.0, np.nan)
    with pytest.raises(ValueError, match="R: expected shape"):
        so3_log(np.eye(4))
    with pytest.raises(ValueError, match="angle_weight"):
        SE3(angle_weight=0)
    with pytest.raises(ValueError, match="angle_weight"):
        SE2(angle_weight=-1.0)
    with pytest.raises(ValueError, match="normalization"):
        Homography("trace")
    with pytest.raises(ValueError, match="max_iter"):
        SE3().split_mean(SE3().identity((2,)), max_iter=0)
