"""The one weighted Kabsch (d = 2, 3) and the one nearest-same-type-landmark query."""

import numpy as np
import pytest

from clap_unified.geometry.rigid import kabsch, pose_from_rt, transform_points, weighted_kabsch
from clap_unified.maps.nearest import nearest_of_type


def svd_kabsch(P, Q, w):
    """Textbook weighted Kabsch in any dimension: SVD of the cross-covariance, reflection fixed."""
    w = w / w.sum()
    cp, cq = w @ P, w @ Q
    H = sum(w[k] * np.outer(P[k] - cp, Q[k] - cq) for k in range(len(P)))
    U, _, Vt = np.linalg.svd(H)
    D = np.eye(P.shape[1])
    D[-1, -1] = 1.0 if np.linalg.det(Vt.T @ U.T) >= 0 else -1.0
    R = Vt.T @ D @ U.T
    return R, cq - R @ cp


@pytest.mark.parametrize("d", [2, 3])
def test_kabsch_matches_the_svd_solution_in_the_plane_and_in_space(d):
    """The 2D closed form (atan2 of the cross-covariance) is the SVD's optimum, batched."""
    rng = np.random.default_rng(d)
    P = rng.normal(size=(40, 6, d))
    Q = P[..., ::-1] * [1.0] * d + rng.normal(0, 0.3, (40, 6, d))  # mirrored, noisy
    w = rng.random((40, 6))
    R, t = kabsch(P, Q, w)
    assert np.allclose(np.linalg.det(R), 1.0)
    for s in range(40):
        Rr, tr = svd_kabsch(P[s], Q[s], w[s])
        assert np.allclose(R[s], Rr, atol=1e-9) and np.allclose(t[s], tr, atol=1e-9)


def test_kabsch_recovers_a_planar_motion_exactly():
    rng = np.random.default_rng(1)
    theta = rng.uniform(-np.pi, np.pi, 8)
    c, s = np.cos(theta), np.sin(theta)
    R0 = np.stack([[c, -s], [s, c]]).transpose(2, 0, 1)
    t0 = rng.normal(size=(8, 2))
    P = rng.normal(size=(8, 2, 2))  # two points fix a planar motion
    R, t = kabsch(P, np.einsum("bij,bkj->bki", R0, P) + t0[:, None])
    assert np.allclose(R, R0, atol=1e-10) and np.allclose(t, t0, atol=1e-10)


def test_kabsch_names_the_bad_argument():
    with pytest.raises(ValueError, match="dimension 2 or 3"):
        kabsch(np.zeros((4, 4)), np.zeros((4, 4)))
    with pytest.raises(ValueError, match="at least 2"):
        kabsch(np.zeros((1, 2)), np.zeros((1, 2)))
    with pytest.raises(ValueError, match="target"):
        kabsch(np.zeros((3, 2)), np.zeros((3, 3)))


def test_weighted_kabsch_reports_an_undetermined_rotation():
    P = np.ones((3, 2))  # one point three times: no rotation
    _, _, H = weighted_kabsch(P, P, np.full(3, 1 / 3))
    assert np.linalg.norm(H) == 0.0


def test_pose_from_rt_and_transform_points_round_trip():
    rng = np.random.default_rng(2)
    R, t = kabsch(rng.normal(size=(3, 4, 3)), rng.normal(size=(3, 4, 3)))
    T = pose_from_rt(R, t)
    pts = rng.normal(size=(5, 3))
    assert np.allclose(transform_points(T, pts), np.einsum("hij,nj->hni", R, pts) + t[:, None])


def test_nearest_of_type_matches_brute_force():
    rng = np.random.default_rng(3)
    marks, kinds = rng.normal(0, 3, (30, 2)), rng.integers(0, 4, 30)
    pts, types = rng.normal(0, 3, (7, 20, 2)), rng.integers(0, 5, 20)  # type 4: not on the map
    distance, index = nearest_of_type(pts, types, marks, kinds)
    for h in range(7):
        for n in range(20):
            members = np.flatnonzero(kinds == types[n])
            if len(members) == 0:
                assert distance[h, n] == np.inf and index[h, n] == -1
                continue
            d = np.linalg.norm(marks[members] - pts[h, n], axis=1)
            assert index[h, n] == members[d.argmin()]
            assert np.isclose(distance[h, n], d.min(), rtol=1e-12)


def test_nearest_of_type_whole_map_and_type_by_type_agree_bit_for_bit(monkeypatch):
    """Few poses run against the whole map at once, many type by type: the same numbers."""
    import clap_unified.maps.nearest as nearest

    rng = np.random.default_rng(4)
    marks, kinds = rng.normal(0, 3, (25, 3)), rng.integers(0, 4, 25)
    kinds[kinds == 3] = 0  # type 3: not on the map
    pts, types = rng.normal(0, 3, (9, 30, 3)), rng.integers(0, 4, 30)
    pts[0, :5] = marks[:5]  # exact hits, and ties between equal landmarks
    marks[7] = marks[6]
    assert 9 * 30 * 25 <= nearest.WHOLE_MAP_LIMIT  # the first call runs on the whole map
    whole = nearest.nearest_of_type(pts, types, marks, kinds)
    monkeypatch.setattr(nearest, "WHOLE_MAP_LIMIT", 0)
    by_type = nearest.nearest_of_type(pts, types, marks, kinds)
    for a, b in zip(whole, by_type, strict=True):
        assert np.array_equal(a, b)
    assert (whole[1][:, types == 3] == -1).all() and np.isinf(whole[0][:, types == 3]).all()


@pytest.mark.parametrize("limit", [0, 10**9])
def test_nearest_of_type_takes_lists_and_an_empty_map_on_both_paths(monkeypatch, limit):
    import clap_unified.maps.nearest as nearest

    monkeypatch.setattr(nearest, "WHOLE_MAP_LIMIT", limit)
    d, i = nearest.nearest_of_type([[[0.0, 1.0]]], [0], [[0.0, 0.0], [5.0, 5.0]], [0, 0])
    assert d.tolist() == [[1.0]] and i.tolist() == [[0]]
    d, i = nearest.nearest_of_type([[[0.0, 1.0]]], [0], np.zeros((0, 2)), [])
    assert np.isinf(d).all() and (i == -1).all()
