"""Cluster centres: where a group of hypotheses is, as one model.

All estimators take a manifold and a stack of points on it. The mean-type
estimators come from the manifold (Karcher, log-Euclidean, tangent-space
median); the medoid is always one of the hypotheses.
"""

from __future__ import annotations

import numpy as np

from .._validation import check_choice

__all__ = ["CENTRES", "cluster_centre"]


def cluster_centre(manifold, points, method: str = "medoid", weights=None) -> np.ndarray:
    """Centre of a cluster of hypotheses.

    Parameters
    ----------
    manifold : Manifold
    points : ndarray of shape (N,) + point_shape
    method : {"medoid", "karcher", "log_euclidean", "split", "median"}
        ``medoid``: the member minimising the sum of distances to the others;
        ``karcher``: intrinsic (Frechet) mean; ``log_euclidean``: mean of the
        logarithms at the identity; ``split``: rotation and translation
        averaged apart (spaces that define ``split_mean``); ``median``:
        geometric median in the tangent space (Lie median).
    weights : ndarray of shape (N,), optional

    Examples
    --------
    >>> from clap_unified.geometry import Line2D
    >>> lines = np.array([[0.10, 1.0], [0.12, 1.0], [0.08, 1.0], [0.10, 1.1], [0.10, 0.9],
    ...                   [1.5, 7.0]])
    >>> cluster_centre(Line2D(), lines, "medoid").tolist()
    [0.1, 1.0]
    """
    check_choice(method, "centre", set(CENTRES))
    return CENTRES[method](manifold, points, weights)


def _medoid(manifold, points, weights):
    return np.asarray(points)[manifold.medoid_index(points, weights)]


def _split(manifold, points, weights):
    if not manifold.has_split_mean:
        raise ValueError(f"centre: 'split' needs a space with a split mean; {manifold!r} has none")
    return manifold.split_mean(points, weights)


#: Centre name -> ``f(manifold, points, weights)``; the names :func:`cluster_centre` accepts.
CENTRES = {
    "medoid": _medoid,
    "karcher": lambda manifold, points, weights: manifold.mean(points, weights),
    "log_euclidean": lambda manifold, points, weights: manifold.log_euclidean_mean(points, weights),
    "split": _split,
    "median": lambda manifold, points, weights: manifold.median(points, weights),
}
