"""The nearest landmark of the same type: the data association of typed landmark maps.

An observation of a landmark type, moved to the map's frame by a pose, is paired
with the closest map landmark of that type. The 2D field
(:class:`~clap_unified.spaces.landmarks2d.Landmark2DSpace`) and the 3D landmark map
(:class:`~clap_unified.spaces.Landmark3DSpace`) both score and refit their poses
with this one query.
"""

from __future__ import annotations

import numpy as np

__all__ = ["nearest_of_type"]

#: Up to this many (pose, observation, landmark) triples the query runs on the whole map at
#: once; beyond, type by type (the same numbers either way).
WHOLE_MAP_LIMIT = 16_384


def nearest_of_type(points, types, positions, position_types):
    """Nearest map landmark of each point's type, for a batch of placements of the points.

    Parameters
    ----------
    points : ndarray of shape (H, N, d)
        Observations in the map's frame, as ``H`` poses place them.
    types : ndarray of int, shape (N,)
        Type id of each observation.
    positions : ndarray of shape (M, d)
        Map landmarks.
    position_types : ndarray of int, shape (M,)
        Type id of each landmark.

    Returns
    -------
    distance : ndarray of shape (H, N)
        Euclidean distance to the nearest landmark of the observation's type;
        ``inf`` where the map has no landmark of that type.
    index : ndarray of int, shape (H, N)
        That landmark's index into ``positions`` (the lowest index among ties);
        ``-1`` where there is none.

    Examples
    --------
    >>> marks = np.array([[0.0, 0.0], [4.0, 0.0], [0.0, 3.0]])
    >>> pts = np.array([[[3.5, 0.0], [0.0, 0.5], [9.0, 9.0]]])
    >>> distance, index = nearest_of_type(pts, np.array([0, 0, 2]), marks, np.array([0, 0, 1]))
    >>> distance.tolist(), index.tolist()
    ([[0.5, 0.5, inf]], [[1, 0, -1]])
    """
    points = np.asarray(points, dtype=float)
    types = np.asarray(types)
    positions = np.asarray(positions, dtype=float)
    position_types = np.asarray(position_types)
    if len(positions) == 0:  # an empty map: no landmark of any type
        return (np.full(points.shape[:2], np.inf),
                np.full(points.shape[:2], -1, dtype=np.intp))
    same = types[:, None] == position_types[None, :]  # (N, M)
    if points.shape[0] * same.size <= WHOLE_MAP_LIMIT:
        return _whole_map(points, same, positions)
    distance = np.full(points.shape[:2], np.inf)
    index = np.full(points.shape[:2], -1, dtype=np.intp)
    for kind in np.unique(types):
        members = np.flatnonzero(position_types == kind)
        if len(members) == 0:
            continue
        cols = types == kind
        diff = points[:, cols, None, :] - positions[members][None, None]
        d2 = np.einsum("hnmi,hnmi->hnm", diff, diff)
        near = d2.argmin(axis=-1)
        distance[:, cols] = np.sqrt(np.take_along_axis(d2, near[..., None], axis=-1)[..., 0])
        index[:, cols] = members[near]
    return distance, index


def _whole_map(points, same, positions):
    """:func:`nearest_of_type` against the whole map at once, other types masked.

    The same squared distances (the same ``einsum``, element by element), the
    same minimum and the same lowest index among ties as the query type by type;
    cheaper when there are few poses (one refit), where the loop's overhead per
    type dominates.
    """
    diff = points[:, :, None, :] - positions
    d2 = np.einsum("hnmk,hnmk->hnm", diff, diff)
    d2[:, ~same] = np.inf
    index = d2.argmin(axis=-1)
    distance = np.sqrt(np.take_along_axis(d2, index[..., None], axis=-1)[..., 0])
    index[:, ~same.any(axis=1)] = -1
    return distance, index
