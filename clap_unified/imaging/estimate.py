"""Homography from point matches by CLAP, the library's RANSAC or a randomized Hough.

The paper's protocol (Sec. "Image Stitching Results") as defaults:

* CLAP: 400 candidate homographies from random 4-match samples (closed-form
  4-point solutions), clustered in the normalised frame of the matches
  (:meth:`HomographySpace.for_data`), robust centre by 5 rounds of trimming
  20 % (medoid by default; the Lie mean ``"karcher"``, the Lie median
  ``"median"``, ``"log_euclidean"`` and MAD rejection are options), then
  optional re-estimation on the data inliers of the centre (DLT refit, and
  by default a polish by reweighted DLT, :mod:`.refinement`);
* RANSAC: DLT on 4-samples, a fixed budget of 1000 iterations, refit on the
  inliers;
* Hough: the same candidates voted into cells of the normalised-frame log
  chart (:func:`~clap_unified.hough.randomized_hough`).

``quality`` (lower is better, e.g. the SIFT ratio of each match) makes the
samples progressive, as in PROSAC: the first candidates are drawn from the
best few matches, later ones from more and more of them. That is what lets
clustering work when only a few percent of the matches are right.
"""

from __future__ import annotations

import time

import numpy as np

from .._validation import (
    as_generator,
    check_array,
    check_choice,
    check_int,
    check_points,
    check_positive,
)
from ..result import ConsensusResult
from ..spaces.base import HypothesisSet
from ..spaces.homography import HomographySpace
from ..spaces.sampling import generate_hypotheses, sample_subsets
from .baselines import OPENCV_METHODS, opencv_homography

__all__ = ["CLAP_PROTOCOL", "METHODS", "clap_homography", "estimate_homography",
           "homography_hypotheses", "hough_homography", "ransac_homography"]

#: The paper's CLAP protocol for homographies.
CLAP_PROTOCOL = {"n_hypotheses": 400, "rounds": 5, "discard_fraction": 0.2}

#: Every method name :func:`estimate_homography` accepts.
METHODS = ("clap", "ransac", "hough", *OPENCV_METHODS)

#: Matches below this count cannot give a homography worth reporting.
MIN_MATCHES = 8


def _check_matches(matches) -> np.ndarray:
    data = check_points(matches, "matches", dim=4, min_count=4)
    if len(data) < MIN_MATCHES:
        raise ValueError(f"matches: too few matches ({len(data)}); at least {MIN_MATCHES} "
                         "are needed for a robust homography")
    return data


def homography_hypotheses(space, matches, n: int = 400, *, quality=None, pools: int = 8,
                          min_pool: int = 8, rng=None) -> HypothesisSet:
    """Candidate homographies from 4-match samples, uniform or progressive.

    Parameters
    ----------
    space : HomographySpace
    matches : ndarray of shape (N, 4)
    n : int
        Candidates wanted.
    quality : ndarray of shape (N,), optional
        Lower is better. When given, the ``n`` draws are split into ``pools``
        groups drawn from the best ``m_1 < m_2 < ... = N`` matches
        (geometrically growing, the first ``min_pool``); no 4-subset is
        drawn twice (a small pool may then give fewer candidates).
    pools, min_pool : int
    rng : None, int or numpy.random.Generator

    Returns
    -------
    HypothesisSet

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> src = rng.uniform(0, 640, (60, 2))
    >>> data = np.c_[src, src + 5.0]
    >>> hs = homography_hypotheses(HomographySpace(), data, 40, quality=np.arange(60), rng=0)
    >>> len(hs), int(hs.samples[:5].max()) < 8
    (40, True)
    """
    data = space.check_data(matches)
    n = check_int(n, "n", minimum=1)
    if quality is None:
        # one batch with a margin for degenerate samples, not a second full batch
        return generate_hypotheses(space, data, n, rng=rng, batch_size=n + n // 4 + 8)
    q = check_array(quality, "quality", shape=(len(data),))
    pools = check_int(pools, "pools", minimum=1)
    order = np.argsort(q, kind="stable")
    sizes = np.unique(np.geomspace(min(max(min_pool, 4), len(data)), len(data), pools)
                      .round().astype(int))
    per = np.diff(np.linspace(0, n, len(sizes) + 1).round().astype(int))
    g = as_generator(rng)
    models, samples = [], []
    drawn = bad = 0
    seen = set()
    for size, k in zip(sizes, per, strict=True):
        if k == 0:
            continue
        # distinct samples only: the first pools are small (8 matches have 70
        # 4-subsets), and a repeated sample would add a copy of a candidate,
        # support that no new data gives (and exact ties between clusters)
        idx = []
        for _ in range(8):
            # a few extra draws so degenerate samples do not leave the pool short
            for row in np.sort(order[sample_subsets(int(size), 4, int(k) + 8, rng=g)], axis=1):
                key = row.tobytes()
                if key not in seen and len(idx) < k + 8:
                    seen.add(key)
                    idx.append(row)
            if len(idx) >= k + 8:
                break
        if not idx:
            continue
        idx = np.array(idx)
        mod, owner = space.solve_minimal(data, idx)
        drawn += len(idx)
        bad += len(idx) - len(owner)
        models.append(mod[:k])
        samples.append(idx[owner[:k]])
    models = np.concatenate(models) if models else np.empty((0, 3, 3))
    samples = np.concatenate(samples) if samples else np.empty((0, 4), dtype=np.intp)
    return HypothesisSet(models, samples, drawn, bad, False, space)


def clap_homography(matches, *, n_hypotheses: int = 400, rounds: int = 5,
                    discard_fraction: float = 0.2, centre: str = "medoid",
                    rejection: str = "trim", metric: str = "lie_linear", refit: bool = True,
                    residual_threshold: float = 3.0, bandwidth_quantile: float = 0.02,
                    quality=None, polish: bool = True, hypotheses: HypothesisSet | None = None,
                    rng=None) -> ConsensusResult:
    """CLAP in homography parameter space with the paper's protocol.

    Parameters
    ----------
    matches : ndarray of shape (N, 4)
        Rows ``(x1, y1, x2, y2)``; ``H`` maps point 1 to point 2.
    n_hypotheses, rounds, discard_fraction
        400 candidates, 5 trimming rounds, 20 % discarded per round.
    centre : {"medoid", "karcher", "median", "log_euclidean"}
        Medoid, Lie (Karcher) mean, Lie median, log-Euclidean mean.
    rejection : {"trim", "mad", "none"}
    metric : {"lie_linear", "lie", "frobenius"}
        Distance between candidates, in the normalised frame of the matches
        (:class:`~clap_unified.geometry.homography_frame.HomographyInFrame`):
        the first-order Lie distance (default, no logarithms), the exact
        Lie distance, or Frobenius.
    refit : bool
        Re-estimate on the data inliers of the centre (DLT).
    residual_threshold : float
        Inlier threshold in pixels for the re-estimation.
    bandwidth_quantile : float
        Quantile of the candidates' 4-NN distances used as the neighbourhood
        radius (only a few percent of 4-samples are all inliers).
    quality : ndarray of shape (N,), optional
        Per-match quality, lower is better: progressive sampling
        (:func:`homography_hypotheses`).
    polish : bool
        With ``refit``: finish with
        :func:`~clap_unified.imaging.refinement.polish_homography` (reweighted
        DLT on the inliers).
    hypotheses : HypothesisSet, optional
        Cluster these candidates instead of drawing new ones.
    rng : None, int or numpy.random.Generator

    Returns
    -------
    ConsensusResult

    Examples
    --------
    >>> rng = np.random.default_rng(1)
    >>> src = rng.uniform(0, 640, (200, 2))
    >>> dst = src @ np.array([[0.9, 0.1], [-0.1, 0.9]]).T + [30.0, -20.0]
    >>> dst += rng.normal(0, 0.5, dst.shape)
    >>> dst[:100] = rng.uniform(0, 640, (100, 2))           # 50 % outliers
    >>> res = clap_homography(np.c_[src, dst], rng=0)
    >>> res.success, np.round(res.model[:2, 2]).tolist()
    (True, [30.0, -20.0])
    """
    from ..clap import clap

    data = _check_matches(matches)
    space = HomographySpace.for_data(data, metric=metric)
    if hypotheses is None:
        hypotheses = homography_hypotheses(space, data, n_hypotheses, quality=quality, rng=rng)
    res = clap(space, data, hypotheses=hypotheses, centre=centre, rejection=rejection,
               rounds=rounds, discard_fraction=discard_fraction, refit=refit,
               residual_threshold=residual_threshold, bandwidth_quantile=bandwidth_quantile)
    return _polished(res, data, residual_threshold) if (refit and polish) else res


def _polished(res, data, threshold):
    """``res`` with its model polished on its inliers (a failure stays a failure)."""
    from .refinement import polish_homography

    if not res.success:
        return res
    res.model, res.inliers = polish_homography(res.model, data, threshold=threshold)
    res.diagnostics["polished"] = True
    return res


def ransac_homography(matches, *, max_trials: int = 1000, residual_threshold: float = 3.0,
                      polish: bool = False, hypotheses: HypothesisSet | None = None,
                      rng=None) -> ConsensusResult:
    """The paper's baseline: DLT + RANSAC, fixed 1000 iterations, refit on the inliers.

    ``polish=True`` adds the same final polish as CLAP's default (not part of
    the paper's baseline).

    Examples
    --------
    >>> rng = np.random.default_rng(1)
    >>> src = rng.uniform(0, 640, (100, 2))
    >>> res = ransac_homography(np.c_[src, src + [4.0, 2.0]], rng=0)
    >>> res.success, np.round(res.model[:2, 2], 6).tolist()
    (True, [4.0, 2.0])
    """
    from ..ransac import ransac

    data = _check_matches(matches)
    res = ransac(HomographySpace(), data, hypotheses=hypotheses, max_trials=max_trials,
                 residual_threshold=residual_threshold, refit=True, rng=rng)
    return _polished(res, data, residual_threshold) if polish else res


def hough_homography(matches, *, n_hypotheses: int = 400, cell_size: float = 0.05,
                     residual_threshold: float = 3.0, quality=None,
                     hypotheses: HypothesisSet | None = None, rng=None) -> ConsensusResult:
    """Randomized Hough over the same candidates as CLAP.

    Candidates are binned on a grid (edge ``cell_size``) in the log chart of
    the normalised frame of the matches (SL(3), 8 coordinates), re-binned at
    the first peak; the estimate is the mean of the fullest cell, refitted on
    its data inliers.
    """
    from ..hough import randomized_hough

    data = _check_matches(matches)
    space = HomographySpace.for_data(data)
    if hypotheses is None:
        hypotheses = homography_hypotheses(space, data, n_hypotheses, quality=quality, rng=rng)
    cell_size = check_positive(cell_size, "cell_size")
    return randomized_hough(space, data, hypotheses=hypotheses, cell_size=cell_size,
                            residual_threshold=residual_threshold, refit=True)


def estimate_homography(matches, method: str = "clap", *, rng=None, **options
                        ) -> ConsensusResult:
    """One entry point for every method in :data:`METHODS` on the same matches.

    ``options`` go to the method's function (:func:`clap_homography`,
    :func:`ransac_homography`, :func:`hough_homography` or
    :func:`~clap_unified.imaging.baselines.opencv_homography`). The result's
    ``diagnostics["seconds"]`` is the wall time of the whole call.

    Examples
    --------
    >>> rng = np.random.default_rng(1)
    >>> src = rng.uniform(0, 640, (100, 2))
    >>> res = estimate_homography(np.c_[src, src + [4.0, 2.0]], "hough", rng=0)
    >>> res.success, np.round(res.model[:2, 2], 3).tolist()
    (True, [4.0, 2.0])
    """
    check_choice(method, "method", set(METHODS))
    t0 = time.perf_counter()
    if method == "clap":
        res = clap_homography(matches, rng=rng, **options)
    elif method == "ransac":
        res = ransac_homography(matches, rng=rng, **options)
    elif method == "hough":
        res = hough_homography(matches, rng=rng, **options)
    else:
        _check_matches(matches)
        res = opencv_homography(matches, method, **options)
    res.diagnostics["seconds"] = time.perf_counter() - t0
    return res
