"""homogr and EVD: planar image pairs, the estimator's input kept apart from the ground truth.

* **homogr** (Lebeda, Matas, Chum, BMVC 2012): 16 pairs with a ground-truth
  homography. Each row of ``<name>_pts.txt`` is ``xA yA 1 xB yB 1 label``:
  label 0 rows are the **tentative matches** (the estimator's input), label 1
  rows (8 per pair) are the manually annotated **validation points**, exact
  under the ground truth and therefore evaluation data only. The file
  ``<name>_model.txt`` maps image B to image A; ``truth.H`` is its inverse,
  mapping A to B like every ``H`` in this package.
* **EVD** (extreme view dataset; Mishkin, Matas, Perdoch, CVIU 2015): 15
  pairs. Every row ``xA yA xB yB ratio ratio detector descriptor label`` is a
  tentative match: all of them are input, with the SIFT ratio as a match
  quality; the label (1: ground-truth inlier; ``pair.inlier_ratio`` is their
  share, which chapter 5 shows per pair) is for
  scoring only. No homography file is given: ``truth.H`` is the DLT fit to
  the labelled inliers. EVD has no separate validation points
  (``truth.validation`` is empty).

Each loader returns a :class:`HomographyPair`, a frozen object with two
frozen parts whose arrays are read-only copies
(:mod:`clap_unified.datatypes`):

* ``pair.input`` (:class:`HomographyInput`): ``matches``, ``quality``,
  ``image_a``, ``image_b``: what an estimator may see;
* ``pair.truth`` (:class:`HomographyTruth`): ``H``, ``inliers`` (over
  ``input.matches``), ``validation``: what scores it.

Files come from the manifest ``manifests/homography.json`` (package data) through
:func:`~clap_unified.imaging.datasets.sources.fetch` (mirror, cache or the
public source, sha256 checked).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ...datatypes import freeze_arrays
from .sources import fetch, load_manifest

__all__ = ["HomographyInput", "HomographyPair", "HomographyTruth", "evd_names",
           "homogr_names", "load_evd", "load_homogr"]

_DATASET = "homography"

#: Symmetric reprojection error (pixels) under ``truth.H`` below which a homogr
#: tentative match counts as a ground-truth inlier.
INLIER_THRESHOLD = 3.0


@dataclass(frozen=True)
class HomographyInput:
    """What a homography estimator may see of one image pair.

    Attributes
    ----------
    matches : ndarray of shape (N, 4)
        Tentative matches, rows ``(xA, yA, xB, yB)`` (read-only).
    quality : ndarray of shape (N,) or None
        Match quality, lower is better (EVD: the SIFT ratio); None when the
        data set gives none.
    image_a, image_b : str
        Paths of the two images ("" when loaded with ``images=False``).
    """

    matches: np.ndarray
    quality: np.ndarray | None = None
    image_a: str = ""
    image_b: str = ""

    def __post_init__(self):
        freeze_arrays(self)


@dataclass(frozen=True)
class HomographyTruth:
    """Evaluation data of one image pair: never input to an estimator.

    Attributes
    ----------
    H : ndarray of shape (3, 3)
        Ground-truth homography from image A to image B, ``H33 = 1``.
    inliers : ndarray of bool, shape (N,)
        Ground-truth inliers among ``input.matches`` (homogr: symmetric
        reprojection error under ``H`` below 3 px; EVD: the labels).
    validation : ndarray of shape (M, 4)
        Rows ``(xA, yA, xB, yB)`` that are exact under ``H`` and absent from
        the input (homogr: the 8 annotated validation points; EVD: none).
    """

    H: np.ndarray
    inliers: np.ndarray
    validation: np.ndarray

    def __post_init__(self):
        freeze_arrays(self)


@dataclass(frozen=True)
class HomographyPair:
    """One image pair: the estimator's ``input`` and the evaluation ``truth``.

    Attributes
    ----------
    name : str
    dataset : str
        ``"homogr"``, ``"EVD"`` or the name of a VPG-layout set.
    input : HomographyInput
    truth : HomographyTruth
    """

    name: str
    dataset: str
    input: HomographyInput
    truth: HomographyTruth

    def __post_init__(self):
        if len(self.truth.inliers) != len(self.input.matches):
            raise ValueError(f"truth: {len(self.truth.inliers)} inlier labels for "
                             f"{len(self.input.matches)} matches")

    @property
    def inlier_ratio(self) -> float:
        """Fraction of ground-truth inliers among the input matches."""
        return float(np.mean(self.truth.inliers))


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


def read_homogr_rows(path) -> tuple[np.ndarray, np.ndarray]:
    """Split a homogr ``<name>_pts.txt`` into tentative matches and validation points.

    Parameters
    ----------
    path : path
        A file of rows ``xA yA 1 xB yB 1 label``.

    Returns
    -------
    matches : ndarray of shape (N, 4)
        The label 0 rows, ``(xA, yA, xB, yB)``, in file order.
    validation : ndarray of shape (M, 4)
        The label 1 rows.

    Raises
    ------
    ValueError
        Rows of fewer than 7 columns, labels other than 0 and 1, non-finite
        values.
    """
    pts = _loadtxt(path, None, "matches")
    if pts.shape[1] < 7:
        raise ValueError(f"{path}: expected rows 'xA yA 1 xB yB 1 label'")
    label = pts[:, 6]
    if not np.all((label == 0) | (label == 1)):
        raise ValueError(f"{path}: labels must be 0 (tentative match) or 1 (validation)")
    rows = np.c_[pts[:, :2], pts[:, 3:5]]
    return rows[label == 0], rows[label == 1]


def load_homogr(name: str, *, images: bool = True) -> HomographyPair:
    """One homogr pair: the label 0 rows as input, the label 1 rows as validation.

    Parameters
    ----------
    name : str
        One of :func:`homogr_names`.
    images : bool
        Fetch the two images and fill ``input.image_a`` / ``image_b``.

    Returns
    -------
    HomographyPair
        ``input.matches``: the tentative (label 0) matches; ``input.quality``:
        None; ``truth.H``: the inverse of ``<name>_model.txt``;
        ``truth.inliers``: tentative matches within 3 px (symmetric) of
        ``truth.H``; ``truth.validation``: the 8 validation points.

    Raises
    ------
    ValueError
        Unknown ``name`` or malformed files.

    Examples
    --------
    >>> pair = load_homogr("city", images=False)     # doctest: +SKIP
    >>> pair.input.matches.shape, pair.truth.validation.shape  # doctest: +SKIP
    ((19, 4), (8, 4))
    """
    from ..metrics import symmetric_reprojection_error

    _check_name(name, homogr_names(), "homogr")
    path = fetch(_DATASET, f"{name}_pts.txt")
    matches, validation = read_homogr_rows(path)
    if len(matches) < 4:
        raise ValueError(f"{path}: fewer than 4 tentative (label 0) matches")
    model = _loadtxt(fetch(_DATASET, f"{name}_model.txt"), None, "model")
    if model.shape != (3, 3):
        raise ValueError(f"{name}_model.txt: expected a 3 x 3 matrix, got {model.shape}")
    H = np.linalg.inv(model)
    H /= H[2, 2]
    inliers = symmetric_reprojection_error(H, matches) < INLIER_THRESHOLD
    a = _image(f"{name}A") if images else ""
    b = _image(f"{name}B") if images else ""
    return HomographyPair(name, "homogr", HomographyInput(matches, None, a, b),
                          HomographyTruth(H, inliers, validation))


def load_evd(name: str, *, images: bool = True) -> HomographyPair:
    """One EVD pair: every row as input (with its SIFT ratio), the labels as truth.

    Parameters
    ----------
    name : str
        One of :func:`evd_names`.
    images : bool
        Fetch the two images and fill ``input.image_a`` / ``image_b``.

    Returns
    -------
    HomographyPair
        ``input.matches``: all rows; ``input.quality``: the SIFT ratio;
        ``truth.inliers``: the labels; ``truth.H``: the DLT fit to the
        labelled inliers; ``truth.validation``: empty ``(0, 4)``.

    Raises
    ------
    ValueError
        Unknown ``name``, malformed file, fewer than 4 labelled inliers.
    """
    from ...geometry.homography_arithmetic import dlt

    _check_name(name, evd_names(), "EVD")
    path = fetch(_DATASET, f"extremeview/{name}_pts.txt")
    pts = _loadtxt(path, (0, 1, 2, 3, 4, 8), "matches")
    matches, ratio, label = pts[:, :4], pts[:, 4], pts[:, 5]
    if not np.all((label == 0) | (label == 1)):
        raise ValueError(f"{path}: labels must be 0 or 1")
    label = label == 1
    if label.sum() < 4:
        raise ValueError(f"{path}: fewer than 4 labelled inliers")
    H = dlt(matches[label, :2], matches[label, 2:])
    H = H / H[2, 2]
    a = _image(f"extremeview/{name}A") if images else ""
    b = _image(f"extremeview/{name}B") if images else ""
    return HomographyPair(name, "EVD", HomographyInput(matches, ratio, a, b),
                          HomographyTruth(H, label, np.empty((0, 4))))
