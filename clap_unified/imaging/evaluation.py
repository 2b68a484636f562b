"""Running every homography estimator on the same matches and scoring it.

Shared by the image-stitching chapter and ``bench/bench_homography.py``: one
row per (pair, method) with wall time, the paper's Lie distance to the ground
truth, mean corner error, inlier count, ratio of ground-truth inliers kept
and the median symmetric reprojection error on the ground-truth inliers.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from .estimate import estimate_homography
from .metrics import corner_error, lie_error, symmetric_reprojection_error

__all__ = ["EVALUATED", "PairMatches", "evaluate_pair", "summarise", "vpg_pair_matches"]

#: Methods compared by default: label -> (estimator name, uses match quality).
EVALUATED = {
    "CLAP": ("clap", False),
    "CLAP ordered": ("clap", True),
    "RANSAC (library)": ("ransac", False),
    "cv2.RANSAC": ("cv2_ransac", False),
    "cv2.USAC_MAGSAC": ("magsac", False),
    "USAC RANSAC 1000": ("usac_ransac_fixed", False),
}


def evaluate_pair(matches, H_gt, *, size=None, quality=None, gt_inliers=None, methods=None,
                  seed: int = 0, repeat: int = 1, **options) -> list[dict]:
    """Run each method on ``matches`` and score it against ``H_gt``.

    Parameters
    ----------
    matches : ndarray of shape (N, 4)
    H_gt : ndarray of shape (3, 3)
    size : (width, height), optional
        Source image size for the corner error (default: the bounding box of
        the source points).
    quality : ndarray of shape (N,), optional
        Match quality for the ordered variants (skipped when None).
    gt_inliers : ndarray of bool, optional
        Ground-truth inliers for the SRE and recall (default: SRE < 3 px under
        ``H_gt``).
    methods : dict, optional
        ``label -> (estimator, uses_quality)``; default :data:`EVALUATED`.
    seed : int
    repeat : int
        Runs per method; the time is the median.
    options
        Passed to every library estimator (not to OpenCV).

    Returns
    -------
    list of dict
        Keys ``method, seconds, lie, corner, inliers, recall, sre``.
    """
    methods = EVALUATED if methods is None else methods
    m = np.asarray(matches, dtype=float)
    if size is None:
        size = tuple(np.ceil(m[:, :2].max(0)))
    if gt_inliers is None:
        gt_inliers = symmetric_reprojection_error(H_gt, m) < 3.0
    rows = []
    for label, (name, ordered) in methods.items():
        if ordered and quality is None:
            continue
        kw = dict(options) if name in ("clap", "ransac", "hough") else {}
        if ordered:
            kw["quality"] = quality
        if name in ("clap", "ransac", "hough"):
            kw["rng"] = seed
        times, res = [], None
        for _ in range(repeat):
            t0 = time.perf_counter()
            res = estimate_homography(m, name, **kw)
            times.append(time.perf_counter() - t0)
        H = res.model if res.success else None
        if H is not None and gt_inliers.any():
            est_in = symmetric_reprojection_error(H, m) < 3.0
            recall = float(np.mean(est_in[gt_inliers]))
            sre = float(np.median(symmetric_reprojection_error(H, m[gt_inliers])))
        elif H is not None:
            recall, sre = float("nan"), float("nan")
        else:
            recall, sre = 0.0, float("inf")
        rows.append({"method": label, "seconds": float(np.median(times)),
                     "lie": lie_error(H, H_gt), "corner": corner_error(H, H_gt, size),
                     "inliers": res.n_inliers, "recall": recall, "sre": sre,
                     "success": bool(res.success)})
    return rows


def summarise(rows, key: str) -> dict:
    """Median of ``key`` per method over a list of :func:`evaluate_pair` rows."""
    out = {}
    for r in rows:
        out.setdefault(r["method"], []).append(r[key])
    return {k: float(np.median(v)) for k, v in out.items()}


@dataclass
class PairMatches:
    """SIFT matches of one image pair of a VPG-layout set, with its ground truth."""

    scene: str
    pair: tuple
    left: np.ndarray
    right: np.ndarray
    matches: np.ndarray
    quality: np.ndarray
    H_gt: np.ndarray | None


def vpg_pair_matches(vpg_set, *, ratio: float = 0.75) -> list[PairMatches]:
    """SIFT + ratio-test matches of every pair of a VPG-layout set.

    ``H_gt`` is the DLT fit to the set's ground-truth correspondences
    (``mNN-MM.txt``), or None for pairs without them (VPG S13-S36).
    """
    from .features import read_image, sift_matches

    out = []
    for i, j in vpg_set.pairs():
        if i not in vpg_set.images or j not in vpg_set.images:
            raise FileNotFoundError(f"{vpg_set.path}: images {i:02d} and {j:02d} are needed")
        left, right = read_image(vpg_set.images[i]), read_image(vpg_set.images[j])
        m, q = sift_matches(left, right, ratio=ratio)
        H = vpg_set.ground_truth(i, j) if (i, j) in vpg_set.correspondences else None
        out.append(PairMatches(vpg_set.name, (i, j), left, right, m, q, H))
    return out
