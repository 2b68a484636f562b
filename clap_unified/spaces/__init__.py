"""Hypothesis spaces: model families, their minimal solvers and residuals."""

from .base import HypothesisSet, HypothesisSpace
from .homography import HomographySpace, dlt
from .lines import LineSpace
from .sampling import enumerate_hypotheses, generate_hypotheses, sample_subsets

__all__ = [
    "HypothesisSet",
    "HomographySpace",
    "HypothesisSpace",
    "LineSpace",
    "dlt",
    "enumerate_hypotheses",
    "generate_hypotheses",
    "sample_subsets",
]
