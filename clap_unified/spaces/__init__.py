"""Hypothesis spaces: model families, their minimal solvers and residuals."""

from .base import HypothesisSet, HypothesisSpace
from .lines import LineSpace
from .sampling import enumerate_hypotheses, generate_hypotheses, sample_subsets

__all__ = [
    "HypothesisSet",
    "HypothesisSpace",
    "LineSpace",
    "enumerate_hypotheses",
    "generate_hypotheses",
    "sample_subsets",
]
