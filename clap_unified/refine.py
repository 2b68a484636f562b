"""Data-space inliers of a model and refitting on them, shared by every strategy."""

from __future__ import annotations

import numpy as np

__all__ = ["inliers_of", "refit_on_inliers"]


def inliers_of(space, model, data, threshold: float) -> np.ndarray:
    """Boolean mask of the data whose residual to ``model`` is below ``threshold``."""
    return space.residuals(np.asarray(model)[None], data)[0] < threshold


def refit_on_inliers(space, model, data, threshold: float, *, iterations: int = 2):
    """Refit ``model`` on its inliers, up to ``iterations`` times.

    The first refit is always taken when it is not degenerate (least squares
    on the inliers is more accurate than the minimal-sample model even when it
    loses an inlier or two at the edge of the threshold, as in scikit-image and
    OpenCV); later rounds are kept only while the inlier set does not shrink,
    and stop when it no longer changes.

    The inlier test and the refit come from ``space.refit_steps(data,
    threshold)``: by default :func:`inliers_of` and
    ``space.refit(data[inliers], initial=model)``; a space that declares
    ``local_refit`` shares work between them (e.g. the data-to-map
    association computed for the inliers of a model is the one its refit
    needs).

    Returns
    -------
    model : ndarray
    inliers : ndarray of bool, shape (N,)
    """
    inliers_fn, refit_fn = space.refit_steps(data, threshold)
    inliers = inliers_fn(model)
    for round_ in range(iterations):
        if np.count_nonzero(inliers) < space.min_samples:
            break
        new = refit_fn(inliers, model)
        if new is None:
            break
        new_inliers = inliers_fn(new)
        if round_ > 0 and np.count_nonzero(new_inliers) < np.count_nonzero(inliers):
            break
        if np.count_nonzero(new_inliers) < space.min_samples:
            break
        changed = not np.array_equal(new_inliers, inliers)
        model, inliers = new, new_inliers
        if not changed:
            break
    return model, inliers
