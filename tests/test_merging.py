"""Clustering in input space: merging a window of detections before localizing."""

import numpy as np
import pytest

from clap_unified.localization import LANDMARK_TYPES, load_field
from clap_unified.localization.merging import merge_detections
from clap_unified.localization.observations import ObservationInput
from clap_unified.localization.tracking import simulate_frames
from clap_unified.localization.trajectory import walk_trajectory


def test_a_landmark_seen_in_every_frame_is_one_merged_detection():
    # the robot walks 0.2 m forward per frame past a landmark at (3, 1) in the first frame
    frames = [np.array([[0.0, 3.0 - 0.2 * k, 1.0]]) for k in range(4)]
    frames[2] = np.r_[frames[2], [[1.0, 5.0, -4.0]]]  # a false detection, once
    merged = merge_detections(frames, np.tile([0.2, 0.0, 0.0], (3, 1)), min_support=2)
    assert merged.n_raw == 5
    assert merged.input.data.tolist() == [[0.0, 2.4, 1.0]] and merged.support.tolist() == [4]


def test_turning_is_undone_by_the_odometry():
    odo = np.array([[0.0, 0.0, np.pi / 2]])  # turn left on the spot
    # a landmark straight ahead becomes one on the right after the turn
    merged = merge_detections([np.array([[2.0, 1.0, 0.0]]), np.array([[2.0, 0.0, -1.0]])], odo)
    assert np.allclose(merged.input.data, [[2.0, 0.0, -1.0]]) and merged.support.tolist() == [2]


def test_merged_detections_are_in_the_current_frame_and_reject_false_ones():
    field = load_field("adult")
    walk = walk_trajectory(field, 12, rng=3)
    frames = simulate_frames(field, walk, false_positive_rate=0.5, rng=4)
    k, t = 5, 11
    merged = merge_detections([f.input for f in frames[t - k + 1:t + 1]],
                              walk.input.odometry[t - k + 1:t])
    pose = walk.truth.poses[t]
    world = merged.input.data[:, 1:] @ pose[:2, :2].T + pose[:2, 2]
    types = merged.input.data[:, 0].astype(int)
    # every merged detection lies near a real landmark of its type (the false ones are gone)
    for (x, y), ty in zip(world, types, strict=True):
        d = np.hypot(*(field.of_type(LANDMARK_TYPES[ty]) - [x, y]).T)
        assert d.min() < 0.3
    assert len(merged.input.data) >= 3


def test_bad_windows_name_the_argument():
    with pytest.raises(ValueError, match="frames"):
        merge_detections([], np.empty((0, 3)))
    with pytest.raises(ValueError, match="odometry"):
        merge_detections([np.zeros((1, 3)), np.zeros((1, 3))], np.zeros((2, 3)))
    with pytest.raises(ValueError, match="frames"):
        merge_detections([np.zeros((1, 2))], np.empty((0, 3)))
    few = merge_detections([ObservationInput(np.zeros((1, 3)))], np.empty((0, 3)))
    assert len(few.input.data) == 0 and few.n_raw == 1
