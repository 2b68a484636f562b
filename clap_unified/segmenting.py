"""``segment``: several models from one data set, the multi-model counterpart of ``fit``.

Data flow of :func:`segment`, sharing :func:`~clap_unified.fitting.fit`'s parts::

    data --check_problem------> checked data and threshold
         --draw_hypotheses----> HypothesisSet            (unless given, or not used)
         --segmenter.run------> Segmentation             (candidate models, best first)
         --finish_partition---> models, labels           (the same finish for every method)
         --> SegmentationResult (frozen)

Every segmenter gets the same hypotheses (with the same seed), the same
threshold, the same minimum support and the same finish: each datum is given
to its nearest model within the threshold (or, with ``coherence > 0``, to the
model its neighbours share, by a graph cut: :mod:`clap_unified.coherence`),
each model is refitted on its own data, and a model left with fewer than
``min_support`` data is dropped
(:func:`~clap_unified.partition.refit_partition`); ``refine=False`` skips the
refit and keeps the segmenter's own labels.
"""

from __future__ import annotations

import math
import time

import numpy as np

from ._validation import check_int, check_positive
from .fitting import _own_options, check_problem, draw_hypotheses
from .partition import assign_labels, finish_partition
from .registry import get_segmenter
from .result import SegmentationResult
from .spaces.base import HypothesisSet, HypothesisSpace

__all__ = ["compare_segmenters", "default_min_support", "segment"]

#: Arguments :func:`segment` gives every segmenter's ``run``; the rest are its options.
COMMON = ("threshold", "rng", "n_hypotheses", "min_support")


def default_min_support(space, n_data: int) -> int:
    """Data a model must explain to count as a structure when the caller gives no number.

    At least 10 data, twice a minimal sample and 2 % of the data: a structure
    must be well more than the sample that made it, and more than a few
    outliers that happen to line up.
    """
    return max(10, 2 * space.min_samples, math.ceil(0.02 * n_data))


def segment(space, data, method: str = "clap", *, n_hypotheses: int = 2000,
            threshold: float | None = None, rng=None, hypotheses: HypothesisSet | None = None,
            min_support: int | None = None, refine: bool = True, sampling: dict | None = None,
            coherence: float = 0.0, coherence_neighbours: int = 8,
            **options) -> SegmentationResult:
    """Every model of ``space`` that ``data`` holds, and which datum belongs to which.

    Parameters
    ----------
    space : HypothesisSpace
        The model family (lines, circles, homographies, fundamental matrices...).
    data : array_like
        Data in the space's format (``space.check_data``).
    method : str
        A registered segmenter (:func:`~clap_unified.registry.segmenter_names`):
        ``"clap"`` (the dense clusters of hypotheses), ``"ransac"`` (sequential
        RANSAC), ``"randomized_hough"`` (the peaks of the accumulator),
        ``"t_linkage"`` (clustering the data by the hypotheses they prefer) and
        other libraries' estimators in a remove-inliers loop.
    n_hypotheses : int
        Hypotheses drawn once and shared (segmenters that use them).
    threshold : float, optional
        Inlier threshold in data units; default the space's.
    rng : None, int or numpy.random.Generator
        The seed: the same seed gives the same result, bit for bit.
    hypotheses : HypothesisSet, optional
        Use these instead of drawing them (to compare segmenters on identical
        hypotheses).
    min_support : int, optional
        Data a model must explain to be kept (:func:`~clap_unified.segmenting.default_min_support`).
    refine : bool
        The common finish: reassign the data to the nearest model, refit each
        model on its data, drop the models left with fewer than
        ``min_support`` (:func:`~clap_unified.partition.refit_partition`).
    sampling : dict, optional
        Space-specific options of hypothesis generation.
    coherence : float
        Spatial coherence of the finish: the cost of two neighbouring data on
        different models, in units of an outlier's cost (0: each datum to its
        nearest model; :mod:`clap_unified.coherence`). The same for every
        segmenter. Structures that interleave in space (their data are each
        other's neighbours) pay for every such pair: a large weight there
        makes every datum an outlier.
    coherence_neighbours : int
        Each datum's neighbours in the coherence graph (nearest data rows).
    **options
        The segmenter's own options.

    Returns
    -------
    SegmentationResult
        Frozen; ``labels`` has one integer per datum, ``-1`` for an outlier.
        Finding nothing is a result with no model and a reason.

    Examples
    --------
    Two lines, 80 and 60 points, and 60 points of clutter:

    >>> from clap_unified import LineSpace
    >>> rng = np.random.default_rng(0)
    >>> x = rng.uniform(-5, 5, 200)
    >>> pts = np.c_[x, np.where(np.arange(200) < 80, 0.5 * x + 1, -x)]
    >>> pts += rng.normal(0, 0.01, pts.shape)
    >>> pts[140:] = rng.uniform(-5, 5, (60, 2))
    >>> res = segment(LineSpace.for_data(pts), pts, "ransac", threshold=0.05, rng=0)
    >>> res.n_models, sorted(res.support.tolist())
    (2, [60, 80])
    >>> segment(LineSpace.for_data(pts), pts, "clap", threshold=0.05, rng=0).n_models
    2
    """
    t0 = time.perf_counter()
    if not isinstance(space, HypothesisSpace):
        raise ValueError(f"space: expected a HypothesisSpace, got {type(space).__name__}")
    segmenter = get_segmenter(method, space)
    _check_segmenter_options(segmenter, options)
    problem = check_problem(space, data, threshold)
    n_hypotheses = check_int(n_hypotheses, "n_hypotheses", minimum=1)
    n = len(problem.data)
    if min_support is None:
        min_support = default_min_support(space, n)
    min_support = check_int(min_support, "min_support", minimum=space.min_samples)
    coherence = check_positive(coherence, "coherence", allow_zero=True)
    coherence_neighbours = check_int(coherence_neighbours, "coherence_neighbours", minimum=1)
    hypotheses, g, gen = draw_hypotheses(
        problem, n_hypotheses, rng, hypotheses=hypotheses,
        sampling=sampling if segmenter.uses_hypotheses else None,
        wanted=segmenter.uses_hypotheses and hypotheses is None)
    if not segmenter.uses_hypotheses:
        hypotheses = None
    found = segmenter.run(space, problem.data, hypotheses, threshold=problem.threshold, rng=g,
                          n_hypotheses=n_hypotheses, min_support=min_support, **options)
    models = np.asarray(found.models, dtype=float).reshape((-1, *space.model_shape))
    scores = np.asarray(found.scores, dtype=float).reshape(-1)
    labels = found.labels
    if refine and len(models):
        models, labels, kept = finish_partition(space, models, problem.data, problem.threshold,
                                                min_support, coherence=coherence,
                                                coherence_neighbours=coherence_neighbours)
        scores = scores[kept]
    elif labels is None:
        labels = assign_labels(space, models, problem.data, problem.threshold)
    labels = np.asarray(labels, dtype=np.intp)
    diag = {**found.diagnostics, "hypotheses": 0 if hypotheses is None else len(hypotheses),
            "min_support": min_support, "coherence": coherence, "generation_seconds": gen,
            "seconds": time.perf_counter() - t0}
    if len(models) == 0:
        reason = (found.reason if found.reason != "ok" else
                  f"no structure explains {min_support} data (min_support)")
        return SegmentationResult(method, False, reason, models, np.full(n, -1, np.intp),
                                  scores[:0], found.selection, diag, space, problem.threshold)
    return SegmentationResult(method, True, "ok", models, labels, scores, found.selection, diag,
                              space, problem.threshold)


def compare_segmenters(space, data, *, methods=("randomized_hough", "ransac", "t_linkage", "clap"),
                       n_hypotheses: int = 2000, threshold: float | None = None, rng=None,
                       min_support: int | None = None, options: dict | None = None,
                       sampling: dict | None = None, coherence: float = 0.0,
                       coherence_neighbours: int = 8) -> dict[str, SegmentationResult]:
    """Several segmenters on the *same* hypotheses, drawn once: the multi-model ``compare``.

    Parameters
    ----------
    space : HypothesisSpace
    data : array_like
    methods : sequence of str
        Registered segmenters that apply to ``space``; those that draw their
        own samples (sequential RANSAC, the peers) draw them from ``rng``.
    n_hypotheses, threshold, rng, min_support, sampling, coherence, coherence_neighbours
        As :func:`segment`, the same for every method.
    options : dict, optional
        Per-method options, e.g. ``{"clap": {"label_cost": 2.0}}``.

    Returns
    -------
    dict
        Method name to :class:`~clap_unified.result.SegmentationResult`; each
        result's ``diagnostics["generation_seconds"]`` is the shared
        generation time.

    Examples
    --------
    >>> from clap_unified import LineSpace
    >>> rng = np.random.default_rng(0)
    >>> x = rng.uniform(-5, 5, 200)
    >>> pts = np.c_[x, np.where(np.arange(200) < 100, 0.5 * x + 1, -x)]
    >>> out = compare_segmenters(LineSpace.for_data(pts), pts, threshold=0.05, rng=0,
    ...                          methods=("ransac", "t_linkage", "clap"))
    >>> {name: r.n_models for name, r in out.items()}
    {'ransac': 2, 't_linkage': 2, 'clap': 2}
    """
    if isinstance(methods, str):
        methods = (methods,)
    if not isinstance(space, HypothesisSpace):
        raise ValueError(f"space: expected a HypothesisSpace, got {type(space).__name__}")
    segmenters = [get_segmenter(m, space) for m in methods]
    options = {} if options is None else dict(options)
    for key in options:
        if key not in methods:
            raise ValueError(f"options: {key!r} is not among methods {list(methods)}")
    problem = check_problem(space, data, threshold)
    n_hypotheses = check_int(n_hypotheses, "n_hypotheses", minimum=1)
    hypotheses, _, gen = draw_hypotheses(problem, n_hypotheses, rng, sampling=sampling,
                                         wanted=any(s.uses_hypotheses for s in segmenters))
    out = {}
    for s in segmenters:
        res = segment(space, problem.data, s.name, n_hypotheses=n_hypotheses,
                      threshold=problem.threshold, rng=rng, min_support=min_support,
                      hypotheses=hypotheses if s.uses_hypotheses else None,
                      coherence=coherence, coherence_neighbours=coherence_neighbours,
                      **options.get(s.name, {}))
        out[s.name] = res.replace(diagnostics={"generation_seconds": gen})
    return out


def _check_segmenter_options(segmenter, options) -> None:
    own = _own_options(segmenter.run)
    if own is None:
        return
    own = tuple(k for k in own if k not in COMMON)
    for key in options:
        if key not in own:
            raise ValueError(f"{key}: not an option of the {segmenter.name!r} segmenter "
                             f"(its options: {', '.join(own) or 'none'}; segment's own: "
                             f"n_hypotheses, threshold, rng, hypotheses, min_support, "
                             f"refine, sampling, coherence, coherence_neighbours)")
