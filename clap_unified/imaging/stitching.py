"""Stitching two images with a homography: warp, canvas, blend.

Convention: ``H`` maps points of the *left* image to the *right* image
(``x_right ~ H x_left``, as estimated from matches ``(x_left, y_left,
x_right, y_right)``). The right image is warped into the left image's frame
by ``H^-1``, on a canvas translated so that both images fit. Blending:

* ``"none"``: overlay, the mean of both images where they overlap (ghosts
  show misalignment);
* ``"overwrite"``: the warped right image on top of the left;
* ``"feather"``: weights from the distance transform of each image's
  footprint (distance to its border), so seams fade out.
"""

from __future__ import annotations

import numpy as np

from .._validation import check_array, check_choice

__all__ = ["BLENDS", "MAX_CANVAS_PIXELS", "StitchError", "panorama_canvas", "stitch"]

#: Blending modes of :func:`stitch`.
BLENDS = ("none", "overwrite", "feather")

#: A canvas larger than this (e.g. from a wild homography) is refused.
MAX_CANVAS_PIXELS = 40_000_000


class StitchError(ValueError):
    """The homography cannot give a sensible panorama (degenerate or huge canvas)."""


def _corners(w, h):
    return np.array([[0.0, 0.0], [w, 0.0], [w, h], [0.0, h]])


def panorama_canvas(H, left_shape, right_shape):
    """Canvas size and the translation ``T`` putting both images on it.

    Returns
    -------
    size : (width, height)
    T : ndarray of shape (3, 3)
        Left image -> canvas; the right image goes to the canvas by ``T H^-1``.

    Raises
    ------
    StitchError
        ``H`` is singular, maps a corner of the right image to infinity
        (behind the camera), or the canvas would exceed
        :data:`MAX_CANVAS_PIXELS`.
    """
    H = check_array(H, "H", shape=(3, 3))
    try:
        Hinv = np.linalg.inv(H)
    except np.linalg.LinAlgError:
        raise StitchError("H: singular homography, cannot warp") from None
    hr, wr = right_shape[:2]
    hl, wl = left_shape[:2]
    c = np.c_[_corners(wr, hr), np.ones(4)] @ Hinv.T
    if np.any(c[:, 2] <= 1e-9 * np.abs(c).max()):
        raise StitchError("H: the right image does not map in front of the left camera")
    warped = c[:, :2] / c[:, 2:]
    pts = np.vstack([_corners(wl, hl), warped])
    lo, hi = np.floor(pts.min(0)), np.ceil(pts.max(0))
    w, h = int(hi[0] - lo[0]), int(hi[1] - lo[1])
    if not (np.all(np.isfinite(pts))) or w * h > MAX_CANVAS_PIXELS or w <= 0 or h <= 0:
        raise StitchError(f"H: the panorama would be {w} x {h} pixels; the homography is "
                          "not a plausible alignment")
    T = np.array([[1.0, 0.0, -lo[0]], [0.0, 1.0, -lo[1]], [0.0, 0.0, 1.0]])
    return (w, h), T


def stitch(left, right, H, *, blend: str = "feather") -> np.ndarray:
    """Panorama of ``left`` and ``right`` with ``right`` warped into ``left``'s frame.

    Parameters
    ----------
    left, right : ndarray of shape (h, w, 3) or (h, w), uint8
    H : ndarray of shape (3, 3)
        Maps left-image points to right-image points.
    blend : {"none", "overwrite", "feather"}

    Returns
    -------
    ndarray, uint8
        The panorama; pixels covered by neither image are black.

    Raises
    ------
    StitchError
        See :func:`panorama_canvas`.

    Examples
    --------
    >>> left = np.full((40, 60, 3), 100, np.uint8)
    >>> right = np.full((40, 60, 3), 200, np.uint8)
    >>> H = np.array([[1.0, 0, -30], [0, 1, 0], [0, 0, 1]])  # right starts at x = 30
    >>> pano = stitch(left, right, H, blend="overwrite")
    >>> pano.shape, int(pano[20, 10, 0]), int(pano[20, 80, 0])
    ((40, 90, 3), 100, 200)
    """
    import cv2

    check_choice(blend, "blend", set(BLENDS))
    (w, h), T = panorama_canvas(H, left.shape, right.shape)
    A = T @ np.linalg.inv(H)
    warped = cv2.warpPerspective(right, A, (w, h), flags=cv2.INTER_LINEAR)
    mask_r = cv2.warpPerspective(np.full(right.shape[:2], 255, np.uint8), A, (w, h),
                                 flags=cv2.INTER_NEAREST) > 0
    base = cv2.warpPerspective(left, T, (w, h), flags=cv2.INTER_NEAREST)
    mask_l = np.zeros((h, w), bool)
    ox, oy = int(T[0, 2]), int(T[1, 2])
    mask_l[oy:oy + left.shape[0], ox:ox + left.shape[1]] = True
    if blend == "overwrite":
        out = base.copy()
        out[mask_r] = warped[mask_r]
        return out
    if blend == "none":
        wl, wr = mask_l.astype(float), mask_r.astype(float)
    else:
        wl, wr = _feather_weight(mask_l), _feather_weight(mask_r)
    total = wl + wr
    total[total == 0] = 1.0
    if base.ndim == 3:
        wl, wr, total = wl[..., None], wr[..., None], total[..., None]
    out = (base * wl + warped * wr) / total
    return np.clip(np.rint(out), 0, 255).astype(np.uint8)


def _feather_weight(mask) -> np.ndarray:
    """Distance of each pixel of ``mask`` to the nearest pixel outside it (feathering weights).

    When the mask covers the whole canvas (one image inside the other) there is no pixel
    outside and OpenCV returns huge distances that overflow the blend; the distance is then
    measured to the canvas border.
    """
    import cv2

    m = np.asarray(mask, dtype=np.uint8)
    if m.all():
        return cv2.distanceTransform(np.pad(m, 1), cv2.DIST_L2, 3)[1:-1, 1:-1]
    return cv2.distanceTransform(m, cv2.DIST_L2, 3)
