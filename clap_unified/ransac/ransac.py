"""RANSAC: consensus scored in data space.

Every hypothesis is checked against every datum; the one with the best score
(inlier count, or the MSAC truncated quadratic cost) wins and is refitted on
its inliers. A fixed budget reproduces the paper's baseline (1000 samples);
``confidence`` turns on the classical adaptive stopping rule.
"""

from __future__ import annotations

import time

import numpy as np

from .._validation import as_generator, check_choice, check_fraction, check_int, check_positive
from ..refine import inliers_of, refit_on_inliers
from ..result import Cluster, ConsensusResult
from ..spaces.base import HypothesisSet
from ..spaces.sampling import sample_subsets

__all__ = ["ransac", "required_trials", "score_hypotheses"]


def required_trials(inlier_ratio: float, sample_size: int, confidence: float) -> float:
    """Samples needed to draw one all-inlier sample with probability ``confidence``.

    ``log(1 - confidence) / log(1 - inlier_ratio ** sample_size)``.

    Examples
    --------
    >>> print(f"{required_trials(0.5, 2, 0.99):.1f}")
    16.0
    """
    p = inlier_ratio**sample_size
    if p >= 1.0:
        return 1.0
    if p <= 0.0:
        return np.inf
    return float(np.log(1.0 - confidence) / np.log1p(-p))


def score_hypotheses(residuals, threshold: float, score: str = "inliers") -> np.ndarray:
    """Score rows of a residual matrix ``(H, N)``; larger is better.

    ``"inliers"`` counts residuals below ``threshold``; ``"msac"`` is minus the
    truncated quadratic cost ``sum(min(r^2, t^2))``.
    """
    if score == "inliers":
        return np.count_nonzero(residuals < threshold, axis=1).astype(float)
    return -np.sum(np.minimum(residuals**2, threshold**2), axis=1)


def ransac(space, data, *, hypotheses: HypothesisSet | None = None, max_trials: int = 1000,
           residual_threshold: float | None = None, score: str = "inliers",
           confidence: float | None = None, refit: bool = True, batch_size: int = 100,
           rng=None) -> ConsensusResult:
    """Random sample consensus over a hypothesis space.

    Parameters
    ----------
    space : HypothesisSpace
    data : array_like
        Data in the space's format, e.g. points ``(N, 2)`` for lines.
    hypotheses : HypothesisSet, optional
        Score these (in order) instead of drawing new samples; lets RANSAC run
        on exactly the hypotheses given to Hough and CLAP.
    max_trials : int
        Minimal samples drawn (the paper's baseline: 1000). With
        ``hypotheses`` it caps how many of them are scored.
    residual_threshold : float, optional
        Inlier threshold in data units; default ``space.default_residual_threshold``.
    score : {"inliers", "msac"}
    confidence : float in (0, 1), optional
        Stop early once this probability of having drawn an all-inlier
        sample is reached (adaptive RANSAC). ``None`` = fixed budget.
    refit : bool
        Refit the winner on its inliers (least squares).
    batch_size : int
        Samples solved and scored together (vectorised).
    rng : None, int or numpy.random.Generator

    Returns
    -------
    ConsensusResult

    Examples
    --------
    >>> from clap_unified.spaces import LineSpace
    >>> rng = np.random.default_rng(0)
    >>> x = rng.uniform(-5, 5, 60)
    >>> pts = np.c_[x, 0.5 * x + 1 + rng.normal(0, 0.01, 60)]
    >>> pts[:20] = rng.uniform(-5, 5, (20, 2))
    >>> res = ransac(LineSpace(), pts, residual_threshold=0.05, rng=0)
    >>> res.success, res.n_inliers >= 40
    (True, True)
    """
    t0 = time.perf_counter()
    data = space.check_data(data)
    max_trials = check_int(max_trials, "max_trials", minimum=1)
    check_choice(score, "score", {"inliers", "msac"})
    batch_size = check_int(batch_size, "batch_size", minimum=1)
    if confidence is not None:
        confidence = check_fraction(confidence, "confidence", inclusive=(False, False))
    t = (space.default_residual_threshold(data) if residual_threshold is None
         else check_positive(residual_threshold, "residual_threshold"))
    g = as_generator(rng)
    n, m = len(data), space.min_samples

    best_score, best_model, best_index, best_count = -np.inf, None, -1, 0
    drawn = scored = degenerate = 0
    needed = float(max_trials)
    while drawn < min(needed, max_trials):
        k = int(min(batch_size, max_trials - drawn))
        if hypotheses is not None:
            if drawn >= len(hypotheses):
                break
            k = min(k, len(hypotheses) - drawn)
            models = hypotheses.models[drawn:drawn + k]
        else:
            idx = sample_subsets(n, m, k, rng=g)
            models, owner = space.solve_minimal(data, idx)
            degenerate += k - len(np.unique(owner))
        if len(models):
            r = space.residuals(models, data)
            s = score_hypotheses(r, t, score)
            j = int(np.argmax(s))
            if s[j] > best_score:
                best_score, best_model, best_index = float(s[j]), models[j], scored + j
                best_count = int(np.count_nonzero(r[j] < t))
            scored += len(models)
        drawn += k
        if confidence is not None and best_model is not None:
            needed = required_trials(best_count / n, m, confidence)

    diag = {"trials": drawn, "hypotheses_scored": scored, "degenerate_samples": degenerate,
            "residual_threshold": t, "score_kind": score}
    n_hyp = len(hypotheses) if hypotheses is not None else 0
    if best_model is None:
        diag["seconds"] = time.perf_counter() - t0
        return ConsensusResult.failure("ransac", "every minimal sample was degenerate", n, n_hyp,
                                       space, **diag)
    model = best_model
    if refit:
        model, inliers = refit_on_inliers(space, model, data, t)
    else:
        inliers = inliers_of(space, model, data, t)
    if np.count_nonzero(inliers) < m:
        diag["seconds"] = time.perf_counter() - t0
        return ConsensusResult.failure("ransac", f"best model has fewer than {m} inliers", n,
                                       n_hyp, space, **diag)
    support = np.zeros(n_hyp, bool)
    if n_hyp:
        support[best_index] = True
    diag["seconds"] = time.perf_counter() - t0
    diag["best_hypothesis"] = best_index
    cluster = Cluster(model, int(np.count_nonzero(inliers)), 0.0, np.array([best_index]))
    return ConsensusResult("ransac", True, "ok", model, inliers, support, best_score,
                           [cluster], diag, space)
