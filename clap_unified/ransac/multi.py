"""Multi-model RANSAC: a set of models kept and improved as the hypotheses come (a segmenter).

MultiRANSAC (Zuliani, Kenney and Manjunath, ICIP 2005) keeps the best set of
at most ``max_models`` models instead of one model. Hypotheses arrive in
batches of ``max_models``; each batch is fused with the current set: the
candidates (the set and the batch) are ranked by their inliers, and taken in
that order while each brings ``min_support`` inliers that the models taken
before it do not explain (in the original, the inlier sets of the kept
models must be disjoint). The set after the last batch is the answer; the
number of models is at most ``max_models`` (MultiRANSAC's known number of
models) and is decided by the minimum support. Registered as the
``"multi_ransac"`` segmenter, on the hypotheses :func:`~clap_unified.segment`
draws for every segmenter.
"""

from __future__ import annotations

import numpy as np

from .._validation import check_int
from ..registry import Segmenter, register_segmenter
from ..result import Segmentation

__all__ = ["run_multi_ransac"]


def run_multi_ransac(space, data, hypotheses, *, threshold: float, rng=None,
                     n_hypotheses: int = 0, min_support: int,
                     max_models: int = 6) -> Segmentation:
    """MultiRANSAC (see the module): fuse each batch of hypotheses with the current set.

    Parameters
    ----------
    space, data, hypotheses, threshold
        As :func:`~clap_unified.segment` gives them; the hypotheses are used
        in the order drawn, ``max_models`` at a time.
    rng, n_hypotheses
        Unused (the hypotheses are drawn before).
    min_support : int
        Inliers, not explained by the models taken before, a model must bring.
    max_models : int
        The size of the set (MultiRANSAC's number of models, here an upper bound).

    Returns
    -------
    Segmentation
        ``scores``: each model's new inliers when it was taken.

    Examples
    --------
    >>> from clap_unified import LineSpace, segment
    >>> rng = np.random.default_rng(0)
    >>> x = rng.uniform(-5, 5, 200)
    >>> pts = np.c_[x, np.where(np.arange(200) < 100, 0.5 * x + 1, -x)]
    >>> res = segment(LineSpace.for_data(pts), pts, "multi_ransac", threshold=0.05, rng=0)
    >>> res.n_models, sorted(res.support.tolist())
    (2, [100, 100])
    """
    max_models = check_int(max_models, "max_models", minimum=1)
    if hypotheses is None or len(hypotheses) == 0:
        return Segmentation(np.empty((0, *space.model_shape)), np.zeros(0),
                            reason="no hypotheses: every minimal sample was degenerate")
    models = np.asarray(hypotheses.models)
    current = np.zeros(0, dtype=np.intp)
    gains = np.zeros(0)
    for start in range(0, len(models), max_models):
        candidates = np.r_[current, np.arange(start, min(start + max_models, len(models)))]
        inl = space.residuals(models[candidates], data) < threshold
        order = np.argsort(-inl.sum(axis=1), kind="stable")
        covered = np.zeros(len(data), bool)
        kept, kept_gain = [], []
        for i in order:
            gain = np.count_nonzero(inl[i] & ~covered)
            if gain >= min_support:
                kept.append(candidates[i])
                kept_gain.append(gain)
                covered |= inl[i]
                if len(kept) == max_models:
                    break
        current, gains = np.asarray(kept, dtype=np.intp), np.asarray(kept_gain, dtype=float)
    if len(current) == 0:
        return Segmentation(np.empty((0, *space.model_shape)), np.zeros(0),
                            reason=f"no hypothesis explains {min_support} data (min_support)",
                            selection="MultiRANSAC: none reached the minimum support")
    return Segmentation(models[current], gains,
                        selection=f"MultiRANSAC: a set of at most {max_models} models, each "
                                  f"bringing {min_support} inliers the others do not explain",
                        diagnostics={"batches": -(-len(models) // max_models)})


register_segmenter(Segmenter(
    "multi_ransac", run_multi_ransac,
    summary="MultiRANSAC: a set of models fused with each batch of hypotheses"))
