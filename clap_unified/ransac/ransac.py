"""RANSAC: consensus scored in data space.

Every hypothesis is checked against every datum; the one with the best score
(inlier count, or the MSAC truncated quadratic cost) wins and is refitted on
its inliers. A fixed budget reproduces the paper's baseline (1000 samples);
``confidence`` turns on the classical adaptive stopping rule.

:func:`run_ransac` is the strategy registered as ``"ransac"``; :func:`ransac`
is :func:`~clap_unified.fit` with that method.
"""

from __future__ import annotations

import numpy as np

from .._validation import as_generator, check_choice, check_fraction, check_int
from ..fitting import fit
from ..registry import Strategy, register_strategy
from ..result import Cluster, Consensus, ConsensusResult
from ..spaces.base import HypothesisSet
from ..spaces.sampling import sample_subsets, unsolved_samples

__all__ = ["ransac", "required_trials", "run_ransac", "score_hypotheses"]


#: Residuals computed at once at most (one batch of hypotheses is scored in chunks).
SCORE_BLOCK = 1_000_000


def required_trials(inlier_ratio: float, sample_size: int, confidence: float) -> float:
    """Samples needed to draw one all-inlier sample with probability ``confidence``.

    ``log(1 - confidence) / log(1 - inlier_ratio ** sample_size)``.

    Examples
    --------
    >>> print(f"{required_trials(0.5, 2, 0.99):.1f}")
    16.0
    >>> required_trials(0.5, 2, 1.0), required_trials(1.0, 2, 1.0)  # no division by zero
    (inf, 1.0)
    """
    p = inlier_ratio**sample_size
    if p >= 1.0:
        return 1.0
    if p <= 0.0 or confidence >= 1.0:
        return np.inf  # certainty, or no all-inlier sample: no finite number of trials
    # log1p: a confidence of 1e-40 is one trial, not 0 (log(1 - 1e-40) == 0); + 0.0, not -0.0
    return float(np.log1p(-confidence) / np.log1p(-p)) + 0.0


def score_hypotheses(residuals, threshold: float, score: str = "inliers") -> np.ndarray:
    """Score rows of a residual matrix ``(H, N)``; larger is better.

    ``"inliers"`` counts residuals below ``threshold``; ``"msac"`` is minus the
    truncated quadratic cost ``sum(min(r^2, t^2))``.
    """
    if score == "inliers":
        return np.count_nonzero(residuals < threshold, axis=1).astype(float)
    return -np.sum(np.minimum(residuals**2, threshold**2), axis=1)


def ransac(space, data, **options) -> ConsensusResult:
    """RANSAC: :func:`~clap_unified.fit` with ``method="ransac"``.

    ``n_hypotheses`` is the trial budget (the paper's baseline: 1000); RANSAC's
    own options are documented at :func:`run_ransac`.

    Examples
    --------
    >>> from clap_unified.spaces import LineSpace
    >>> rng = np.random.default_rng(0)
    >>> x = rng.uniform(-5, 5, 60)
    >>> pts = np.c_[x, 0.5 * x + 1 + rng.normal(0, 0.01, 60)]
    >>> pts[:20] = rng.uniform(-5, 5, (20, 2))
    >>> res = ransac(LineSpace(), pts, threshold=0.05, rng=0)
    >>> res.success, res.n_inliers >= 40
    (True, True)
    """
    return fit(space, data, "ransac", **options)


def run_ransac(space, data, hypotheses: HypothesisSet | None, *, threshold: float, prior=None,
               radius=None, rng=None, n_hypotheses: int = 1000, score: str = "inliers",
               confidence: float | None = None, batch_size: int = 100) -> Consensus:
    """The RANSAC strategy: the hypothesis with the best score in data space.

    Parameters
    ----------
    space : HypothesisSpace
    data : ndarray
        Checked data in the space's format.
    hypotheses : HypothesisSet or None
        Score these, in order (at most ``n_hypotheses`` of them); ``None``
        draws minimal samples lazily, ``batch_size`` at a time.
    threshold : float
        Inlier threshold in data units.
    prior, radius
        Unused (with a prior, :func:`~clap_unified.fit` hands over only the
        hypotheses near it).
    rng : numpy.random.Generator
        Draws the minimal samples when no hypotheses are given.
    n_hypotheses : int
        Trial budget: minimal samples drawn, or hypotheses scored.
    score : {"inliers", "msac"}
        Inlier count, or minus the truncated quadratic cost.
    confidence : float in (0, 1), optional
        Stop early once this probability of having drawn an all-inlier
        sample is reached (adaptive RANSAC). ``None`` = fixed budget.
    batch_size : int
        Samples solved and scored together (vectorised).

    Returns
    -------
    Consensus
        The best hypothesis; ``diagnostics`` counts trials, hypotheses scored
        and degenerate samples.
    """
    check_choice(score, "score", {"inliers", "msac"})
    batch_size = check_int(batch_size, "batch_size", minimum=1)
    if confidence is not None:
        confidence = check_fraction(confidence, "confidence", inclusive=(False, False))
    t = threshold
    g = as_generator(rng)
    n, m = len(data), space.min_samples
    budget = n_hypotheses

    best_score, best_model, best_index, best_count = -np.inf, None, -1, 0
    drawn = scored = degenerate = 0
    needed = float(budget)
    while drawn < min(needed, budget):
        k = int(min(batch_size, budget - drawn))
        if hypotheses is not None:
            if drawn >= len(hypotheses):
                break
            k = min(k, len(hypotheses) - drawn)
            models = hypotheses.models[drawn:drawn + k]
        else:
            idx = sample_subsets(n, m, k, rng=g)
            models, owner = space.solve_minimal(data, idx)
            degenerate += unsolved_samples(k, owner)
        # score in chunks of at most SCORE_BLOCK residuals (memory stays bounded for
        # many data); the samples drawn, hence the result, do not depend on it
        step = max(1, SCORE_BLOCK // max(n, 1))
        for c in range(0, len(models), step):
            chunk = models[c:c + step]
            r = space.residuals(chunk, data)
            s = score_hypotheses(r, t, score)
            j = int(np.argmax(s))
            if s[j] > best_score:
                best_score, best_model, best_index = float(s[j]), chunk[j], scored + j
                best_count = int(np.count_nonzero(r[j] < t))
            scored += len(chunk)
        drawn += k
        if confidence is not None and best_model is not None:
            needed = required_trials(best_count / n, m, confidence)

    diag = {"trials": drawn, "hypotheses_scored": scored, "degenerate_samples": degenerate,
            "score_kind": score}
    if best_model is None:
        return Consensus.failed("every minimal sample was degenerate", **diag)
    diag["best_hypothesis"] = best_index
    n_hyp = len(hypotheses) if hypotheses is not None else 0
    support = np.zeros(n_hyp, bool)
    members = np.empty(0, np.intp)
    if n_hyp:
        support[best_index] = True
        members = np.array([best_index])
    cluster = Cluster(best_model, best_count, 0.0, members)
    return Consensus(best_model, (cluster,), support, best_score, "ok", diag)


def _finish(space, data, model, inliers, threshold, consensus):
    """Score the returned (refined) model again (``fit``'s success rule has already
    failed a model with fewer inliers than a minimal sample)."""
    kind = consensus.diagnostics["score_kind"]
    if kind == "inliers":  # the inliers are the residuals below the threshold: count them
        return float(np.count_nonzero(inliers)), "ok"
    r = space.residuals(np.asarray(model)[None], data)
    return float(score_hypotheses(r, threshold, kind)[0]), "ok"


register_strategy(Strategy(
    "ransac", run_ransac, draws_samples=True, finish=_finish,
    summary="the hypothesis with the most inliers (or best MSAC score) in data space"))
