"""Localization applications built on the core.

2D (RoboCup Humanoid fields): typed landmark maps (:mod:`.field`), a camera
and detection simulator (:mod:`.observations`), one-frame localization by
CLAP, RANSAC or Hough on the same candidates (:mod:`.localize2d`).
"""

from .field import LANDMARK_TYPES, Field, load_field
from .localize2d import LOCALIZE_METHODS, as_pose, localize2d, observation_data
from .observations import (
                           FALSE_POSITIVE_KINDS,
                           Camera,
                           Observations,
                           simulate_observations,
                           visible_landmarks,
)

__all__ = [
    "FALSE_POSITIVE_KINDS",
    "LANDMARK_TYPES",
    "LOCALIZE_METHODS",
    "Camera",
    "Field",
    "Observations",
    "as_pose",
    "load_field",
    "localize2d",
    "observation_data",
    "simulate_observations",
    "visible_landmarks",
]
