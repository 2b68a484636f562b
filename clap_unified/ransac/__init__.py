"""RANSAC: hypotheses scored by consensus in data space."""

from .multi import run_multi_ransac
from .ransac import ransac, required_trials, run_ransac, score_hypotheses
from .sequential import run_sequential

__all__ = ["ransac", "required_trials", "run_multi_ransac", "run_ransac", "run_sequential",
           "score_hypotheses"]
