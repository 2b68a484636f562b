"""Geometry: the manifolds and Lie groups hypotheses live in."""

from .base import Manifold, MatrixLieGroup
from .lines import Line2D, canonical_lines, wrap_angle

__all__ = ["Line2D", "Manifold", "MatrixLieGroup", "canonical_lines", "wrap_angle"]
