"""Localization applications built on the core.

2D (RoboCup Humanoid fields): typed landmark maps (:mod:`.field`), a camera
and detection simulator (:mod:`.observations`), one-frame localization by
CLAP, RANSAC or Hough on the same candidates (:mod:`.localize2d`), a walking
trajectory (:mod:`.trajectory`), an SE(2) EKF (:mod:`.ekf`), Monte Carlo
localization (:mod:`.mcl`) and the tracking comparison (:mod:`.tracking`).

3D (SE(3)): typed landmark maps and the MoCap lab (:mod:`.map3d`), a MoCap-like
trajectory and detection simulator (:mod:`.scene3d`), one-frame 6-DoF localization by
CLAP, RANSAC or Open3D (:mod:`.localize3d`) and the Open3D baselines, point clouds
included (:mod:`.open3d_baselines`).

Every simulator returns a frozen pair ``(input, truth)``: estimators take the
``input`` (detections, odometry, scans), scoring takes the ``truth`` (poses,
landmark identities, false-detection labels, noise-free copies); see
:mod:`clap_unified.datatypes`.

The map modules are imported eagerly; the estimators, which build on
:mod:`clap_unified.spaces` (whose landmark space needs the map), on first use.
"""

import importlib

from .field import FIELD_DIMENSIONS, LANDMARK_TYPES, Field, field_landmarks, load_field
from .observations import (
    FALSE_POSITIVE_KINDS,
    Camera,
    ObservationInput,
    Observations,
    ObservationTruth,
    random_frames,
    simulate_observations,
    visible_landmarks,
)

_LAZY = {
    "LOCALIZE_METHODS": "localize2d", "as_pose": "localize2d", "localize2d": "localize2d",
    "observation_data": "localize2d",
    "Trajectory": "trajectory", "OdometryInput": "trajectory", "TrajectoryTruth": "trajectory",
    "walk_trajectory": "trajectory",
    "PoseEKF": "ekf", "ParticleFilter": "mcl",
    "TrackingRun": "tracking", "simulate_frames": "tracking", "track_clap_ekf": "tracking",
    "track_mcl": "tracking", "tracking_errors": "tracking", "tracking_summary": "tracking",
    "LandmarkMap3D": "map3d", "lab_map": "map3d",
    "View3D": "scene3d", "Detections3D": "scene3d", "DetectionInput3D": "scene3d",
    "DetectionTruth3D": "scene3d", "mocap_trajectory": "scene3d",
    "simulate_detections": "scene3d", "associate_nearest": "scene3d",
    "LOCALIZE3D_METHODS": "localize3d", "localize3d": "localize3d",
    "align_correspondences": "localize3d", "pose_errors": "localize3d",
}


def __getattr__(name):
    if name in _LAZY:
        value = getattr(importlib.import_module(f".{_LAZY[name]}", __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_LAZY))


__all__ = [
    "FALSE_POSITIVE_KINDS",
    "FIELD_DIMENSIONS",
    "LANDMARK_TYPES",
    "Camera",
    "Field",
    "ObservationInput",
    "Observations",
    "ObservationTruth",
    "field_landmarks",
    "load_field",
    "random_frames",
    "simulate_observations",
    "visible_landmarks",
    *_LAZY,
]
