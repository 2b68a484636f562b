"""How far an estimated homography is from the truth, or from the matches.

* :func:`lie_error`: the paper's ``||log(H_gt^-1 H)||_F`` (``H33 = 1``),
  ``inf`` for a missing or degenerate estimate instead of an exception;
* :func:`corner_error`: mean distance of the image corners mapped by ``H``
  and by ``H_gt`` (pixels), the error a viewer of the panorama sees;
* :func:`symmetric_reprojection_error`: root mean square of the forward and
  backward transfer errors of correspondences (pixels), the paper's SRE for
  scenes without a ground-truth homography.
"""

from __future__ import annotations

import numpy as np

from .._validation import check_array, check_points
from ..geometry.homography import lie_distance
from ..geometry.homography_arithmetic import symmetric_transfer_error, transfer

__all__ = ["corner_error", "lie_error", "symmetric_reprojection_error", "transfer"]


def lie_error(H, H_gt) -> float:
    """``||log(H_gt^-1 H)||_F``, or ``inf`` when ``H`` is None or degenerate.

    Examples
    --------
    >>> H_gt = np.array([[1.0, 0.0, 5.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    >>> print(f"{lie_error(H_gt, H_gt):.3f} {lie_error(None, H_gt)}")
    0.000 inf
    """
    if H is None:
        return float("inf")
    try:
        return float(lie_distance(H, H_gt))
    except ValueError:
        return float("inf")


def corner_error(H, H_gt, size) -> float:
    """Mean corner displacement (pixels) between ``H`` and ``H_gt`` on an image of ``size``.

    Parameters
    ----------
    H, H_gt : ndarray of shape (3, 3)
    size : (width, height)
        Size of the source image.

    Examples
    --------
    >>> H = np.array([[1.0, 0.0, 3.0], [0.0, 1.0, 4.0], [0.0, 0.0, 1.0]])
    >>> print(f"{corner_error(H, np.eye(3), (640, 480)):.1f}")
    5.0
    """
    if H is None:
        return float("inf")
    w, h = size
    corners = np.array([[0.0, 0.0], [w, 0.0], [w, h], [0.0, h]])
    H = check_array(H, "H", shape=(3, 3))
    H_gt = check_array(H_gt, "H_gt", shape=(3, 3))
    d = np.linalg.norm(transfer(H, corners) - transfer(H_gt, corners), axis=1)
    return float(np.mean(d)) if np.all(np.isfinite(d)) else float("inf")


def symmetric_reprojection_error(H, matches) -> np.ndarray:
    """Per-correspondence SRE ``sqrt((|x2 - H x1|^2 + |x1 - H^-1 x2|^2) / 2)`` (pixels).

    Examples
    --------
    >>> H = np.array([[1.0, 0.0, 1.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    >>> symmetric_reprojection_error(H, np.array([[0.0, 0.0, 1.0, 0.0], [0, 0, 3, 0]])).tolist()
    [0.0, 2.0]
    """
    m = check_points(matches, "matches", dim=4, min_count=0)
    if H is None:
        return np.full(len(m), np.inf)
    return symmetric_transfer_error(check_array(H, "H", shape=(3, 3)), m)

