"""CLAP across n possibilities: every cluster of refined hypotheses that pays for its label.

The multi-model CLAP, a segmenter of :func:`~clap_unified.segment`:

1. **refine** each hypothesis on its own inliers
   (:func:`~clap_unified.partition.refine_hypotheses`): minimal-sample
   hypotheses of one structure scatter with the noise of four points;
   refitted on what they explain, they move onto the structure (on the
   AdelaideRMF planes nearly every one still keeps an inlier set of its own,
   as chapter 7 of the book counts on barrsmith, so a small plane is often
   one refined hypothesis, and step 3 does the choosing);
2. **cluster** the refined hypotheses in hypothesis space: those that
   converged to one model (``bandwidth=None``: the same inlier set, hence the
   same refit) or that lie within ``bandwidth`` of a density seed
   (:func:`~clap_unified.clap.run_clap`'s global mode); each cluster's centre
   is a candidate and its support the hypotheses behind it;
3. **select** how many: the candidates whose set minimises the truncated
   residuals of the data plus a cost per model
   (:func:`~clap_unified.partition.select_by_label_cost`), or, with
   ``select="cover"``, the clusters by support while each explains
   ``min_support`` new data.

:func:`~clap_unified.segment` then gives every datum to its nearest model and
refits each (the finish every segmenter gets).
"""

from __future__ import annotations

import numpy as np

from .._validation import check_choice, check_int, check_positive
from ..partition import refine_hypotheses, select_by_label_cost, select_models
from ..registry import Segmenter, register_segmenter
from ..result import Segmentation
from ..spaces.base import HypothesisSet
from .clap import run_clap

__all__ = ["DEFAULT_LABEL_COST", "label_cost_of", "run_clap_segment"]

#: CLAP's default label cost, in units of ``min_support`` data at the threshold.
DEFAULT_LABEL_COST = 1.0


def label_cost_of(label_cost: float, min_support: int, threshold: float) -> float:
    """The cost of one model in squared data units: ``label_cost * min_support * threshold**2``.

    A model must save about ``label_cost * min_support`` data that would
    otherwise be outliers to pay for itself.

    Examples
    --------
    >>> label_cost_of(1.0, 10, 5.0)
    250.0
    """
    return float(label_cost) * int(min_support) * float(threshold) ** 2


def run_clap_segment(space, data, hypotheses: HypothesisSet, *, threshold: float, rng=None,
                     n_hypotheses: int = 0, min_support: int, refine_rounds: int = 1,
                     bandwidth: float | None = None, select: str = "label_cost",
                     label_cost: float = DEFAULT_LABEL_COST, max_models: int = 20,
                     max_clusters: int = 60) -> Segmentation:
    """The multi-model CLAP (see the module): refine, cluster, select.

    Parameters
    ----------
    space, data, hypotheses, threshold
        As :func:`~clap_unified.segment` gives them.
    rng, n_hypotheses
        Unused (the hypotheses are drawn before).
    min_support : int
        Data a model must explain (the label cost's unit and ``"cover"``'s rule).
    refine_rounds : int
        Refits of each hypothesis on its inliers before clustering (0: none).
    bandwidth : float or "auto", optional
        ``None``: a cluster is the hypotheses that converged to the same
        inlier set. A number: density clusters within this radius in the
        space's manifold distance (:func:`~clap_unified.clap.run_clap`,
        ``suppress=1``, at most ``max_clusters``); ``"auto"``: the same with
        :func:`~clap_unified.clap.auto_bandwidth` (the paper's CLAP, cluster
        after cluster).
    select : {"label_cost", "cover"}
        How many models: by the label cost (``label_cost * min_support *
        threshold**2`` per model), or greedily by cluster support.
    label_cost : float
        The cost of a model, in units of ``min_support`` data at the threshold.
    max_models, max_clusters : int

    Returns
    -------
    Segmentation
        ``scores``: each model's cluster support (hypotheses behind it).
    """
    check_choice(select, "select", {"label_cost", "cover"})
    refine_rounds = check_int(refine_rounds, "refine_rounds", minimum=0)
    label_cost = check_positive(label_cost, "label_cost")
    max_models = check_int(max_models, "max_models", minimum=1)
    if hypotheses is None or len(hypotheses) == 0:
        return Segmentation(np.empty((0, *space.model_shape)), np.zeros(0),
                            reason="no hypotheses: every minimal sample was degenerate")
    models = refine_hypotheses(space, hypotheses.models, data, threshold, rounds=refine_rounds)
    inl = space.residuals(models, data) < threshold
    if bandwidth is None:
        _, first, counts = np.unique(np.packbits(inl, axis=1), axis=0, return_index=True,
                                     return_counts=True)
        order = np.lexsort((first, -counts))  # by support, ties by first appearance
        centres, support = models[first[order]], counts[order]
        how = "hypotheses converged to the same inliers"
    else:
        if bandwidth != "auto":
            bandwidth = check_positive(bandwidth, "bandwidth")
        refined = HypothesisSet(models, hypotheses.samples, hypotheses.n_draws,
                                hypotheses.n_degenerate, hypotheses.exhaustive, space)
        found = run_clap(space, data, refined, threshold=threshold,
                         bandwidth=None if bandwidth == "auto" else bandwidth,
                         max_clusters=max_clusters, min_support=1, suppress=1.0)
        centres = np.array([c.model for c in found.clusters]).reshape(-1, *space.model_shape)
        support = np.array([c.support for c in found.clusters], dtype=int)
        bw = found.diagnostics.get("bandwidth", bandwidth)
        how = f"density clusters within bandwidth {bw:.3g}"
    if select == "label_cost":
        cost = label_cost_of(label_cost, min_support, threshold)
        kept = select_by_label_cost(space, centres, data, threshold, cost, max_models)
        rule = (f"label cost: a model must save {label_cost:g} x {min_support} data at the "
                f"threshold ({len(centres)} clusters: {how})")
    else:
        kept = select_models(space, centres, data, threshold, min_support, max_models)
        rule = (f"cover: clusters by support while each explains {min_support} new data "
                f"({len(centres)} clusters: {how})")
    return Segmentation(centres[kept], support[kept].astype(float), selection=rule,
                        diagnostics={"clusters": int(len(centres)),
                                     "refine_rounds": refine_rounds})


register_segmenter(Segmenter(
    "clap", run_clap_segment,
    summary="refined hypotheses clustered, as many clusters as pay their label cost"))
