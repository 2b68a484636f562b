"""AdelaideRMF: image pairs with several structures; the input kept apart from the labels.

AdelaideRMF (Wong, Chin, Yu, Suter, ICCV 2011) is the standard benchmark of
multi-model fitting. Each sequence is one image pair with SIFT
correspondences labelled by hand: 0 for a gross outlier, ``k > 0`` for the
structure it belongs to. Two kinds:

* ``"homography"`` (folder ``H/``): each structure is a plane, one homography
  (17 of the 19 standard sequences: ``johnsona`` and ``johnsonb`` are missing
  from the public copies);
* ``"fundamental"`` (folder ``F/``): each structure is a rigidly moving
  object, one fundamental matrix (all 19 sequences).

Each ``<name>.mat`` holds ``img1``, ``img2``, ``data`` (6 x N rows
``x1 y1 1 x2 y2 1``), ``score`` (the SIFT matching score) and ``label``.
:func:`load_adelaidermf` returns a :class:`MultiModelPair`, a frozen object
with two frozen parts whose arrays are read-only copies
(:mod:`clap_unified.datatypes`):

* ``pair.input`` (:class:`MultiModelInput`): ``matches``, ``score``,
  ``image_a``, ``image_b``: what an estimator may see;
* ``pair.truth`` (:class:`MultiModelTruth`): ``labels`` (0 = outlier,
  1..K structures) and ``n_structures``: what scores it, with
  :func:`~clap_unified.imaging.segmentation_metrics.misclassification_error`.

Files come from the manifest ``manifests/adelaidermf.json`` (package data)
through :func:`~clap_unified.imaging.datasets.sources.fetch` (mirror, cache
or the public source, sha256 checked). :func:`published_results` lists
published misclassification errors on the benchmark, each with where it was
read (``manifests/adelaidermf_published.json``).
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from functools import cache

import numpy as np

from ...datatypes import freeze_arrays
from .sources import MANIFESTS, fetch, load_manifest

__all__ = ["KINDS", "MultiModelInput", "MultiModelPair", "MultiModelTruth",
           "adelaidermf_names", "load_adelaidermf", "published_results",
           "read_adelaidermf_mat"]

_DATASET = "adelaidermf"

#: Kind of structure -> folder of the data set.
KINDS = {"homography": "H", "fundamental": "F"}


@dataclass(frozen=True)
class MultiModelInput:
    """What a multi-model estimator may see of one image pair.

    Attributes
    ----------
    matches : ndarray of shape (N, 4)
        Correspondences, rows ``(x1, y1, x2, y2)`` in pixels (read-only).
    score : ndarray of shape (N,)
        The SIFT matching score of each correspondence, as given upstream
        (float; the data set does not define a scale or direction).
    image_a, image_b : ndarray of uint8 or None
        The two images, ``(H, W, 3)`` or ``(H, W)`` (two F sequences are
        grey); None when loaded with ``images=False``.
    """

    matches: np.ndarray
    score: np.ndarray
    image_a: np.ndarray | None = None
    image_b: np.ndarray | None = None

    def __post_init__(self):
        for name in ("matches", "score"):
            object.__setattr__(self, name, np.asarray(getattr(self, name), dtype=float))
        freeze_arrays(self)
        if self.matches.ndim != 2 or self.matches.shape[1] != 4:
            raise ValueError(f"matches: expected shape (N, 4), got {self.matches.shape}")
        if self.score.shape != (len(self.matches),):
            raise ValueError(f"score: expected shape ({len(self.matches)},), "
                             f"got {self.score.shape}")


@dataclass(frozen=True)
class MultiModelTruth:
    """Evaluation data of one image pair: never input to an estimator.

    Attributes
    ----------
    labels : ndarray of int, shape (N,)
        The structure of each correspondence of ``input.matches``: 0 for a
        gross outlier, ``1..K`` for a structure.

    Examples
    --------
    >>> MultiModelTruth(np.array([0, 1, 2, 2])).n_structures
    2
    """

    labels: np.ndarray

    def __post_init__(self):
        labels = np.asarray(self.labels)
        if labels.ndim != 1 or not np.issubdtype(labels.dtype, np.integer):
            raise ValueError(f"labels: expected a 1-D integer array, got {labels.dtype} "
                             f"of shape {labels.shape}")
        if len(labels) and labels.min() < 0:
            raise ValueError("labels: expected 0 (outlier) or a positive structure index")
        object.__setattr__(self, "labels", labels.astype(np.int64))
        freeze_arrays(self)

    @property
    def n_structures(self) -> int:
        """Number of structures ``K`` (the largest label)."""
        return int(self.labels.max()) if len(self.labels) else 0


@dataclass(frozen=True)
class MultiModelPair:
    """One AdelaideRMF sequence: the estimator's ``input`` and the evaluation ``truth``.

    Attributes
    ----------
    name : str
    kind : str
        ``"homography"`` or ``"fundamental"``.
    input : MultiModelInput
    truth : MultiModelTruth
    """

    name: str
    kind: str
    input: MultiModelInput
    truth: MultiModelTruth

    def __post_init__(self):
        if len(self.truth.labels) != len(self.input.matches):
            raise ValueError(f"truth: {len(self.truth.labels)} labels for "
                             f"{len(self.input.matches)} matches")

    @property
    def outlier_ratio(self) -> float:
        """Fraction of gross outliers (label 0) among the input matches."""
        return float(np.mean(self.truth.labels == 0))


def _check_kind(kind) -> str:
    if kind not in KINDS:
        raise ValueError(f"kind: expected one of {sorted(KINDS)}, got {kind!r}")
    return KINDS[kind]


def adelaidermf_names(kind: str = "homography") -> list[str]:
    """Sequence names of one kind, from the manifest.

    Parameters
    ----------
    kind : {"homography", "fundamental"}

    Examples
    --------
    >>> len(adelaidermf_names("homography")), len(adelaidermf_names("fundamental"))
    (17, 19)
    >>> adelaidermf_names("fundamental")[:2]
    ['biscuit', 'biscuitbook']
    """
    _check_kind(kind)
    return list(load_manifest(_DATASET)[kind])


def read_adelaidermf_mat(path, *, images: bool = True) -> dict:
    """Read and check one AdelaideRMF ``.mat`` file (no sha256 check: see :func:`load_adelaidermf`).

    Parameters
    ----------
    path : path
        A MATLAB file with ``data`` (6 x N, rows ``x1 y1 1 x2 y2 1``),
        ``score`` (N), ``label`` (N) and, when ``images``, ``img1`` and
        ``img2`` (uint8).
    images : bool
        Read the two images (else they are not even decompressed).

    Returns
    -------
    dict
        ``matches`` (N, 4) float, ``score`` (N,) float, ``labels`` (N,) int,
        ``image_a``, ``image_b`` (uint8 arrays, or None without ``images``).

    Raises
    ------
    ValueError
        Naming the file: not a readable MATLAB file, a missing key, wrong
        shapes, homogeneous coordinates other than 1, non-finite values,
        negative or non-integer labels, images that are not uint8 2-D or 3-D.
    """
    from scipy.io import loadmat

    keys = ["data", "score", "label"] + (["img1", "img2"] if images else [])
    try:
        mat = loadmat(path, variable_names=keys)
    except Exception as exc:  # scipy raises ValueError, TypeError, MatReadError, ...
        raise ValueError(f"{path}: not a readable MATLAB file ({type(exc).__name__}: "
                         f"{exc})") from None
    missing = [k for k in keys if k not in mat]
    if missing:
        raise ValueError(f"{path}: missing {missing} (expected {keys})")
    data = np.asarray(mat["data"])
    if data.ndim != 2 or data.shape[0] != 6 or data.shape[1] == 0:
        raise ValueError(f"{path}: data must be 6 x N (x1 y1 1 x2 y2 1), got {data.shape}")
    try:
        data = data.astype(float)
    except (TypeError, ValueError):
        raise ValueError(f"{path}: data is not numeric ({data.dtype})") from None
    if not np.all(np.isfinite(data)):
        raise ValueError(f"{path}: non-finite values in data")
    if not np.allclose(data[[2, 5]], 1.0):
        raise ValueError(f"{path}: data rows 3 and 6 (homogeneous coordinates) must be 1")
    n = data.shape[1]
    out = {"matches": data[[0, 1, 3, 4]].T.copy()}
    for key, name in (("score", "score"), ("label", "labels")):
        v = np.asarray(mat[key])
        if v.size != n or v.ndim > 2 or (v.ndim == 2 and 1 not in v.shape):
            raise ValueError(f"{path}: {key} must hold {n} values (one per column of data), "
                             f"got shape {v.shape}")
        try:
            v = v.ravel().astype(float)
        except (TypeError, ValueError):
            raise ValueError(f"{path}: {key} is not numeric ({v.dtype})") from None
        if not np.all(np.isfinite(v)):
            raise ValueError(f"{path}: non-finite values in {key}")
        out[name] = v
    labels = out["labels"]
    if np.any(labels < 0) or np.any(labels != np.round(labels)):
        raise ValueError(f"{path}: labels must be 0 (outlier) or a positive integer")
    out["labels"] = labels.astype(np.int64)
    for key, name in (("img1", "image_a"), ("img2", "image_b")):
        if not images:
            out[name] = None
            continue
        img = np.asarray(mat[key])
        if img.dtype != np.uint8 or img.ndim not in (2, 3) or (img.ndim == 3
                                                               and img.shape[2] != 3):
            raise ValueError(f"{path}: {key} must be a uint8 image (H x W or H x W x 3), "
                             f"got {img.dtype} of shape {img.shape}")
        out[name] = img
    return out


def load_adelaidermf(name: str, kind: str = "homography", *,
                     images: bool = True) -> MultiModelPair:
    """One AdelaideRMF sequence: correspondences, scores and images as input, labels as truth.

    Parameters
    ----------
    name : str
        One of :func:`adelaidermf_names` of ``kind``.
    kind : {"homography", "fundamental"}
        The folder: ``H/`` (planes) or ``F/`` (moving objects).
    images : bool
        Read the two images into ``input.image_a`` / ``image_b`` (uint8,
        at most about 2 MB each); else they stay None and are not decoded.

    Returns
    -------
    MultiModelPair
        ``input.matches``: the columns of ``data`` as rows ``(x1, y1, x2,
        y2)``; ``input.score``: ``score``; ``truth.labels``: ``label`` (0 =
        outlier, 1..K structures).

    Raises
    ------
    ValueError
        Unknown ``kind`` or ``name``; a file that fails its sha256 check or
        lacks the expected keys and shapes (the message names the file).
    FileNotFoundError
        The file is neither mirrored, cached nor downloadable.

    Examples
    --------
    >>> pair = load_adelaidermf("bonython", images=False)     # doctest: +SKIP
    >>> pair.input.matches.shape, pair.truth.n_structures     # doctest: +SKIP
    ((198, 4), 1)
    """
    folder = _check_kind(kind)
    names = adelaidermf_names(kind)
    if name not in names:
        raise ValueError(f"name: {name!r} is not an AdelaideRMF {kind} sequence; "
                         f"expected one of {names}")
    path = fetch(_DATASET, f"{folder}/{name}.mat")
    d = read_adelaidermf_mat(path, images=images)
    return MultiModelPair(name, kind,
                          MultiModelInput(d["matches"], d["score"], d["image_a"], d["image_b"]),
                          MultiModelTruth(d["labels"]))


def published_results(kind: str | None = None) -> list[dict]:
    """Published misclassification errors on AdelaideRMF, each with its source.

    Read from the package data ``manifests/adelaidermf_published.json``: one
    dict per (method, paper, kind) with ``mean`` and ``median`` (percent,
    None when the source gives none), ``n_sequences``, ``models_given``,
    ``protocol`` and ``source`` (where the number was read).

    Parameters
    ----------
    kind : {"homography", "fundamental"} or None
        Only the results of that kind; None for all.

    Examples
    --------
    >>> r = [r for r in published_results("homography")
    ...      if r["method"] == "Progressive-X" and r["n_sequences"] == 19][0]
    >>> r["mean"], r["median"]
    (6.6, 4.1)
    """
    if kind is not None:
        _check_kind(kind)
    return [dict(r) for r in _published()["results"] if kind is None or r["kind"] == kind]


@cache
def _published() -> dict:
    return json.loads(MANIFESTS.joinpath("adelaidermf_published.json").read_text())
