"""OpenCV's robust homography estimators on the same matches, as ConsensusResults.

``cv2.findHomography`` with ``cv2.RANSAC`` (the classical baseline; OpenCV
stops adaptively once ``confidence`` is reached, at most ``max_iters``
iterations), ``cv2.USAC_MAGSAC`` (MAGSAC++ in OpenCV's USAC framework) and
``"usac_ransac_fixed"``: plain RANSAC in the USAC framework (uniform
sampling, inlier-count score, no local optimisation, OpenCV's least-squares
final polisher requested) with confidence 1, so it does not stop early on
confidence: the closest OpenCV setting to the paper's fixed budget. On the
test pairs its estimate is visibly less refined than ``cv2.RANSAC``'s.
Convention as everywhere here: rows ``(x1, y1, x2, y2)``, ``x2 ~ H x1``.
"""

from __future__ import annotations

import time

import numpy as np

from .._validation import check_choice, check_fraction, check_int, check_points, check_positive
from ..result import ConsensusResult
from ..spaces.homography import HomographySpace

__all__ = ["OPENCV_METHODS", "opencv_homography"]

#: Method names accepted by :func:`opencv_homography`.
OPENCV_METHODS = ("cv2_ransac", "magsac", "usac_ransac_fixed")


def opencv_homography(matches, method: str = "cv2_ransac", *, threshold: float = 3.0,
                      max_iters: int = 1000, confidence: float = 0.995) -> ConsensusResult:
    """``cv2.findHomography`` on ``matches``, returned like the library's strategies.

    Parameters
    ----------
    matches : ndarray of shape (N, 4)
        Rows ``(x1, y1, x2, y2)``; ``H`` maps point 1 to point 2.
    method : {"cv2_ransac", "magsac", "usac_ransac_fixed"}
        ``cv2.RANSAC``, ``cv2.USAC_MAGSAC``, or USAC's plain RANSAC with a
        fixed budget of ``max_iters`` iterations (``confidence`` ignored).
    threshold : float
        Reprojection threshold in pixels (OpenCV's ``ransacReprojThreshold``).
    max_iters : int
        Iteration cap (the paper's budget: 1000).
    confidence : float
        OpenCV's stopping confidence, strictly between 0 and 1.

    Returns
    -------
    ConsensusResult
        ``method`` is the name given; ``diagnostics["seconds"]`` the wall time
        of the OpenCV call. A ``None`` or non-finite answer is a failure.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> src = rng.uniform(0, 640, (100, 2))
    >>> res = opencv_homography(np.c_[src, src + [5.0, -3.0]], "magsac")
    >>> res.success, res.n_inliers, np.round(res.model[:2, 2], 3).tolist()
    (True, 100, [5.0, -3.0])
    """
    import cv2

    data = check_points(matches, "matches", dim=4, min_count=4)
    check_choice(method, "method", set(OPENCV_METHODS))
    threshold = check_positive(threshold, "threshold")
    max_iters = check_int(max_iters, "max_iters", minimum=1)
    confidence = check_fraction(confidence, "confidence", inclusive=(False, False))
    src = np.ascontiguousarray(data[:, :2], dtype=np.float64)
    dst = np.ascontiguousarray(data[:, 2:], dtype=np.float64)
    if method == "usac_ransac_fixed":
        params = cv2.UsacParams()
        params.confidence = 1.0  # never stops early: exactly maxIterations
        params.maxIterations = max_iters
        params.threshold = threshold
        params.sampler = cv2.SAMPLING_UNIFORM
        params.score = cv2.SCORE_METHOD_RANSAC
        params.loMethod = cv2.LOCAL_OPTIM_NULL
        params.isParallel = False
        params.final_polisher = cv2.LSQ_POLISHER
        t0 = time.perf_counter()
        H, mask = cv2.findHomography(src, dst, params)
    else:
        flag = cv2.RANSAC if method == "cv2_ransac" else cv2.USAC_MAGSAC
        t0 = time.perf_counter()
        H, mask = cv2.findHomography(src, dst, flag, threshold, maxIters=max_iters,
                                     confidence=confidence)
    seconds = time.perf_counter() - t0
    space = HomographySpace()
    n = len(data)
    if H is None or not np.all(np.isfinite(H)) or abs(H[2, 2]) < 1e-12:
        return ConsensusResult.failure(method, "OpenCV found no homography", n, 0, space,
                                       seconds=seconds)
    inliers = mask.ravel().astype(bool) if mask is not None else np.zeros(n, bool)
    return ConsensusResult(method, True, "ok", H / H[2, 2], inliers, np.zeros(0, bool),
                           float(inliers.sum()), [], {"seconds": seconds}, space)
