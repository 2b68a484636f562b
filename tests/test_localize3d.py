"""3D localization: Kabsch, triplet spaces, the lab scenario, CLAP vs RANSAC vs Open3D."""

from itertools import combinations

import numpy as np
import pytest

from clap_unified.clap.density import dense_candidates
from clap_unified.geometry import SE3, so3_exp
from clap_unified.geometry.rigid import kabsch
from clap_unified.localization.localize3d import (
    align_correspondences,
    localize3d,
    pose_errors,
)
from clap_unified.localization.map3d import LandmarkMap3D, lab_map
from clap_unified.localization.scene3d import mocap_trajectory, simulate_detections
from clap_unified.spaces import generate_hypotheses
from clap_unified.spaces.landmarks3d import Landmark3DSpace
from clap_unified.spaces.rigid3d import Correspondence3DSpace, min_altitude

LAB = lab_map()
TRAJ = mocap_trajectory(30, rng=0)


def test_kabsch_batched_matches_truth_and_fixes_reflection():
    rng = np.random.default_rng(0)
    R0 = so3_exp(rng.normal(size=(5, 3)))
    t0 = rng.normal(size=(5, 3))
    P = rng.normal(size=(5, 6, 3))
    Q = np.einsum("bij,bkj->bki", R0, P) + t0[:, None]
    R, t = kabsch(P, Q)
    assert np.allclose(R, R0, atol=1e-10) and np.allclose(t, t0, atol=1e-10)
    # a planar set mirrored: the best proper rotation, never a reflection
    flat = np.c_[rng.normal(size=(6, 2)), np.zeros(6)]
    mirrored = flat * [1.0, -1.0, 1.0] + rng.normal(0, 0.01, (6, 3))
    R, _ = kabsch(flat, mirrored)
    assert np.isclose(np.linalg.det(R), 1.0)


def test_kabsch_bad_input():
    with pytest.raises(ValueError, match="target"):
        kabsch(np.zeros((4, 3)), np.zeros((5, 3)))
    with pytest.raises(ValueError, match="at least 3"):
        kabsch(np.zeros((2, 3)), np.zeros((2, 3)))
    with pytest.raises(ValueError, match="weights"):
        kabsch(np.eye(3), np.eye(3), weights=[-1.0, 0.0, 0.0])


def test_collinear_and_distance_checks_reject_triplets():
    p = np.array([[0.0, 0, 0], [1.0, 0, 0], [2.0, 0.01, 0], [0.0, 2.0, 0]])
    assert min_altitude(p[[0, 1, 2]][None])[0] < 0.02
    space = Correspondence3DSpace()
    data = np.c_[p, p + 1.0]
    models, owner = space.solve_minimal(data, np.array([[0, 1, 2], [0, 1, 3]]))
    assert owner.tolist() == [1]                       # collinear triplet rejected
    data[3, 3:] += [0.0, 0.5, 0.0]                     # distances disagree by 0.5 m
    assert len(space.solve_minimal(data, np.array([[0, 1, 3]]))[0]) == 0


def test_typed_space_finds_true_pose_among_matches():
    space = LAB.space()
    det = simulate_detections(LAB, TRAJ[3], outlier_ratio=0.0, miss_rate=0.0, rng=0)
    hyps = generate_hypotheses(space, det.input.data, 500, rng=0)
    e = [pose_errors(T, det.truth.pose) for T in hyps.models]
    assert min(et for et, _ in e) < 0.05
    # the residual of a correct detection under the truth is the noise only
    r = space.residuals(det.truth.pose[None], det.input.data)[0]
    assert np.all(r[~det.truth.is_outlier] < 0.1)


def test_typed_space_bad_input():
    with pytest.raises(ValueError, match="types"):
        Landmark3DSpace(np.eye(3), ["a", "b"])
    space = Landmark3DSpace(np.eye(3), ["a", "b", "b"])
    with pytest.raises(ValueError, match="not a landmark type"):
        space.observations_array([{"type": "zz", "x": 0, "y": 0, "z": 0}])
    with pytest.raises(ValueError, match="type id"):
        space.check_data(np.array([[5.0, 0, 0, 0]] * 3))
    with pytest.raises(ValueError, match="metric"):
        Landmark3DSpace(np.eye(3), "abc", metric="frobenius")
    with pytest.raises(ValueError, match="positions"):
        LandmarkMap3D(np.array(["a"]), np.zeros((1, 3)))


def test_localize3d_too_few_observations_is_a_failure_value():
    res = localize3d(np.array([[0.0, 1, 2, 3]]), LAB)
    assert not res and "at least 3" in res.reason


def test_scenario_is_seeded_and_has_the_requested_outlier_ratio():
    a = simulate_detections(LAB, TRAJ[5], outlier_ratio=0.6, rng=3)
    b = simulate_detections(LAB, TRAJ[5], outlier_ratio=0.6, rng=3)
    assert np.array_equal(a.input.data, b.input.data)
    assert abs(a.truth.outlier_ratio - 0.6) < 0.05
    assert set(a.truth.kind) <= {"landmark", "random", "wrong_type"}
    with pytest.raises(ValueError, match="outlier_ratio"):
        simulate_detections(LAB, TRAJ[5], outlier_ratio=1.0)


@pytest.mark.parametrize("frame", [2, 9, 17, 24])
def test_clap_within_5cm_1deg_at_60_percent_outliers_ransac_beside(frame):
    det = simulate_detections(LAB, TRAJ[frame], outlier_ratio=0.6, rng=frame)
    space = LAB.space()
    hyps = generate_hypotheses(space, det.input.data, 1000, rng=frame)
    clap_res = localize3d(det.input.data, LAB, space=space, hypotheses=hyps)
    ransac_res = localize3d(det.input.data, LAB, method="ransac", space=space, hypotheses=hyps)
    e_t, e_r = pose_errors(clap_res.model, det.truth.pose)
    assert e_t < 0.05 and e_r < 1.0
    # RANSAC on the same candidates: measured beside, and on this easy typed
    # scene it is as accurate (the distance check leaves few wrong candidates)
    r_t, r_r = pose_errors(ransac_res.model, det.truth.pose)
    assert r_t < 0.05 and r_r < 1.0
    assert clap_res.n_inliers >= np.count_nonzero(~det.truth.is_outlier) - 2


def test_correspondences_60_percent_outliers_same_budget():
    errors = {"clap": [], "ransac": []}
    for f in range(0, 30, 3):
        det = simulate_detections(LAB, TRAJ[f], outlier_ratio=0.6, rng=50 + f,
                                  prior_error=(0.2, np.radians(2.0)))
        data = det.input.correspondences(LAB)
        for m in errors:
            res = align_correspondences(data, method=m, n_hypotheses=1000, rng=f)
            errors[m].append(pose_errors(res.model, det.truth.pose) if res else (np.inf, np.inf))
    for m, e in errors.items():
        e = np.array(e)
        ok = (e[:, 0] < 0.05) & (e[:, 1] < 1.0)
        assert ok.mean() >= 0.9, (m, e)


def test_clap_needs_several_agreeing_candidates_where_ransac_needs_one():
    # 80 % outliers, 100 triplets: about one all-inlier triplet. RANSAC can
    # win with one; CLAP needs min_support = 3 agreeing candidates.
    rng = np.random.default_rng(1)
    p = rng.uniform(-4, 4, (50, 3))
    q = p + [1.0, 0.0, 0.0] + rng.normal(0, 0.01, (50, 3))
    q[:40] = rng.uniform(-4, 4, (40, 3))
    ok = {"clap": 0, "ransac": 0}
    for seed in range(20):
        for m in ok:
            res = align_correspondences(np.c_[p, q], method=m, n_hypotheses=100, rng=seed)
            ok[m] += bool(res) and np.allclose(res.model[:3, 3], [1, 0, 0], atol=0.05)
    assert ok["ransac"] > ok["clap"]


def test_metric_and_centre_choices_agree_on_an_easy_frame():
    det = simulate_detections(LAB, TRAJ[12], outlier_ratio=0.5, rng=7)
    for metric in ("relative", "lie", "point_set"):
        for centre in ("medoid", "karcher", "log_euclidean", "split"):
            space = LAB.space(metric=metric)
            res = localize3d(det.input.data, LAB, space=space, centre=centre, rng=0)
            e_t, e_r = pose_errors(res.model, det.truth.pose)
            assert e_t < 0.05 and e_r < 1.0, (metric, centre)


def test_relative_metric_and_chordal_bound():
    g = SE3(2.0, metric="relative")
    T = g.random(40, rng=0, scale=0.5)
    D = g.pairwise_distance(T)
    e = g.chordal_embedding(T)
    C = np.linalg.norm(e[:, None] - e[None], axis=-1)
    assert np.all(C <= D + 1e-12)
    e_t, e_r = g.relative_error(T[:, None], T[None])
    assert np.allclose(D, np.sqrt(e_t**2 + 4 * e_r**2), atol=1e-9)
    keep = dense_candidates(g, np.r_[T[:1].repeat(4, 0), T], 1e-6, 4)
    assert keep.tolist() == [0, 1, 2, 3, 4]


def test_type_correspondences_and_open3d_run():
    det = simulate_detections(LAB, TRAJ[6], outlier_ratio=0.5, rng=4)
    space = LAB.space()
    source, target, corr = space.correspondences(det.input.data)
    assert source.shape == (len(det.input.data), 3) and target is space.positions
    ids = det.input.data[corr[:, 0], 0].astype(int)
    assert np.array_equal(ids, space.type_ids[corr[:, 1]])
    res = localize3d(det.input.data, LAB, method="open3d", rng=0)
    e_t, e_r = pose_errors(res.model, det.truth.pose)
    assert res and e_t < 0.05 and e_r < 1.0


def test_cluster_members_index_the_given_candidates():
    det = simulate_detections(LAB, TRAJ[7], outlier_ratio=0.6, rng=11)
    space = LAB.space()
    hyps = generate_hypotheses(space, det.input.data, 1000, rng=0)
    res = localize3d(det.input.data, LAB, space=space, hypotheses=hyps)
    members = res.clusters[0].members
    assert res.support.shape == (len(hyps),) and res.support[members].all()
    e_t, e_r = space.manifold.relative_error(res.clusters[0].model, hyps.models[members])
    assert np.all(np.sqrt(e_t**2 + 4 * e_r**2) <= 2 * 0.15 + 1e-9)   # within 2 bandwidths


def test_local_mode_around_a_prior():
    det = simulate_detections(LAB, TRAJ[20], outlier_ratio=0.8, rng=21)
    space = LAB.space()
    hyps = generate_hypotheses(space, det.input.data, 1000, rng=0)
    nudge = SE3.from_rt(so3_exp([0.0, 0.0, np.radians(4.0)]), [0.2, -0.1, 0.05])
    prior = det.truth.pose @ nudge
    for method in ("clap", "ransac"):
        res = localize3d(det.input.data, LAB, method=method, space=space, hypotheses=hyps,
                         prior=prior)
        e_t, e_r = pose_errors(res.model, det.truth.pose)
        assert res and e_t < 0.05 and e_r < 1.0, method
        assert 0 < res.diagnostics["near_prior"] < len(hyps)
        supported = hyps.models[res.support]
        assert res.support.shape == (len(hyps),) and len(supported) > 0
        e_t, _ = space.manifold.relative_error(prior, supported)
        assert np.all(e_t <= 0.5)               # only candidates near the prior
    far = det.truth.pose @ SE3.from_rt(np.eye(3), [5.0, 0.0, 0.0])
    res = localize3d(det.input.data, LAB, space=space, hypotheses=hyps, prior=far)
    assert not res and "of the prior" in res.reason
    with pytest.raises(ValueError, match="prior"):
        localize3d(det.input.data, LAB, space=space, prior=np.eye(3))
    with pytest.raises(ValueError, match="max_rotation"):
        localize3d(det.input.data, LAB, space=space, prior=prior, max_rotation=-1.0)


def test_point_set_metric_matches_point_set_distance_and_needs_points():
    X = np.random.default_rng(0).normal(size=(7, 3))
    g = SE3(metric="point_set", reference_points=X)
    T = SE3().random(6, rng=1)
    assert np.allclose(g.distance(T[:3], T[3:]), SE3().point_set_distance(T[:3], T[3:], X))
    with pytest.raises(ValueError, match="reference_points"):
        SE3(metric="point_set")
    with pytest.raises(ValueError, match="metric"):
        SE3(metric="chordal")


def test_triplet_matching_in_chunks_gives_the_same_candidates(monkeypatch):
    import clap_unified.spaces.landmarks3d as mod

    det = simulate_detections(LAB, TRAJ[8], outlier_ratio=0.5, rng=2)
    space = LAB.space()
    samples = np.array(list(combinations(range(len(det)), 3)))
    whole = space.match_triplets(det.input.data, samples)
    monkeypatch.setattr(mod, "MASK_LIMIT", 7 * len(LAB) ** 2)   # chunks of 7 triplets
    parts = space.match_triplets(det.input.data, samples)
    assert len(whole[0]) > 0
    assert np.array_equal(whole[0], parts[0]) and np.array_equal(whole[1], parts[1])
