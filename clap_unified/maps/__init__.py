"""Maps the spaces localize against: the RoboCup field as a typed landmark map.

A floor between :mod:`clap_unified.geometry` and :mod:`clap_unified.spaces`:
the landmark hypothesis spaces read these maps, and the localization
applications load them, so neither has to import the other upwards.
"""

from .field import FIELD_DIMENSIONS, LANDMARK_TYPES, Field, field_landmarks, load_field

__all__ = ["FIELD_DIMENSIONS", "LANDMARK_TYPES", "Field", "field_landmarks", "load_field"]
