"""Reading images and matching them: SIFT keypoints and Lowe's ratio test (OpenCV)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .._validation import check_fraction, check_int

__all__ = ["match_images", "read_image", "sift_matches"]


def read_image(path) -> np.ndarray:
    """An image file as a BGR ``uint8`` array ``(H, W, 3)``.

    Raises
    ------
    ValueError
        Naming the file when it is missing or not a readable image.
    """
    import cv2

    p = Path(path)
    if not p.is_file():
        raise ValueError(f"{p}: no such image file")
    img = cv2.imread(str(p), cv2.IMREAD_COLOR)
    if img is None or img.size == 0:
        raise ValueError(f"{p}: not a readable image")
    return img


def sift_matches(img1, img2, *, ratio: float = 0.75, max_features: int = 4000,
                 mutual: bool = False):
    """SIFT matches from ``img1`` to ``img2`` that pass the ratio test.

    Parameters
    ----------
    img1, img2 : ndarray
        BGR or grey ``uint8`` images.
    ratio : float
        Lowe's ratio: keep a match when its distance is below ``ratio`` times
        the second-best distance.
    max_features : int
        SIFT keypoints per image at most.
    mutual : bool
        Keep only matches that are also best from ``img2`` to ``img1``.

    Returns
    -------
    matches : ndarray of shape (N, 4)
        Rows ``(x1, y1, x2, y2)``, sorted by ``quality``.
    quality : ndarray of shape (N,)
        The ratio of each match (lower is better).

    Examples
    --------
    >>> import cv2
    >>> from skimage import data
    >>> img = data.astronaut()[..., ::-1].copy()
    >>> shifted = np.roll(img, (7, 12), axis=(0, 1))
    >>> m, q = sift_matches(img, shifted)
    >>> len(m) > 100, bool(np.median(m[:, 2] - m[:, 0]) == 12.0)
    (True, True)
    """
    import cv2

    ratio = check_fraction(ratio, "ratio", inclusive=(False, True))
    max_features = check_int(max_features, "max_features", minimum=8)
    sift = cv2.SIFT_create(nfeatures=max_features)
    grey = [cv2.cvtColor(i, cv2.COLOR_BGR2GRAY) if i.ndim == 3 else i for i in (img1, img2)]
    k1, d1 = sift.detectAndCompute(grey[0], None)
    k2, d2 = sift.detectAndCompute(grey[1], None)
    if d1 is None or d2 is None or len(k1) < 2 or len(k2) < 2:
        return np.empty((0, 4)), np.empty(0)
    matcher = cv2.BFMatcher(cv2.NORM_L2)
    knn = matcher.knnMatch(d1, d2, k=2)
    rows, quality = [], []
    best_back = None
    if mutual:
        best_back = {m.queryIdx: m.trainIdx for m in matcher.match(d2, d1)}
    for pair in knn:
        if len(pair) < 2:
            continue
        a, b = pair
        q = a.distance / max(b.distance, 1e-12)
        if q >= ratio:
            continue
        if best_back is not None and best_back.get(a.trainIdx) != a.queryIdx:
            continue
        rows.append((*k1[a.queryIdx].pt, *k2[a.trainIdx].pt))
        quality.append(q)
    if not rows:
        return np.empty((0, 4)), np.empty(0)
    m, q = np.array(rows, dtype=float), np.array(quality)
    order = np.argsort(q, kind="stable")
    return m[order], q[order]


def match_images(path1, path2, **options):
    """:func:`read_image` both files, then :func:`sift_matches`.

    Returns ``(img1, img2, matches, quality)``.
    """
    img1, img2 = read_image(path1), read_image(path2)
    m, q = sift_matches(img1, img2, **options)
    return img1, img2, m, q
