"""Localization applications built on the core: RoboCup fields and their landmarks."""

from .field import LANDMARK_TYPES, Field, load_field

__all__ = ["LANDMARK_TYPES", "Field", "load_field"]
