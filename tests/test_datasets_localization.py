"""Every localization generator keeps the estimator's input apart from the evaluation data.

For each generator: the result is a frozen ``input`` / ``truth`` pair with
read-only arrays; no evaluation row (noise-free landmark positions, the true
pose) is among the input rows; and the input is what the estimator needs
(it localizes from the input alone).
"""

import dataclasses

import numpy as np
import pytest
from split_checks import assert_rows_disjoint, assert_split

from clap_unified.geometry import SE2, SE3
from clap_unified.localization import load_field, localize2d, simulate_observations
from clap_unified.localization.localize3d import localize3d, pose_errors
from clap_unified.localization.map3d import lab_map
from clap_unified.localization.scene3d import (
    associate_nearest,
    mocap_trajectory,
    simulate_detections,
)
from clap_unified.localization.tracking import simulate_frames, track_clap_ekf
from clap_unified.localization.trajectory import walk_trajectory

FIELD = load_field("adult")
LAB = lab_map()


def _field_names(part):
    return {f.name for f in dataclasses.fields(part)}


def _pose_rows(T):
    """The true pose as rows an input could hold: its translation and its rotation's rows."""
    T = np.asarray(T, dtype=float)
    d = T.shape[0] - 1
    return np.r_[T[:d, d][None], T[:d, :d], T[:d, :d].T]


# ------------------------------------------------------------------- 2D frames
def test_2d_observations_split_and_input_rows_hold_no_evaluation_data():
    truth = SE2.from_xytheta(3.0, 1.0, 0.2)
    obs = simulate_observations(FIELD, truth, false_positive_rate=0.4,
                                false_kinds=("wrong_type", "neighbour"), rng=1)
    assert_split(obs)
    assert _field_names(obs.input) == {"data"}
    assert _field_names(obs.truth) == {"pose", "landmark", "kind", "clean"}
    with pytest.raises(dataclasses.FrozenInstanceError):
        obs.input.data = obs.truth.clean
    with pytest.raises(ValueError):
        obs.input.data[0, 1] = 0.0
    xy = obs.input.data[:, 1:]
    clean = obs.truth.clean[np.isfinite(obs.truth.clean[:, 0])]
    assert len(clean) == len(obs)           # every detection here has a landmark behind it
    assert_rows_disjoint(xy, clean, atol=1e-9)       # noise-free positions are not input
    np.testing.assert_allclose(obs.truth.pose, truth)
    # the true pose is not reachable from the input: no row is its translation
    assert_rows_disjoint(xy, SE2.to_xytheta(truth)[None, :2], atol=1e-6)
    # ... and the input is what the estimator needs
    res = localize2d(obs.input, FIELD, prior=(2.9, 1.1, 0.25))
    x, y, th = SE2.to_xytheta(res.model)
    assert res and abs(x - 3.0) < 0.1 and abs(y - 1.0) < 0.1 and abs(th - 0.2) < 0.03


def test_walk_split_the_odometry_is_not_the_true_motion():
    walk = walk_trajectory(FIELD, 40, pushes=1, rng=3)
    assert_split(walk)
    assert _field_names(walk.input) == {"odometry", "dt"}
    assert _field_names(walk.truth) == {"poses", "pushes"}
    from clap_unified.localization.trajectory import relative_motion

    true_steps = relative_motion(walk.truth.poses[:-1], walk.truth.poses[1:])
    assert_rows_disjoint(walk.input.odometry, true_steps, atol=1e-9)
    assert_rows_disjoint(walk.input.odometry, walk.truth.xytheta, atol=1e-6)
    frames = simulate_frames(FIELD, walk, false_positive_rate=0.2, rng=4)
    for f in frames:
        assert_split(f)
    run = track_clap_ekf(FIELD, walk.input, [f.input for f in frames],
                         initial=walk.truth.xytheta[0])
    assert run.estimates.shape == (40, 3)


# ------------------------------------------------------------------- 3D frames
def test_3d_detections_split_and_input_rows_hold_no_evaluation_data():
    poses = mocap_trajectory(20, rng=0)
    assert not poses.flags.writeable
    det = simulate_detections(LAB, poses[4], outlier_ratio=0.6, rng=2)
    assert_split(det)
    assert _field_names(det.input) == {"data", "type_names", "prior", "association"}
    assert det.input.prior is None and det.input.association is None
    assert _field_names(det.truth) == {"pose", "landmark", "kind", "clean"}
    with pytest.raises(ValueError, match="association"):
        det.input.correspondences(LAB)
    xyz = det.input.data[:, 1:]
    clean = det.truth.clean[np.isfinite(det.truth.clean[:, 0])]
    assert len(clean) == np.count_nonzero(det.truth.kind != "random") > 0
    assert_rows_disjoint(xyz, clean, atol=1e-9)
    # neither the map positions (world frame) nor the pose's rows are input rows
    assert_rows_disjoint(xyz, LAB.positions, atol=1e-6)
    assert_rows_disjoint(xyz, _pose_rows(det.truth.pose), atol=1e-6)
    res = localize3d(det.input, LAB, rng=0)
    e_t, e_r = pose_errors(res.model, det.truth.pose)
    assert res and e_t < 0.05 and e_r < 1.0


def test_3d_association_comes_from_a_pose_guess_not_from_the_truth():
    T = mocap_trajectory(20, rng=0)[9]
    plain = simulate_detections(LAB, T, outlier_ratio=0.5, rng=5)
    det = simulate_detections(LAB, T, outlier_ratio=0.5, rng=5, prior_error=(0.3, 0.05))
    assert_split(det)
    # the guess is drawn after the detections: same detections with and without it
    np.testing.assert_array_equal(plain.input.data, det.input.data)
    e_t, e_r = SE3().relative_error(det.truth.pose, det.input.prior)
    assert e_t == pytest.approx(0.3) and e_r == pytest.approx(0.05)
    assert_rows_disjoint(det.input.prior[:3, 3][None], det.truth.pose[:3, 3][None], atol=0.1)
    # the association is recomputed from input alone
    again = associate_nearest(det.input.data, LAB, det.input.prior)
    np.testing.assert_array_equal(again, det.input.association)
    # and it is a front end's guess, not the truth: false detections are wrongly associated
    wrong = det.input.association != det.truth.landmark
    assert wrong[det.truth.is_outlier].all()
    corr = det.input.correspondences(LAB)
    assert corr.shape == (len(det), 6)
    assert_rows_disjoint(corr[:, :3], det.truth.clean[np.isfinite(det.truth.clean[:, 0])],
                         atol=1e-9)


def test_3d_generator_rejects_a_bad_prior_error():
    with pytest.raises(ValueError, match="prior_error"):
        simulate_detections(LAB, np.eye(4), prior_error=(-0.1, 0.0))
    with pytest.raises(ValueError, match="prior_error"):
        simulate_detections(LAB, np.eye(4), prior_error="far")
    with pytest.raises(ValueError, match="prior"):
        associate_nearest(np.zeros((2, 4)), LAB, np.eye(3))


def test_localizers_refuse_the_whole_sample():
    det = simulate_detections(LAB, mocap_trajectory(20, rng=0)[4], outlier_ratio=0.5, rng=2)
    with pytest.raises(ValueError, match="observations"):
        localize3d(det, LAB)


# ---------------------------------------------------------------- point clouds
def test_point_cloud_scene_split_noise_free_points_are_not_input():
    pytest.importorskip("open3d")
    from clap_unified.localization.open3d_baselines import scene_point_clouds

    sc = scene_point_clouds(n_points=2000, rng=3)
    assert_split(sc)
    assert _field_names(sc.input) == {"source", "target"}
    assert _field_names(sc.truth) == {"pose", "source_clean", "target_clean"}
    assert sc.input.source.shape == sc.truth.source_clean.shape
    assert_rows_disjoint(sc.input.source, sc.truth.source_clean, atol=1e-9)
    assert_rows_disjoint(sc.input.target, sc.truth.target_clean, atol=1e-9)
    # the noise is what the scene says (5 mm per axis), so the clean copies are the truth
    noise = (sc.input.target - sc.truth.target_clean).std()
    assert 0.004 < noise < 0.006
    T = sc.truth.pose
    moved = sc.truth.source_clean @ T[:3, :3].T + T[:3, 3]
    assert moved.shape == sc.input.source.shape
