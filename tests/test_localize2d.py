"""2D localization on the RoboCup field: simulator, one-frame estimators, tracking."""

import numpy as np
import pytest

from clap_unified.geometry import SE2
from clap_unified.localization import (
    Camera,
    frames_at_rates,
    load_field,
    localize2d,
    random_frames,
    simulate_observations,
    visible_landmarks,
)
from clap_unified.localization.ekf import PoseEKF
from clap_unified.localization.localize2d import MIRROR, pose_error
from clap_unified.localization.mcl import ParticleFilter
from clap_unified.localization.tracking import (
    simulate_frames,
    track_clap_ekf,
    track_mcl,
    tracking_summary,
)
from clap_unified.localization.trajectory import walk_trajectory
from clap_unified.spaces import generate_hypotheses
from clap_unified.spaces.landmarks2d import Landmark2DSpace

FIELD = load_field("adult")
SPACE = Landmark2DSpace(FIELD)


def scenes_with_false_positives(rate, n, seed, min_true=4):
    frames = random_frames(FIELD, n, false_positive_rate=rate, min_true=min_true, rng=seed)
    return [(obs.truth.pose, obs) for obs in frames]


# ----------------------------------------------------------------- simulator
def test_frames_at_rates_share_poses_and_true_detections_across_rates():
    rates = [0.0, 0.3, 0.6]
    per_rate = frames_at_rates(FIELD, 6, rates, rng=3)
    assert [len(frames) for frames in per_rate] == [6, 6, 6]
    for k in range(6):
        frames = [per_rate[i][k] for i in range(3)]
        true_rows = [sorted(map(tuple, f.input.data[~f.truth.is_false].tolist()))
                     for f in frames]
        assert true_rows[0] == true_rows[1] == true_rows[2]
        assert len(true_rows[0]) >= 3
        for f in frames[1:]:
            np.testing.assert_array_equal(f.truth.pose, frames[0].truth.pose)
        n_true = len(true_rows[0])
        assert [int(f.truth.is_false.sum()) for f in frames] == [
            round(n_true * r / (1 - r)) for r in rates]
    again = frames_at_rates(FIELD, 6, rates, rng=3)
    np.testing.assert_array_equal(again[2][5].input.data, per_rate[2][5].input.data)


@pytest.mark.parametrize("rates, match", [([], "false_positive_rates"),
                                          (0.3, "false_positive_rates"),
                                          (None, "false_positive_rates"),
                                          (["a"], "false_positive_rates"),
                                          ([0.2, float("nan")], "false_positive_rates"),
                                          ([1.0], "false_positive_rates")])
def test_frames_at_rates_rejects_bad_rates(rates, match):
    with pytest.raises(ValueError, match=match):
        frames_at_rates(FIELD, 2, rates, rng=0)


def test_simulator_is_seeded_and_counts_false_positives():
    truth = SE2.from_xytheta(3.0, 1.0, 0.2)
    a = simulate_observations(FIELD, truth, false_positive_rate=0.4, rng=5)
    b = simulate_observations(FIELD, truth, false_positive_rate=0.4, rng=5)
    np.testing.assert_array_equal(a.input.data, b.input.data)
    t = a.truth
    n_true = np.count_nonzero(~t.is_false)
    assert np.count_nonzero(t.is_false) == round(n_true * 0.4 / 0.6)
    assert set(t.kind[t.is_false]) <= {"random", "wrong_type", "neighbour"}
    # true detections are near their landmarks, seen from the pose
    local = (np.linalg.inv(truth) @ np.c_[FIELD.positions[t.landmark[~t.is_false]],
                                          np.ones(n_true)].T).T[:, :2]
    assert np.max(np.linalg.norm(local - a.input.data[~t.is_false, 1:], axis=1)) < 0.5
    np.testing.assert_allclose(t.clean[~t.is_false], local, atol=1e-12)
    assert len(a.input.to_dicts()) == len(a)


def test_noise_grows_with_range_and_camera_limits_the_view():
    cam = Camera(sigma_range=0.01, range_growth=0.01, sigma_bearing=0.0)
    truth = SE2.from_xytheta(-1.0, 0.0, 0.0)
    errs = {True: [], False: []}
    for seed in range(200):
        obs = simulate_observations(FIELD, truth, camera=cam, miss_rate=0.0, rng=seed)
        local = FIELD.positions[obs.truth.landmark] - [-1.0, 0.0]
        r = np.linalg.norm(local, axis=1)
        err = np.linalg.norm(obs.input.data[:, 1:] - local, axis=1)
        for far in (True, False):
            errs[far].extend(err[(r > 4.0) == far])
    assert np.std(errs[True]) > 3 * np.std(errs[False])
    seen = visible_landmarks(FIELD, truth, cam)
    assert np.all(FIELD.positions[seen, 0] > -1.0)  # facing +x with a 90 degree view
    assert np.all(np.linalg.norm(FIELD.positions[seen] - [-1.0, 0.0], axis=1) <= cam.max_range)


@pytest.mark.parametrize("kwargs, match", [
    (dict(miss_rate=1.5), "miss_rate"),
    (dict(false_positive_rate=1.0), "false_positive_rate"),
    (dict(false_kinds=("ghost",)), "false_kinds"),
    (dict(pose=np.eye(2)), "pose"),
])
def test_simulator_rejects_bad_arguments(kwargs, match):
    args = dict(pose=SE2.from_xytheta(0.0, 0.0, 0.0))
    args.update(kwargs)
    with pytest.raises(ValueError, match=match):
        simulate_observations(FIELD, **args)


def test_camera_rejects_bad_geometry():
    with pytest.raises(ValueError, match="fov"):
        Camera(fov=7.0)
    with pytest.raises(ValueError, match="min_range"):
        Camera(min_range=8.0, max_range=6.0)


# ------------------------------------------------------ one-frame estimators
def test_clap_global_recovers_pose_or_mirror_pair_at_40_percent_false_positives():
    scenes = scenes_with_false_positives(0.4, 20, seed=11)
    ok = []
    for truth, obs in scenes:
        res = localize2d(obs.input, FIELD)
        assert res.success
        top = [c for c in res.clusters if c.support == res.clusters[0].support]
        # the field is point-symmetric: truth and mirror both lead, with equal support
        found = [min(pose_error(c.model, t) for c in top) for t in (truth, MIRROR @ truth)]
        ok.append(all(e[0] < 0.10 and e[1] < 2.0 for e in found))
        # the reported pose is one of the two (after the refit)
        best = pose_error(res.model, truth, up_to_symmetry=True)
        ok[-1] &= best[0] < 0.10 and best[1] < 2.0
    assert np.mean(ok) >= 0.85, f"{np.mean(ok):.2f} of scenes recovered"


def test_ransac_and_randomized_hough_on_identical_candidates_measured_beside_clap():
    scenes = scenes_with_false_positives(0.4, 20, seed=12)
    rates = {}
    for method in ("clap", "ransac", "randomized_hough"):
        good = 0
        for truth, obs in scenes:
            hyps = generate_hypotheses(SPACE, obs.input.data, 20000)
            res = localize2d(obs.input, space=SPACE, hypotheses=hyps, method=method)
            err = pose_error(res.model, truth, up_to_symmetry=True)
            good += res.success and err[0] < 0.10 and err[1] < 2.0
        rates[method] = good / len(scenes)
    # measured 0.85 / 0.90 / 0.90: one scene has a second arrangement of the
    # visible features that ties with the truth in CLAP's support (3 candidates
    # each) while RANSAC's inlier count (4 vs 3) tells them apart
    assert rates["clap"] >= 0.8 and rates["ransac"] >= 0.8, rates
    assert rates["randomized_hough"] >= 0.7, rates


def test_local_mode_picks_the_true_pose_not_its_mirror():
    truth, obs = scenes_with_false_positives(0.4, 1, seed=13)[0]
    prior = truth @ SE2.from_xytheta(0.2, -0.15, np.radians(6))
    res = localize2d(obs.input, FIELD, prior=prior)
    dist, ang = pose_error(res.model, truth)
    assert res.success and dist < 0.10 and ang < 2.0
    for method in ("clap", "ransac", "randomized_hough"):
        r = localize2d(obs.input, FIELD, method=method, prior=(0.0, -5.4, 1.0), radius=0.3)
        assert not r.success and ("radius" in r.reason or "candidate" in r.reason), r.reason


def test_too_few_observations_fail_with_a_reason_and_bad_input_is_named():
    res = localize2d([{"type": "L", "x": 1.0, "y": 0.0}], "adult")
    assert not res.success and "at least 2" in res.reason
    with pytest.raises(ValueError, match="unknown type"):
        localize2d([{"type": "corner", "x": 1.0, "y": 0.0}] * 2)
    with pytest.raises(ValueError, match="observations"):
        localize2d(np.zeros((3, 2)))
    with pytest.raises(ValueError, match="prior"):
        localize2d(np.zeros((3, 3)), prior=(0.0, np.nan, 0.0))
    with pytest.raises(ValueError, match="method"):
        localize2d(np.zeros((3, 3)), method="icp")


def test_same_seed_same_result_when_pairs_are_sampled():
    truth, obs = scenes_with_false_positives(0.4, 1, seed=14)[0]
    a = localize2d(obs.input, FIELD, n_hypotheses=5, rng=3)
    b = localize2d(obs.input, FIELD, n_hypotheses=5, rng=3)
    np.testing.assert_array_equal(a.model, b.model)


# ------------------------------------------------------------------ tracking
def test_ekf_gates_the_mirror_and_tracks_odometry():
    ekf = PoseEKF((1.0, 2.0, 0.3), np.diag([0.01, 0.01, 0.001]))
    ekf.predict((0.1, 0.0, 0.05))
    np.testing.assert_allclose(ekf.mean[:2], [1.0 + 0.1 * np.cos(0.3), 2.0 + 0.1 * np.sin(0.3)])
    R = np.diag([0.01, 0.01, 0.001])
    assert not ekf.update(SE2.to_xytheta(MIRROR @ SE2.from_xytheta(*ekf.mean)), R)
    assert ekf.update(ekf.mean + [0.05, 0.0, 0.01], R)


def test_clap_ekf_tracks_a_walk_with_false_positives_and_mcl_runs_beside_it():
    walk = walk_trajectory(FIELD, 80, rng=2)
    frames = [f.input for f in simulate_frames(FIELD, walk, false_positive_rate=0.4, rng=3)]
    start = walk.truth.xytheta[0]  # robots enter the field from known positions
    clap_run = track_clap_ekf(FIELD, walk.input, frames, initial=start)
    s = tracking_summary(clap_run, walk.truth)
    assert s["position_median"] < 0.10 and s["diverged"] == 0.0 and s["jumps"] == 0
    mcl_run = track_mcl(FIELD, walk.input, frames, initial=start, rng=0)
    m = tracking_summary(mcl_run, walk.truth)
    assert np.isfinite(m["position_median"]) and mcl_run.estimates.shape == (80, 3)
    again = track_mcl(FIELD, walk.input, frames, initial=start, rng=0)
    np.testing.assert_array_equal(mcl_run.estimates, again.estimates)


def test_clap_recovers_from_a_push_the_odometry_did_not_see():
    walk = walk_trajectory(FIELD, 120, pushes=1, push_size=(0.8, np.radians(40.0)), rng=4)
    frames = [f.input for f in simulate_frames(FIELD, walk, false_positive_rate=0.2, rng=5)]
    run = track_clap_ekf(FIELD, walk.input, frames, initial=walk.truth.xytheta[0])
    pos = np.hypot(*(run.estimates[:, :2] - walk.truth.xytheta[:, :2]).T)
    assert np.median(pos[-20:]) < 0.15  # back on track by the end


def test_estimators_refuse_a_frame_that_carries_its_truth():
    truth, obs = scenes_with_false_positives(0.4, 1, seed=15)[0]
    with pytest.raises(ValueError, match="observations"):
        localize2d(obs, FIELD)
    walk = walk_trajectory(FIELD, 5, rng=1)
    frames = simulate_frames(FIELD, walk, rng=2)
    with pytest.raises(ValueError, match="frames"):
        track_clap_ekf(FIELD, walk.input, frames, initial=walk.truth.xytheta[0])
    with pytest.raises(ValueError, match="odometry"):
        track_mcl(FIELD, walk, [f.input for f in frames], initial=(0.0, 0.0, 0.0))
    with pytest.raises(ValueError, match="truth"):
        tracking_summary(track_mcl(FIELD, walk.input, [f.input for f in frames],
                                   initial=(0.0, 0.0, 0.0), rng=0), walk)


def test_particle_filter_validates_its_arguments():
    with pytest.raises(ValueError, match="n_particles"):
        ParticleFilter(FIELD, 0)
    with pytest.raises(ValueError, match="false_rate"):
        ParticleFilter(FIELD, 10, false_rate=2.0)
