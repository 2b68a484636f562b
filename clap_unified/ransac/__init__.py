"""RANSAC: hypotheses scored by consensus in data space."""

from .ransac import ransac, required_trials, run_ransac, score_hypotheses

__all__ = ["ransac", "required_trials", "run_ransac", "score_hypotheses"]
