"""Clustering in input space: merge a short window of detections before localizing.

A robot sees the same landmark in consecutive frames; a false detection
rarely repeats at the same place. Carried into the current robot frame by the
odometry, the detections of the last few frames form one dense cluster per
landmark and scattered singletons for the false ones. CLAP in the input space
(:class:`~clap_unified.spaces.ObservationSpace`) finds those clusters; their
centres, each backed by several frames, are what :func:`merge_detections`
hands to the pose estimator in place of the raw detections.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validation import check_array, check_int, check_positive
from ..datatypes import freeze_arrays
from ..fitting import fit
from ..geometry.se2 import SE2
from ..spaces.observations import ObservationSpace
from .observations import ObservationInput

__all__ = ["MergedDetections", "merge_detections"]


@dataclass(frozen=True)
class MergedDetections:
    """Detections merged over a window of frames, in the current robot frame.

    Attributes
    ----------
    input : ObservationInput
        One detection ``(type_id, x, y)`` per cluster: the cluster centre.
    support : ndarray of int, shape (M,)
        Detections behind each merged one (at most one per frame is expected).
    n_raw : int
        Detections in the window.
    """

    input: ObservationInput
    support: np.ndarray
    n_raw: int

    def __post_init__(self):
        freeze_arrays(self)


def _frame_rows(frame, k: int) -> np.ndarray:
    if isinstance(frame, ObservationInput):
        return np.asarray(frame.data, dtype=float)
    rows = np.asarray(frame, dtype=float)
    if rows.ndim != 2 or rows.shape[1] != 3:
        raise ValueError(f"frames: frame {k} should be an ObservationInput or rows "
                         f"(type_id, x, y), got shape {rows.shape}")
    return rows


def merge_detections(frames, odometry, *, threshold: float = 0.3, bandwidth: float = 0.3,
                     min_support: int = 2) -> MergedDetections:
    """Cluster the detections of a window of frames in the current robot frame.

    Parameters
    ----------
    frames : sequence of ObservationInput or ndarray of shape (N_k, 3)
        The detections of ``K`` consecutive frames, oldest first; the last is
        the current frame.
    odometry : ndarray of shape (K - 1, 3)
        Odometry increments ``(dx, dy, dtheta)`` from frame ``k`` to ``k + 1``
        in the robot frame of ``k`` (a slice of
        ``OdometryInput.odometry``).
    threshold : float
        Metres: a detection within this distance of a cluster centre (same
        type) belongs to it.
    bandwidth : float
        Metres: CLAP's neighbourhood radius among detections.
    min_support : int
        Clusters backed by fewer detections are dropped (a landmark seen once
        in the window is indistinguishable from a false detection).

    Returns
    -------
    MergedDetections
        Empty (no rows) when no cluster has ``min_support`` detections.

    Examples
    --------
    >>> frames = [np.array([[0.0, 2.0, 1.0], [1.0, 3.0, -2.0]]),   # frame 0
    ...           np.array([[0.0, 1.5, 1.0], [2.0, 0.7, 0.7]])]    # frame 1: 0.5 m further
    >>> merged = merge_detections(frames, np.array([[0.5, 0.0, 0.0]]))
    >>> merged.input.data.tolist(), merged.support.tolist(), merged.n_raw
    ([[0.0, 1.5, 1.0]], [2], 4)
    """
    frames = list(frames)
    if not frames:
        raise ValueError("frames: expected at least one frame")
    k = len(frames)
    inc = check_array(odometry, "odometry", shape=(k - 1, 3))
    threshold = check_positive(threshold, "threshold")
    bandwidth = check_positive(bandwidth, "bandwidth")
    min_support = check_int(min_support, "min_support", minimum=1)
    # pose of every frame in the current (last) robot frame
    to_current = [np.eye(3)] * k
    for j in range(k - 2, -1, -1):
        to_current[j] = to_current[j + 1] @ np.linalg.inv(SE2.from_xytheta(*inc[j]))
    rows = []
    for j, frame in enumerate(frames):
        r = _frame_rows(frame, j)
        if len(r):
            xy = r[:, 1:] @ to_current[j][:2, :2].T + to_current[j][:2, 2]
            rows.append(np.c_[r[:, :1], xy])
    data = np.concatenate(rows) if rows else np.empty((0, 3))
    empty = MergedDetections(ObservationInput(np.empty((0, 3))), np.empty(0, int), len(data))
    if len(data) < min_support:
        return empty
    res = fit(ObservationSpace(2), data, "clap", threshold=threshold, bandwidth=bandwidth,
              min_support=min_support, max_clusters=len(data), centre="karcher",
              n_hypotheses=len(data))
    if not res.success:
        return empty
    centres = np.array([c.model for c in res.clusters])
    support = np.array([c.support for c in res.clusters], dtype=int)
    return MergedDetections(ObservationInput(centres), support, len(data))
