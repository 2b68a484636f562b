import numpy as np
import pytest
import scipy.linalg

from clap_unified.geometry import SE3, Homography, frobenius_distance, lie_distance, logm, so3_exp
from clap_unified.geometry.so3 import so3_log


def test_lie_distance_is_the_paper_metric():
    rng = np.random.default_rng(0)
    g = Homography()
    H = g.projection(g.expmap(0.2 * rng.standard_normal((50, 9)))) * rng.uniform(0.5, 3, (50, 1, 1))
    Hgt = g.projection(g.expmap(0.2 * rng.standard_normal((50, 9))))
    ours = lie_distance(H, Hgt)
    ref = [np.linalg.norm(scipy.linalg.logm(np.linalg.inv(Hgt[i] / Hgt[i, 2, 2])
                                            @ (H[i] / H[i, 2, 2])), "fro") for i in range(50)]
    np.testing.assert_allclose(ours, ref, rtol=1e-9)
    assert lie_distance(Hgt[0], Hgt[0]) == pytest.approx(0.0, abs=1e-12)
    np.testing.assert_allclose(frobenius_distance(H, H * 2.0), 0.0, atol=1e-12)


def test_logm_fast_path_and_fallback_match_scipy():
    rng = np.random.default_rng(1)
    A = scipy.linalg.expm(0.5 * rng.standard_normal((40, 3, 3)))
    # near-defective: a Jordan block and an exactly repeated eigenvalue
    A[0] = [[2.0, 1.0, 0.0], [0.0, 2.0, 1.0], [0.0, 0.0, 2.0]]
    A[1] = [[1.5, 1e-9, 0.0], [0.0, 1.5, 0.0], [0.0, 0.0, 0.7]]
    ours = logm(A)
    for i in range(40):
        np.testing.assert_allclose(ours[i], scipy.linalg.logm(A[i]), atol=1e-8)
    # negative real eigenvalue: no real logarithm, complex result like scipy
    B = np.diag([-1.0, 2.0, 1.0])
    assert np.iscomplexobj(logm(B))
    np.testing.assert_allclose(np.linalg.norm(logm(B)), np.linalg.norm(scipy.linalg.logm(B)))


def test_so3_log_near_pi_and_zero():
    for angle in (np.pi - 1e-9, np.pi - 1e-4, 1e-9, 0.0):
        axis = np.array([1.0, -2.0, 0.5]) / np.linalg.norm([1.0, -2.0, 0.5])
        R = so3_exp(angle * axis)
        np.testing.assert_allclose(so3_exp(so3_log(R)), R, atol=1e-8)
        assert np.linalg.norm(so3_log(R)) == pytest.approx(angle, abs=1e-7)


def test_se3_paper_distances_on_hand_cases():
    g = SE3(angle_weight=2.0)
    T1 = g.identity()
    T2 = g.from_rt(so3_exp([0.0, 0.0, 0.3]), [1.0, 2.0, 2.0])
    e_t, e_r = g.relative_error(T1, T2)
    assert e_t == pytest.approx(3.0) and e_r == pytest.approx(0.3)
    P = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
    shift = g.from_rt(np.eye(3), [0.0, 0.0, 0.5])
    assert g.point_set_distance(T1, shift, P) == pytest.approx(0.5)
    pure_rot = g.from_rt(so3_exp([0.0, 0.0, 0.1]), np.zeros(3))
    assert g.distance(T1, pure_rot) == pytest.approx(0.2)  # lambda * angle


def test_invalid_input_is_named():
    with pytest.raises(ValueError, match="H: H\\[2, 2\\] is zero"):
        lie_distance(np.array([[1.0, 0, 0], [0, 1, 0], [0, 0, 0]]), np.eye(3))
    with pytest.raises(ValueError, match="H_gt: expected shape"):
        lie_distance(np.eye(3), np.eye(2))
    with pytest.raises(ValueError, match="contains 1 non-finite"):
        Homography().projection(np.array([[1.0, 0, 0], [0, np.nan, 0], [0, 0, 1]]))
    with pytest.raises(ValueError, match="reference_points"):
        SE3().point_set_distance(np.eye(4), np.eye(4), np.zeros((3, 2)))
    with pytest.raises(ValueError, match="angle_weight"):
        SE3(angle_weight=0)
    with pytest.raises(ValueError, match="normalization"):
        Homography("trace")
