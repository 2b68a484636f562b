"""Data-space inliers of a model and refitting on them, shared by every strategy."""

from __future__ import annotations

import numpy as np

__all__ = ["inliers_of", "refit_on_inliers"]


def inliers_of(space, model, data, threshold: float) -> np.ndarray:
    """Boolean mask of the data whose residual to ``model`` is below ``threshold``."""
    return space.residuals(np.asarray(model)[None], data)[0] < threshold


def refit_on_inliers(space, model, data, threshold: float, *, iterations: int = 2):
    """Refit ``model`` on its inliers, up to ``iterations`` times.

    Each round refits on the current inliers and keeps the refit only if it
    has at least as many inliers; stops when the inlier set no longer changes.

    Returns
    -------
    model : ndarray
    inliers : ndarray of bool, shape (N,)
    """
    inliers = inliers_of(space, model, data, threshold)
    for _ in range(iterations):
        if np.count_nonzero(inliers) < space.min_samples:
            break
        new = space.refit(data[inliers])
        if new is None:
            break
        new_inliers = inliers_of(space, new, data, threshold)
        if np.count_nonzero(new_inliers) < np.count_nonzero(inliers):
            break
        changed = not np.array_equal(new_inliers, inliers)
        model, inliers = new, new_inliers
        if not changed:
            break
    return model, inliers
