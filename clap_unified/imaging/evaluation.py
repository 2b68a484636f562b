"""Running every homography estimator on the same matches and scoring it.

Shared by the image-stitching chapter and ``bench/bench_homography.py``: one
row per (pair, method) with wall time, the paper's Lie distance to the ground
truth, mean corner error, inlier count, ratio of ground-truth inliers kept,
the median symmetric reprojection error on the ground-truth inliers and on
the validation points. Estimators see a pair's ``input`` only; its ``truth``
scores them.

The peers (:data:`PEERS`: OpenCV, PoseLib, COLMAP) are compared with the
library's CLAP by :func:`compare_peers` (one row per pair and method, every
estimate scored by the one rule of :func:`estimate_error`) and summarised by
:func:`peer_table`; ``bench/bench_peers.py`` is their front end.
"""

from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass

import numpy as np

from ..registry import get_strategy
from ..spaces.homography import DEFAULT_THRESHOLD
from .datasets.homography_benchmarks import HomographyInput, HomographyTruth
from .estimate import estimate_homography, strategy_of
from .metrics import corner_error, lie_error, symmetric_reprojection_error

__all__ = ["EVALUATED", "PEERS", "PEER_METHODS", "PairMatches", "compare_peers",
           "estimate_error", "evaluate_pair", "evaluate_trials", "peer_table", "shuffled_pair",
           "summarise", "vpg_pair_matches"]

#: Methods compared by default (the paper's): label -> (method name, uses match quality).
EVALUATED = {
    "CLAP": ("clap_paper", False),
    "CLAP ordered": ("clap_paper", True),
    "RANSAC (library)": ("ransac", False),
    "cv2.RANSAC": ("cv2_ransac", False),
    "cv2.USAC_MAGSAC": ("magsac", False),
    "USAC RANSAC 1000": ("usac_ransac_fixed", False),
}

#: Other libraries' estimators (baselines): label -> (method name, uses match quality).
PEERS = {
    "cv2.RANSAC": ("cv2_ransac", False),
    "cv2.USAC_MAGSAC": ("magsac", False),
    "cv2.USAC_ACCURATE": ("usac_accurate", False),
    "PoseLib": ("poselib", False),
    "COLMAP": ("colmap", False),
}

#: What :func:`compare_peers` runs by default: the library's CLAP (with its
#: protocol, and with match quality where a pair has it) and every peer.
PEER_METHODS = {"CLAP": ("clap", False), "CLAP quality": ("clap", True), **PEERS}


def estimate_error(H, pair) -> float:
    """The error of an estimate in pixels: one rule for every data set.

    The median symmetric reprojection error of ``H`` on
    ``pair.truth.validation`` when the pair has validation points (homogr,
    the synthetic pairs), else on the matches labelled inliers,
    ``pair.input.matches[pair.truth.inliers]`` (EVD).

    Parameters
    ----------
    H : ndarray of shape (3, 3) or None
        The estimate; None (a failed estimate) is an infinite error.
    pair : HomographyPair or PairMatches

    Returns
    -------
    float
        ``inf`` for a failed or non-finite estimate, NaN when the pair has
        neither validation points nor labelled inliers.

    Examples
    --------
    >>> from clap_unified.imaging.datasets import synthetic_pair
    >>> pair = synthetic_pair(0.3, noise=0.0, rng=0)
    >>> estimate_error(pair.truth.H, pair) < 1e-6, estimate_error(None, pair)
    (True, inf)
    """
    if H is None or not np.all(np.isfinite(H)):
        return float("inf")
    validation = np.asarray(pair.truth.validation, dtype=float).reshape(-1, 4)
    if not len(validation):
        validation = np.asarray(pair.input.matches)[np.asarray(pair.truth.inliers, bool)]
    if not len(validation):
        return float("nan")
    return float(np.median(symmetric_reprojection_error(H, validation)))


def compare_peers(pairs, methods=None, *, repeat: int = 5, seed: int = 0, dataset=None,
                  progress=None) -> list[dict]:
    """Every method on the same matches of every pair, timed and scored alike.

    Methods are interleaved (for each repeat, one run of each method in
    turn) so that a slow phase of the machine hits every method alike; the
    time of a method is the median of its ``repeat`` runs, measured by
    :func:`time.perf_counter` around :func:`estimate_homography` only. Every
    method sees ``pair.input`` only (the quality variants also
    ``input.quality``) and runs with ``rng=seed``.

    Parameters
    ----------
    pairs : iterable of HomographyPair or PairMatches
    methods : dict, optional
        ``label -> (method name, uses_quality)``; default
        :data:`PEER_METHODS`. A quality variant is skipped on pairs without
        quality.
    repeat : int
        Runs per method and pair (at least 1).
    seed : int
        The ``rng`` of every estimate.
    dataset : str, optional
        The ``dataset`` of the rows (default: each pair's ``dataset``).
    progress : callable, optional
        Called with 1 after every run (e.g. a ``tqdm`` bar's ``update``).

    Returns
    -------
    list of dict
        One per (pair, method): ``dataset, pair, n, ratio, method, name,
        peer`` (a baseline of another library), ``seconds`` (median),
        ``error`` (:func:`estimate_error`), ``success``, ``inliers``,
        ``model``.

    Raises
    ------
    ValueError
        ``repeat`` below 1.

    Examples
    --------
    >>> from clap_unified.imaging.datasets import synthetic_pair
    >>> rows = compare_peers([synthetic_pair(0.3, rng=0)], repeat=1,
    ...                      methods={"CLAP": ("clap", False), "PoseLib": ("poselib", False)})
    >>> [(r["method"], r["peer"], r["error"] < 5) for r in rows]
    [('CLAP', False, True), ('PoseLib', True, True)]
    """
    if int(repeat) < 1:
        raise ValueError(f"repeat: expected at least 1, got {repeat}")
    methods = PEER_METHODS if methods is None else methods
    rows = []
    for pair in pairs:
        m, quality = pair.input.matches, pair.input.quality
        run = {label: (name, {"quality": quality} if ordered else {})
               for label, (name, ordered) in methods.items()
               if not (ordered and quality is None)}
        times = {label: [] for label in run}
        results = {}
        for _ in range(int(repeat)):
            for label, (name, kw) in run.items():
                t0 = time.perf_counter()
                res = estimate_homography(m, name, rng=seed, **kw)
                times[label].append(time.perf_counter() - t0)
                results[label] = res
                if progress is not None:
                    progress(1)
        for label, (name, _) in run.items():
            res = results[label]
            H = res.model if res.success else None
            rows.append({"dataset": dataset or getattr(pair, "dataset", ""),
                         "pair": pair.name, "n": len(m),
                         "ratio": float(np.mean(pair.truth.inliers)), "method": label,
                         "name": name, "peer": get_strategy(strategy_of(name)).baseline,
                         "seconds": float(np.median(times[label])),
                         "error": estimate_error(H, pair), "success": bool(res.success),
                         "inliers": res.n_inliers, "model": H})
    return rows


def peer_table(rows, *, within: float = 5.0, reference: str = "cv2.RANSAC") -> list[dict]:
    """Per data set and method, the summary of :func:`compare_peers` rows.

    Parameters
    ----------
    rows : list of dict
        From :func:`compare_peers`.
    within : float
        Error (pixels, :func:`estimate_error`) below which an estimate counts
        as right.
    reference : str
        The method whose median time the ``vs_reference`` ratio divides by.

    Returns
    -------
    list of dict
        In the order of first appearance: ``dataset, method, pairs,
        within`` (pairs with error below ``within``), ``median_error``,
        ``ms`` (median time over pairs, milliseconds), ``vs_reference``
        (median time over the reference's, NaN without it), ``vs_best_peer``
        (over the best peer's), ``best_peer`` (the peer, ``peer`` rows, with
        the most pairs within ``within``, ties broken by the lower median
        error).

    Examples
    --------
    >>> rows = [{"dataset": "d", "pair": p, "method": m, "peer": m != "C", "seconds": t,
    ...          "error": e} for p in "ab" for m, t, e in [("C", 2.0, 1.0), ("R", 1.0, 9.0),
    ...                                                  ("P", 4.0, 2.0)]]
    >>> [(r["method"], r["within"], r["vs_reference"], r["vs_best_peer"])
    ...  for r in peer_table(rows, reference="R")]
    [('C', 2, 2.0, 0.5), ('R', 0, 1.0, 0.25), ('P', 2, 4.0, 1.0)]
    """
    out = []
    for dataset in dict.fromkeys(r["dataset"] for r in rows):
        mine = [r for r in rows if r["dataset"] == dataset]
        stats = {}
        for method in dict.fromkeys(r["method"] for r in mine):
            e = np.array([r["error"] for r in mine if r["method"] == method], float)
            t = np.array([r["seconds"] for r in mine if r["method"] == method], float)
            peer = any(r.get("peer", False) for r in mine if r["method"] == method)
            stats[method] = {"dataset": dataset, "method": method, "pairs": len(e),
                             "within": int(np.sum(e < within)),
                             "median_error": float(np.median(e)),
                             "ms": 1e3 * float(np.median(t)), "peer": peer}
        peers = [s for s in stats.values() if s["peer"]]
        best = (min(peers, key=lambda s: (-s["within"], s["median_error"]))["method"]
                if peers else None)
        ref = stats.get(reference)
        for s in stats.values():
            s["vs_reference"] = s["ms"] / ref["ms"] if ref else float("nan")
            s["vs_best_peer"] = s["ms"] / stats[best]["ms"] if best else float("nan")
            s["best_peer"] = best
            out.append(s)
    return out


def evaluate_pair(pair, *, size=None, methods=None, seed: int = 0, repeat: int = 1,
                  **options) -> list[dict]:
    """Run each method on ``pair.input`` and score it against ``pair.truth``.

    The estimators see ``pair.input.matches`` (and ``pair.input.quality`` for
    the ordered variants) and nothing else; ``pair.truth`` is read only to
    score their estimates.

    Parameters
    ----------
    pair : HomographyPair or PairMatches
        Anything with ``input`` (``matches``, ``quality``) and ``truth``
        (``H``, ``inliers``, ``validation``), e.g. from
        :func:`~clap_unified.imaging.datasets.load_homogr`,
        :func:`~clap_unified.imaging.datasets.load_evd` or
        :func:`vpg_pair_matches`.
    size : (width, height), optional
        Source image size for the corner error (default: the bounding box of
        the source points).
    methods : dict, optional
        ``label -> (estimator, uses_quality)``; default :data:`EVALUATED`.
        Ordered variants are skipped when the pair has no quality.
    seed : int
        The seed (``rng``) of every estimator (OpenCV's ignore it).
    repeat : int
        Runs per method; the time is the median.
    options
        Passed to every estimator that uses hypotheses (the library's, not
        OpenCV's), e.g. ``n_hypotheses`` and ``bandwidth_quantile``.

    Returns
    -------
    list of dict
        Keys ``method, seconds, lie, corner, inliers, recall, sre, validation,
        success, model`` (the estimate, None when it failed): ``recall`` is the
        fraction of ``truth.inliers`` within 3 px (symmetric) of the estimate,
        ``sre`` the median symmetric reprojection error on them, ``validation``
        the median symmetric reprojection error on ``truth.validation`` (NaN
        when it is empty).

    Raises
    ------
    ValueError
        ``pair`` without ``input`` and ``truth``, or ``repeat`` below 1.
    """
    if not (hasattr(pair, "input") and hasattr(pair, "truth")):
        raise ValueError("pair: expected an object with 'input' and 'truth' (a loader's result)")
    if int(repeat) < 1:
        raise ValueError(f"repeat: expected at least 1, got {repeat}")
    methods = EVALUATED if methods is None else methods
    m = pair.input.matches
    quality = pair.input.quality
    H_gt, gt_inliers = pair.truth.H, np.asarray(pair.truth.inliers, dtype=bool)
    validation = np.asarray(pair.truth.validation, dtype=float).reshape(-1, 4)
    if size is None:
        size = tuple(np.ceil(m[:, :2].max(0)))
    rows = []
    for label, (name, ordered) in methods.items():
        if ordered and quality is None:
            continue
        kw = dict(options) if get_strategy(strategy_of(name)).uses_hypotheses else {}
        if ordered:
            kw["quality"] = quality
        times, res = [], None
        for _ in range(repeat):
            t0 = time.perf_counter()
            res = estimate_homography(m, name, rng=seed, **kw)
            times.append(time.perf_counter() - t0)
        H = res.model if res.success else None
        if H is not None and gt_inliers.any():
            e = symmetric_reprojection_error(H, m)[gt_inliers]
            recall = float(np.mean(e < DEFAULT_THRESHOLD))
            sre = float(np.median(e))
        elif H is not None:
            recall, sre = float("nan"), float("nan")
        else:
            recall, sre = 0.0, float("inf")
        if not len(validation):
            val = float("nan")
        elif H is None:
            val = float("inf")
        else:
            val = float(np.median(symmetric_reprojection_error(H, validation)))
        rows.append({"method": label, "seconds": float(np.median(times)),
                     "lie": lie_error(H, H_gt), "corner": corner_error(H, H_gt, size),
                     "inliers": res.n_inliers, "recall": recall, "sre": sre,
                     "validation": val, "success": bool(res.success), "model": H})
    return rows


def shuffled_pair(pair, seed: int):
    """``pair`` with its matches in a random order (labels and quality follow).

    OpenCV's estimators are deterministic for a given list but depend on where
    the inliers sit in it; a trial of an experiment is one order of the
    matches (and one seed of the library's estimators).

    Parameters
    ----------
    pair : HomographyPair or PairMatches
    seed : int
        Seed of the permutation.

    Returns
    -------
    same type as ``pair``
        ``input.matches``, ``input.quality``, ``truth.inliers`` (and
        ``truth.decoys`` of a synthetic pair) permuted alike; ``truth.H``
        and ``truth.validation`` unchanged.

    Examples
    --------
    >>> from clap_unified.imaging.datasets import HomographyInput, HomographyPair, HomographyTruth
    >>> p = HomographyPair("p", "test", HomographyInput(np.arange(20.0).reshape(5, 4)),
    ...                    HomographyTruth(np.eye(3), np.arange(5) < 2, np.zeros((0, 4))))
    >>> q = shuffled_pair(p, 1)
    >>> bool(np.all(q.input.matches[q.truth.inliers, 0] < 8))
    True
    """
    order = np.random.default_rng(seed).permutation(len(pair.input.matches))
    q = pair.input.quality
    inp = dataclasses.replace(pair.input, matches=pair.input.matches[order],
                              quality=None if q is None else q[order])
    per_match = {"inliers": pair.truth.inliers[order]}
    if "decoys" in {f.name for f in dataclasses.fields(pair.truth)}:  # SyntheticTruth
        per_match["decoys"] = pair.truth.decoys[order]
    truth = dataclasses.replace(pair.truth, **per_match)
    return dataclasses.replace(pair, input=inp, truth=truth)


def evaluate_trials(pair, trials: int, *, methods=None, **options) -> list[dict]:
    """:func:`evaluate_pair` on ``trials`` shuffled copies of ``pair``.

    Trial ``t`` orders the matches by :func:`shuffled_pair` with seed ``t``
    and seeds the library's estimators with ``t``.

    Parameters
    ----------
    pair : HomographyPair or PairMatches
    trials : int
        Number of trials (at least 1).
    methods : dict, optional
        As in :func:`evaluate_pair`.
    options
        Passed to :func:`evaluate_pair` (``size``, estimator options).

    Returns
    -------
    list of dict
        The rows of every trial, each with a ``trial`` key.

    Raises
    ------
    ValueError
        ``trials`` below 1.
    """
    if int(trials) < 1:
        raise ValueError(f"trials: expected at least 1, got {trials}")
    rows = []
    for t in range(int(trials)):
        for r in evaluate_pair(shuffled_pair(pair, t), methods=methods, seed=t, **options):
            r["trial"] = t
            rows.append(r)
    return rows


def summarise(rows, key: str) -> dict:
    """Median of ``key`` per method over a list of :func:`evaluate_pair` rows."""
    out = {}
    for r in rows:
        out.setdefault(r["method"], []).append(r[key])
    return {k: float(np.median(v)) for k, v in out.items()}


@dataclass(frozen=True)
class PairMatches:
    """SIFT matches of one image pair of a VPG-layout set, split into input and truth.

    Attributes
    ----------
    scene : str
        The set's name ``"Sxx"``.
    pair : (int, int)
        1-based image indices.
    input : HomographyInput
        ``matches`` and ``quality`` (SIFT ratio) computed from the images,
        ``image_a`` / ``image_b`` the image files.
    truth : HomographyTruth or None
        ``H``: DLT fit to the set's ground-truth correspondences;
        ``inliers``: SIFT matches within 3 px (symmetric) of ``H``;
        ``validation``: the ground-truth correspondences themselves. None for
        pairs without ground truth (VPG S13-S36).
    """

    scene: str
    pair: tuple
    input: HomographyInput
    truth: HomographyTruth | None

    @property
    def name(self) -> str:
        """``"Sxx i-j"``."""
        return f"{self.scene} {self.pair[0]}-{self.pair[1]}"


def vpg_pair_matches(vpg_set, *, ratio: float = 0.75) -> list[PairMatches]:
    """SIFT + ratio-test matches of every pair of a VPG-layout set.

    Parameters
    ----------
    vpg_set : VPGSet
        From :func:`~clap_unified.imaging.datasets.load_vpg_set`; only its
        ``input`` (images) makes the matches, its ``truth`` scores them.
    ratio : float
        Lowe's ratio test.

    Returns
    -------
    list of PairMatches
        One per pair of ``vpg_set.pairs()``.

    Raises
    ------
    FileNotFoundError
        An image of a pair is missing.
    """
    from .features import read_image, sift_matches

    out = []
    images = vpg_set.input.images
    for i, j in vpg_set.pairs():
        if i not in images or j not in images:
            raise FileNotFoundError(f"{vpg_set.path}: images {i:02d} and {j:02d} are needed")
        m, q = sift_matches(read_image(images[i]), read_image(images[j]), ratio=ratio)
        inp = HomographyInput(m, q, str(images[i]), str(images[j]))
        truth = None
        if (i, j) in vpg_set.truth.correspondences:
            H = vpg_set.truth.H(i, j)
            inliers = (symmetric_reprojection_error(H, m) < DEFAULT_THRESHOLD if len(m)
                       else np.zeros(0, bool))
            truth = HomographyTruth(H, inliers, vpg_set.truth.correspondences[(i, j)])
        out.append(PairMatches(vpg_set.name, (i, j), inp, truth))
    return out
