"""Localization applications built on the core.

2D (RoboCup Humanoid fields): typed landmark maps (:mod:`clap_unified.maps`), a camera
and detection simulator (:mod:`.observations`), one-frame localization by
CLAP, RANSAC or randomized Hough on the same candidates (``localize2d``), a walking
trajectory (:mod:`.trajectory`), an SE(2) EKF (:mod:`.ekf`), Monte Carlo
localization (:mod:`.mcl`), the tracking comparison (:mod:`.tracking`), and
detections merged over a window of frames by clustering in input space (:mod:`.merging`).

3D (SE(3)): typed landmark maps, the whole RoboCup field and the MoCap lab
(:mod:`.map3d`), a MoCap-like trajectory and detection simulator (:mod:`.scene3d`),
one-frame 6-DoF localization by CLAP, RANSAC or Open3D (``localize3d``) and the Open3D
baselines, point clouds included (:mod:`.open3d_baselines`).

Both one-frame localizers are thin: they turn their input into the data of a
pose space and call the one pipeline, :func:`.core.localize` (hence
:func:`~clap_unified.fit`); the strategies are those registered for the space.

Every simulator returns a frozen pair ``(input, truth)``: estimators take the
``input`` (detections, odometry, scans), scoring takes the ``truth`` (poses,
landmark identities, false-detection labels, noise-free copies); see
:mod:`clap_unified.datatypes`.

The field maps live one floor down, in :mod:`clap_unified.maps` (the landmark
hypothesis space reads them too); they are re-exported here.
"""

from ..maps import FIELD_DIMENSIONS, LANDMARK_TYPES, Field, field_landmarks, load_field
from .core import localize
from .ekf import PoseEKF
from .localize2d import as_pose, localize2d, observation_data
from .localize3d import align_correspondences, localize3d, pose_errors
from .map3d import LandmarkMap3D, field_map, lab_map
from .mcl import ParticleFilter
from .merging import MergedDetections, merge_detections
from .observations import (
    FALSE_POSITIVE_KINDS,
    Camera,
    ObservationInput,
    Observations,
    ObservationTruth,
    frames_at_rates,
    random_frames,
    simulate_observations,
    visible_landmarks,
)
from .scene3d import (
    DetectionInput3D,
    Detections3D,
    DetectionTruth3D,
    View3D,
    associate_nearest,
    mocap_trajectory,
    simulate_detections,
)
from .tracking import (
    TrackingRun,
    simulate_frames,
    track_clap_ekf,
    track_mcl,
    tracking_errors,
    tracking_summary,
)
from .trajectory import OdometryInput, Trajectory, TrajectoryTruth, walk_trajectory

__all__ = [
    "Camera",
    "DetectionInput3D",
    "DetectionTruth3D",
    "Detections3D",
    "FALSE_POSITIVE_KINDS",
    "FIELD_DIMENSIONS",
    "Field",
    "LANDMARK_TYPES",
    "LandmarkMap3D",
    "MergedDetections",
    "ObservationInput",
    "ObservationTruth",
    "Observations",
    "OdometryInput",
    "ParticleFilter",
    "PoseEKF",
    "TrackingRun",
    "Trajectory",
    "TrajectoryTruth",
    "View3D",
    "align_correspondences",
    "as_pose",
    "associate_nearest",
    "field_landmarks",
    "field_map",
    "lab_map",
    "load_field",
    "localize",
    "localize2d",
    "localize3d",
    "merge_detections",
    "mocap_trajectory",
    "observation_data",
    "pose_errors",
    "frames_at_rates",
    "random_frames",
    "simulate_detections",
    "simulate_frames",
    "simulate_observations",
    "track_clap_ekf",
    "track_mcl",
    "tracking_errors",
    "tracking_summary",
    "visible_landmarks",
    "walk_trajectory",
]
