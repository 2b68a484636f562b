"""RANSAC: hypotheses scored by consensus in data space."""

from .ransac import ransac, required_trials, run_ransac, score_hypotheses
from .sequential import run_sequential

__all__ = ["run_sequential", "ransac", "required_trials", "run_ransac", "score_hypotheses"]
