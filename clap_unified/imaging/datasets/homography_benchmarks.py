"""homogr and EVD: planar image pairs with point matches and ground truth.

* **homogr** (Lebeda, Matas, Chum, BMVC 2012): 16 pairs with a ground-truth
  homography. The file ``<name>_model.txt`` maps image B to image A; here
  ``H_gt`` is its inverse, mapping A to B like every ``H`` in this package.
* **EVD** (extreme view dataset; Mishkin, Matas, Perdoch, CVIU 2015): 15
  pairs whose tentative matches carry a ground-truth inlier label (2-51 %
  inliers) and the SIFT ratio of each match. No homography file is given:
  ``H_gt`` is the DLT fit to the labelled inliers.

Files come from the manifest ``data/homography/manifest.json`` through
:func:`~clap_unified.imaging.datasets.sources.fetch` (mirror, cache or the
public source, sha256 checked).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .sources import fetch, load_manifest

__all__ = ["HomographyPair", "evd_names", "homogr_names", "load_evd", "load_homogr"]

_DATASET = "homography"


@dataclass
class HomographyPair:
    """One image pair with matches and ground truth.

    Attributes
    ----------
    name : str
    dataset : {"homogr", "EVD"}
    matches : ndarray of shape (N, 4)
        Rows ``(xA, yA, xB, yB)``.
    H_gt : ndarray of shape (3, 3)
        Maps image A to image B, ``H33 = 1``.
    gt_inliers : ndarray of bool, shape (N,)
        homogr: matches within 3 px (symmetric) of ``H_gt``; EVD: the labels.
    quality : ndarray of shape (N,) or None
        EVD: the SIFT ratio of each match (lower is better).
    image_a, image_b : str
        Paths of the two images (fetched on first access of the pair).
    """

    name: str
    dataset: str
    matches: np.ndarray
    H_gt: np.ndarray
    gt_inliers: np.ndarray
    quality: np.ndarray | None
    image_a: str
    image_b: str

    @property
    def inlier_ratio(self) -> float:
        return float(np.mean(self.gt_inliers))


def homogr_names() -> list[str]:
    """Pair names of homogr, from the manifest."""
    return list(load_manifest(_DATASET)["homogr"])


def evd_names() -> list[str]:
    """Pair names of EVD, from the manifest."""
    return list(load_manifest(_DATASET)["evd"])


def _image(prefix: str) -> str:
    files = load_manifest(_DATASET)["files"]
    for ext in (".png", ".jpg"):
        if prefix + ext in files:
            return str(fetch(_DATASET, prefix + ext))
    raise ValueError(f"{_DATASET}: no image {prefix}.png/.jpg in the manifest")


def _loadtxt(path, usecols, name) -> np.ndarray:
    try:
        arr = np.loadtxt(path, usecols=usecols, ndmin=2)
    except ValueError as exc:
        raise ValueError(f"{path}: cannot parse {name} ({exc})") from None
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{path}: non-finite values in {name}")
    return arr


def _check_name(name, names, dataset):
    if name not in names:
        raise ValueError(f"name: {name!r} is not a {dataset} pair; expected one of {names}")


def load_homogr(name: str, *, images: bool = True) -> HomographyPair:
    """One homogr pair.

    Examples
    --------
    >>> pair = load_homogr("city", images=False)     # doctest: +SKIP
    >>> pair.matches.shape, round(pair.inlier_ratio, 2)  # doctest: +SKIP
    ((27, 4), 0.93)
    """
    from ..metrics import symmetric_reprojection_error

    _check_name(name, homogr_names(), "homogr")
    pts = _loadtxt(fetch(_DATASET, f"{name}_pts.txt"), None, "matches")
    if pts.shape[1] < 5:
        raise ValueError(f"{name}_pts.txt: expected rows 'xA yA 1 xB yB 1 label'")
    model = _loadtxt(fetch(_DATASET, f"{name}_model.txt"), None, "model")
    if model.shape != (3, 3):
        raise ValueError(f"{name}_model.txt: expected a 3 x 3 matrix, got {model.shape}")
    H = np.linalg.inv(model)
    H /= H[2, 2]
    matches = np.c_[pts[:, :2], pts[:, 3:5]]
    gt = symmetric_reprojection_error(H, matches) < 3.0
    a = _image(f"{name}A") if images else ""
    b = _image(f"{name}B") if images else ""
    return HomographyPair(name, "homogr", matches, H, gt, None, a, b)


def load_evd(name: str, *, images: bool = True) -> HomographyPair:
    """One EVD pair; ``H_gt`` is the DLT fit to the labelled inliers."""
    from ...spaces.homography import dlt

    _check_name(name, evd_names(), "EVD")
    pts = _loadtxt(fetch(_DATASET, f"extremeview/{name}_pts.txt"), (0, 1, 2, 3, 4, 8), "matches")
    matches, ratio, label = pts[:, :4], pts[:, 4], pts[:, 5] == 1
    if label.sum() < 4:
        raise ValueError(f"extremeview/{name}_pts.txt: fewer than 4 labelled inliers")
    H = dlt(matches[label, :2], matches[label, 2:])
    H = H / H[2, 2]
    a = _image(f"extremeview/{name}A") if images else ""
    b = _image(f"extremeview/{name}B") if images else ""
    return HomographyPair(name, "EVD", matches, H, label, ratio, a, b)
