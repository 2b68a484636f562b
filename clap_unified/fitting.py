"""``fit``: the one entry point, and ``compare``: several strategies on one hypothesis set.

Data flow of :func:`fit`::

    data --space.check_data--> checked data
         --space.hypotheses--> HypothesisSet          (unless given, or not used)
         --space.near_prior--> the hypotheses near the prior (with ``prior``)
         --strategy.run------> Consensus              (where the consensus is)
         --space.refine------> model, inliers         (local optimisation)
         --strategy.finish---> score                  (of the returned model)
         --> ConsensusResult (frozen)

Every application (lines, 2D and 3D localization, homographies, stitching)
and every command of the CLI goes through :func:`fit`.
"""

from __future__ import annotations

import dataclasses
import functools
import inspect
import math
import time
from dataclasses import dataclass

import numpy as np

from ._validation import (
    Checked,
    as_generator,
    check_array,
    check_choice,
    check_int,
    check_positive,
    unwrap_checked,
)
from .presets import resolve_preset
from .registry import get_strategy
from .result import ConsensusResult
from .spaces.base import HypothesisSet, HypothesisSpace
from .spaces.lines import LineSpace

__all__ = ["ALL_INLIER_SAMPLES", "compare", "fit", "fit_line"]

#: ``fit(max_hypotheses=...)`` draws hypotheses until about this many all-inlier
#: minimal samples are expected among them.
ALL_INLIER_SAMPLES = 5

#: Arguments :func:`fit` gives every strategy's ``run``; the rest are its options.
COMMON = ("threshold", "prior", "radius", "rng", "n_hypotheses")


def fit(space, data, method: str = "clap", *, n_hypotheses: int | None = None,
        threshold: float | None = None, rng=None, hypotheses: HypothesisSet | None = None,
        prior=None, radius=None, refine: bool | None = None, sampling: dict | None = None,
        max_hypotheses: int | None = None, preset=None, **options) -> ConsensusResult:
    """Robust estimate of one model of ``space`` from ``data`` by the strategy ``method``.

    Parameters
    ----------
    space : HypothesisSpace
        The model family (lines, homographies, poses...).
    data : array_like
        Data in the space's format (``space.check_data``).
    method : str
        A registered strategy (:func:`~clap_unified.registry.strategy_names`):
        ``"clap"``, ``"ransac"``, ``"randomized_hough"``, and, where they
        apply, ``"hough"`` (lines), OpenCV's and Open3D's estimators.
    n_hypotheses : int, optional
        The hypothesis budget: hypotheses generated (CLAP, randomized Hough),
        minimal samples drawn or hypotheses scored (RANSAC). Default the
        preset's, else 1000. With a preset that has an adaptive budget
        (``max_hypotheses``, e.g. the homography CLAP's), this is the first
        budget: more may be drawn when it is short (see ``max_hypotheses``).
    threshold : float, optional
        Inlier threshold in data units; default the preset's, else the
        space's (or strategy's).
    rng : None, int or numpy.random.Generator
        The seed: the same seed gives the same result, bit for bit.
    hypotheses : HypothesisSet, optional
        Use these instead of generating them (to compare strategies on
        identical hypotheses).
    prior : model, optional
        A previous estimate. Only hypotheses within ``radius`` of it are used
        (``space.near_prior``); CLAP then runs in local mode. A space that
        declares ``prior_hypotheses`` also builds its hypotheses from the data
        association the prior implies.
    radius : float (or what the space's ``near_prior`` accepts), optional
        The gate around ``prior``; required with it. Measured by the distance
        of the space the call runs in (``result.space.manifold``): a preset
        that builds the space from a plain one chooses that distance (the
        homography CLAP's: pixels at anchors of the matched region).
    refine : bool, optional
        Refine the consensus model on its data inliers (``space.refine``)
        before the result is built. Default the preset's, else ``True``.
    sampling : dict, optional
        Space-specific options of hypothesis generation (e.g. ``quality`` of
        homography matches for progressive sampling).
    max_hypotheses : int, optional
        Adaptive budget, for strategies that use hypotheses fit generates.
        After a first fit with ``n_hypotheses``, the inlier ratio ``w`` of its
        estimate says how many all-inlier minimal samples to expect,
        ``n_hypotheses * w**min_samples``; when that is below
        :data:`~clap_unified.fitting.ALL_INLIER_SAMPLES`, ``min(max_hypotheses,
        ceil(ALL_INLIER_SAMPLES / w**min_samples))`` hypotheses are drawn
        (the same generator, continued) and fitted again, and the estimate
        with more inliers is returned (``diagnostics["adaptive_hypotheses"]``:
        the second budget, or ``n_hypotheses`` when one fit was enough;
        ``diagnostics["first_inlier_ratio"]``: ``w``, which sized it). The
        counterpart of RANSAC's adaptive stopping for a strategy that needs
        several right hypotheses, not one. Default the preset's (raised to
        ``n_hypotheses`` when that is larger; none with ``hypotheses``), else
        none. ``max_hypotheses=n_hypotheses`` keeps one budget whatever the
        preset (``None`` means "the preset's").
    preset : str or Preset, optional
        The defaults this call starts from (:mod:`~clap_unified.presets`):
        ``"default"`` (the library's best), ``"paper"`` (the paper's
        protocol), ``"own"`` (the strategy's own defaults, no preset), a protocol name
        (``"clap_paper"``...) or a :class:`~clap_unified.presets.Preset`.
        ``None``: ``"default"`` when ``space`` is plain (e.g.
        ``HomographySpace()``), else ``"own"``. A preset builds its space
        from a plain space (homographies: in the frame of the matches, its
        metric and polish); a space configured by hand is used as given,
        and a named preset with it applies whole when the space is the one
        the preset builds, else raises ``ValueError`` naming ``preset`` and
        the conflicting settings (:func:`~clap_unified.presets.space_conflicts`).
        Every argument passed explicitly, and every option, overrides the preset.
    **options
        The strategy's own options (e.g. ``bandwidth`` for CLAP,
        ``cell_size`` for randomized Hough, ``score`` for RANSAC); with a
        preset on a plain space, also the preset's space settings
        (homographies: ``frame``, ``metric``, ``polish``, ``screen``).

    Returns
    -------
    ConsensusResult
        Frozen. ``diagnostics["seconds"]`` is the wall time of the call,
        ``diagnostics["generation_seconds"]`` the part spent generating
        hypotheses.

    Raises
    ------
    ValueError
        Naming the argument: unknown method, method not for this space,
        bad data, threshold, budget or option. A degenerate problem is not
        an error: it gives ``success=False`` with a reason.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> x = rng.uniform(-5, 5, 100)
    >>> pts = np.c_[x, 0.5 * x + 1 + rng.normal(0, 0.01, 100)]
    >>> pts[:60] = rng.uniform(-5, 5, (60, 2))             # 60 % outliers
    >>> res = fit(LineSpace.for_data(pts), pts, "clap", threshold=0.05, rng=0)
    >>> res.success, res.n_inliers >= 40
    (True, True)
    >>> fit(LineSpace(), pts, "ransac", threshold=0.05, rng=0).n_inliers >= 40
    True

    On homographies the plain space gets the library's tuned CLAP, the same
    as :func:`~clap_unified.imaging.estimate_homography`; ``preset="paper"``
    the paper's protocol:

    >>> from clap_unified.spaces import HomographySpace
    >>> src = rng.uniform(0, 640, (100, 2))
    >>> m = np.c_[src, src + [30.0, -20.0] + rng.normal(0, 0.5, (100, 2))]
    >>> m[:40, 2:] = rng.uniform(0, 640, (40, 2))            # 40 % outliers
    >>> res = fit(HomographySpace(), m, "clap", rng=0)
    >>> res.success, res.space.polish, np.round(res.model[:2, 2]).tolist()
    (True, 2.0, [30.0, -20.0])
    >>> fit(HomographySpace(), m, "clap", rng=0, preset="paper").diagnostics["hypotheses"]
    400
    """
    t0 = time.perf_counter()
    if not isinstance(space, HypothesisSpace):
        raise ValueError(f"space: expected a HypothesisSpace, got {type(space).__name__}")
    strategy = get_strategy(method, space)
    if n_hypotheses is not None:
        n_hypotheses = check_int(n_hypotheses, "n_hypotheses", minimum=1)
    if max_hypotheses is not None:
        max_hypotheses = check_int(max_hypotheses, "max_hypotheses", minimum=1)
    given = {k: v for k, v in (("n_hypotheses", n_hypotheses), ("threshold", threshold),
                               ("refine", refine), ("max_hypotheses", max_hypotheses))
             if v is not None}
    # the one check of the data on fit's path: what it calls gets them checked
    data = data if isinstance(data, Checked) else Checked(space.check_data(data))
    space, args, options = resolve_preset(space, data, method, preset, given, options,
                                          hypotheses_given=hypotheses is not None)
    n_hypotheses = args.get("n_hypotheses", 1000)
    threshold, max_hypotheses = args.get("threshold"), args.get("max_hypotheses")
    refine = args.get("refine", True)
    _check_options(strategy, options)
    problem = check_problem(space, data, threshold, prior, radius,
                            default_threshold=_strategy_threshold(strategy, options))
    n_hypotheses = check_int(n_hypotheses, "n_hypotheses", minimum=1)
    if max_hypotheses is not None:
        return _fit_adaptive(problem, method, strategy, n_hypotheses, max_hypotheses, rng,
                             hypotheses, refine, sampling, options, t0)
    return _fit_once(problem, method, strategy, n_hypotheses, rng, hypotheses, refine,
                     sampling, options, t0)


def _strategy_threshold(strategy, options):
    """The strategy's default threshold as ``check_problem`` takes it, or ``None``."""
    if strategy.default_threshold is None:
        return None
    return lambda space, data: strategy.default_threshold(space, data, options)


def _fit_once(problem, method, strategy, n_hypotheses, rng, hypotheses, refine, sampling,
              options, t0) -> ConsensusResult:
    """One fit of a checked problem: draw, gate, run, refine, finish, build the result."""
    space, n = problem.space, len(problem.data)
    wanted = (strategy.uses_hypotheses and hypotheses is None
              and not (strategy.draws_samples and problem.prior is None))
    hypotheses, g, gen = draw_hypotheses(problem, n_hypotheses, rng, hypotheses=hypotheses,
                                         sampling=sampling if strategy.uses_hypotheses else None,
                                         wanted=wanted)
    if not strategy.uses_hypotheses:
        hypotheses = None
    n_hyp = 0 if hypotheses is None else len(hypotheses)
    diag = {}
    candidates, keep = hypotheses, None
    if not strategy.gates_prior:
        candidates, keep, n_near = gate_prior(problem, hypotheses)
        if n_near is not None:
            diag["near_prior"] = n_near

    def failed(reason):
        return ConsensusResult.failure(method, reason, n, n_hyp, space, problem.threshold,
                                       **{**diag, "hypotheses": n_hyp, "generation_seconds": gen,
                                          "seconds": time.perf_counter() - t0})

    if candidates is not None and len(candidates) == 0:
        if problem.prior is not None and n_hyp:
            return failed(f"no hypothesis within radius {describe_radius(problem.radius)} of "
                          f"the prior ({n_hyp} generated)")
        return failed("no hypotheses: every minimal sample was degenerate")
    consensus = strategy.run(space, problem.data, candidates, threshold=problem.threshold,
                             prior=problem.prior, radius=problem.radius, rng=g,
                             n_hypotheses=n_hypotheses, **options)
    diag.update(consensus.diagnostics)
    if consensus.model is None:
        return failed(consensus.reason)
    clusters, support = _to_hypothesis_indices(consensus, keep, n_hyp, diag)
    model, inliers = finish_model(problem, consensus.model, refine=refine)
    reason = success_rule(space, inliers)
    if reason != "ok":
        return failed(reason)
    score = consensus.score
    if strategy.finish is not None:
        score, reason = strategy.finish(space, problem.data, model, inliers, problem.threshold,
                                        consensus)
    if reason != "ok":
        return failed(reason)
    diag.update(hypotheses=n_hyp, generation_seconds=gen, seconds=time.perf_counter() - t0)
    return ConsensusResult(method, True, "ok", model, inliers, support, float(score),
                           clusters, diag, space, problem.threshold)


def _fit_adaptive(problem, method, strategy, n_hypotheses, max_hypotheses, rng, hypotheses,
                  refine, sampling, options, t0) -> ConsensusResult:
    """``fit(max_hypotheses=...)``: a second, larger budget when the first one was short."""
    max_hypotheses = check_int(max_hypotheses, "max_hypotheses", minimum=n_hypotheses)
    if hypotheses is not None:
        raise ValueError("max_hypotheses: not with hypotheses= (fit draws no more)")
    if not strategy.uses_hypotheses or strategy.draws_samples:
        raise ValueError(f"max_hypotheses: only for a strategy that uses hypotheses fit "
                         f"generates (not with hypotheses=, not for {method!r})")
    g = as_generator(rng)
    first = _fit_once(problem, method, strategy, n_hypotheses, g, None, refine, sampling,
                      options, t0)
    w = first.n_inliers / len(problem.data) if first.success else 0.0
    need = (max_hypotheses if w == 0 else
            min(max_hypotheses, math.ceil(ALL_INLIER_SAMPLES / w ** problem.space.min_samples)))
    best = first
    if need > n_hypotheses:
        second = _fit_once(problem, method, strategy, need, g, None, refine, sampling, options,
                           time.perf_counter())
        if second.success and (not first.success or second.n_inliers > first.n_inliers):
            best = second
    return best.replace(diagnostics={"adaptive_hypotheses": max(need, n_hypotheses),
                                     "first_inlier_ratio": w,
                                     "seconds": time.perf_counter() - t0})


@dataclass(frozen=True)
class Problem:
    """A checked estimation problem: what :func:`fit` and :func:`segment` share.

    Built by :func:`check_problem`; every field is valid for ``space``.

    Attributes
    ----------
    space : HypothesisSpace
    data : ndarray
        The data as ``space.check_data`` returns it.
    threshold : float
        The inlier threshold, in data units.
    prior : ndarray or None
        A previous estimate, one model of ``space``.
    radius : float, ndarray or None
        The gate around ``prior``.
    """

    space: HypothesisSpace
    data: np.ndarray
    threshold: float
    prior: np.ndarray | None = None
    radius: object = None


def check_problem(space, data, threshold=None, prior=None, radius=None, *,
                  default_threshold=None) -> Problem:
    """Check the arguments every entry point takes, once; errors name the argument.

    ``data`` is checked by ``space.check_data`` unless the caller has done so and
    passes them wrapped in :class:`~clap_unified._validation.Checked`.
    ``default_threshold(space, data) -> float`` gives the threshold when none is
    passed (default: ``space.default_threshold(data)``).
    """
    if not isinstance(space, HypothesisSpace):
        raise ValueError(f"space: expected a HypothesisSpace, got {type(space).__name__}")
    data = unwrap_checked(data, space.check_data)
    if threshold is None:
        threshold = (default_threshold(space, data) if default_threshold is not None
                     else space.default_threshold(data))
    else:
        threshold = check_positive(threshold, "threshold")
    if prior is not None:
        prior = space.manifold.validate(prior, "prior")
        if prior.shape != tuple(space.model_shape):
            raise ValueError(f"prior: expected one model of shape {space.model_shape}, "
                             f"got shape {prior.shape}")
        if radius is None:
            raise ValueError("radius: a prior needs a radius (the gate around it)")
        if np.ndim(radius) == 0:
            radius = check_positive(radius, "radius")
        else:  # a space-specific gate, e.g. (max_translation, max_rotation)
            radius = check_array(radius, "radius", shape=(None,))
            if len(radius) == 0 or np.any(radius <= 0):
                raise ValueError(f"radius: expected positive bounds, got {radius.tolist()}")
    return Problem(space, data, threshold, prior, radius)


def draw_hypotheses(problem: Problem, n_hypotheses: int, rng, *, hypotheses=None,
                    sampling=None, wanted: bool = True):
    """The hypotheses of a fit: ``(hypotheses, rng, seconds)``.

    Given ``hypotheses`` are checked and used; otherwise, when ``wanted``,
    ``space.hypotheses`` draws ``n_hypotheses`` from ``rng`` (made a
    Generator, returned so that a strategy continues the same stream).
    """
    if hypotheses is not None and not isinstance(hypotheses, HypothesisSet):
        raise ValueError(f"hypotheses: expected a HypothesisSet, got {type(hypotheses).__name__}")
    if hypotheses is not None or not wanted:
        if sampling:
            raise ValueError("sampling: only used when fit generates the hypotheses")
        return hypotheses, rng, 0.0
    t0 = time.perf_counter()
    g = as_generator(rng)
    hypotheses = problem.space.hypotheses(problem.data, n_hypotheses, rng=g, prior=problem.prior,
                                          radius=problem.radius, **(sampling or {}))
    return hypotheses, g, time.perf_counter() - t0


def gate_prior(problem: Problem, hypotheses):
    """The hypotheses within the prior's radius: ``(candidates, keep, n_near)``.

    ``keep`` maps the candidates' indices to the hypotheses' (``None`` when
    every hypothesis is kept or there is no prior); ``n_near`` is ``None``
    without a prior.
    """
    if problem.prior is None or hypotheses is None:
        return hypotheses, None, None
    near = problem.space.near_prior(problem.prior, hypotheses.models, problem.radius)
    n_near = int(np.count_nonzero(near))
    if n_near == len(hypotheses):
        return hypotheses, None, n_near
    keep = np.flatnonzero(near)
    return hypotheses.subset(keep), keep, n_near


def _to_hypothesis_indices(consensus, keep, n_hyp, diag):
    """Clusters and support of a consensus over candidates, as indices into the hypotheses."""
    clusters, support = list(consensus.clusters), consensus.support
    if keep is None:
        return clusters, support
    clusters = [dataclasses.replace(c, members=keep[c.members]) for c in clusters]
    support = np.zeros(n_hyp, bool)
    support[keep[np.flatnonzero(consensus.support)]] = True
    if "best_hypothesis" in diag:  # RANSAC's winner, an index like the members
        diag["best_hypothesis"] = int(keep[diag["best_hypothesis"]])
    return clusters, support


def finish_model(problem: Problem, centre, *, refine: bool = True):
    """``(model, inliers)``: ``centre`` refined on its data inliers, or as it is."""
    if refine:
        return problem.space.refine(centre, problem.data, problem.threshold)
    return centre, problem.space.inliers(centre, problem.data, problem.threshold)


def success_rule(space, inliers) -> str:
    """The one success rule of :func:`fit`, for every strategy: ``"ok"`` or why it fails.

    A model with fewer inliers than a minimal sample (``space.min_samples``)
    is not supported by the data, whichever strategy found it: the result is a
    failure with this reason (RANSAC, CLAP, randomized Hough and the peers
    alike; before, CLAP and randomized Hough could succeed with no inlier at
    a tiny threshold where RANSAC failed).

    Examples
    --------
    >>> success_rule(LineSpace(), np.array([True, False, False]))
    'the model has 1 inlier(s), fewer than a minimal sample (2)'
    >>> success_rule(LineSpace(), np.array([True, True, False]))
    'ok'
    """
    m, k = space.min_samples, int(np.count_nonzero(inliers))
    if k < m:
        return f"the model has {k} inlier(s), fewer than a minimal sample ({m})"
    return "ok"


def describe_radius(radius) -> str:
    """A gate for messages: ``0.5`` or ``(0.5, 0.17)``."""
    return f"{radius:g}" if np.ndim(radius) == 0 else str(tuple(float(r) for r in radius))


def _own_options(run) -> tuple[str, ...] | None:
    """The keyword options of a strategy's ``run`` (``None``: it takes any); looked up once."""
    try:
        return _cached_options(run)
    except TypeError:  # an unhashable callable: no cache
        return _options_of(run)


def _options_of(run) -> tuple[str, ...] | None:
    params = inspect.signature(run).parameters
    if any(p.kind is p.VAR_KEYWORD for p in params.values()):
        return None
    return tuple(k for k, p in params.items() if p.kind is p.KEYWORD_ONLY and k not in COMMON)


_cached_options = functools.lru_cache(maxsize=64)(_options_of)


def _check_options(strategy, options) -> None:
    own = _own_options(strategy.run)
    if own is None:
        return
    for key in options:
        if key not in own:
            raise ValueError(f"{key}: not an option of the {strategy.name!r} strategy "
                             f"(its options: {', '.join(own) or 'none'}; fit's own: "
                             f"n_hypotheses, threshold, rng, hypotheses, prior, radius, "
                             f"refine, sampling, max_hypotheses, preset)")


def compare(space, data, *, methods=("randomized_hough", "ransac", "clap"),
            n_hypotheses: int = 1000, threshold: float | None = None, rng=None,
            options: dict | None = None, sampling: dict | None = None
            ) -> dict[str, ConsensusResult]:
    """Run several strategies through :func:`fit` on the *same* hypotheses, drawn once.

    Each strategy runs with its own defaults (``preset="own"``, no preset of
    :mod:`~clap_unified.presets`), on the space as given: the strategies differ
    only in how they reach consensus.

    Parameters
    ----------
    space : HypothesisSpace
    data : array_like
    methods : sequence of str
        Registered strategy names that apply to ``space``.
    n_hypotheses : int
    threshold : float, optional
        Same data-space inlier threshold for every strategy.
    rng : None, int or numpy.random.Generator
    options : dict, optional
        Per-method options, e.g. ``{"randomized_hough": {"cell_size": 0.1}}``.
    sampling : dict, optional
        Space-specific options of the one hypothesis generation.

    Returns
    -------
    dict
        Method name to :class:`~clap_unified.result.ConsensusResult`; each
        result's ``diagnostics["seconds"]`` is its own run time and
        ``diagnostics["generation_seconds"]`` the shared generation time.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> x = rng.uniform(-5, 5, 100)
    >>> pts = np.c_[x, 0.5 * x + rng.normal(0, 0.01, 100)]
    >>> pts[:50] = rng.uniform(-5, 5, (50, 2))
    >>> out = compare(LineSpace.for_data(pts), pts, threshold=0.05, rng=0,
    ...               options={"randomized_hough": {"cell_size": 0.1}})
    >>> {name: r.n_inliers >= 50 for name, r in out.items()}
    {'randomized_hough': True, 'ransac': True, 'clap': True}
    """
    if isinstance(methods, str):
        methods = (methods,)
    if not isinstance(space, HypothesisSpace):
        raise ValueError(f"space: expected a HypothesisSpace, got {type(space).__name__}")
    strategies = [get_strategy(m, space) for m in methods]
    n_hypotheses = check_int(n_hypotheses, "n_hypotheses", minimum=1)
    options = {} if options is None else dict(options)
    for key in options:
        if key not in methods:
            raise ValueError(f"options: {key!r} is not among methods {list(methods)}")
    data = space.check_data(data)
    t0 = time.perf_counter()
    hyps = (space.hypotheses(data, n_hypotheses, rng=as_generator(rng), **(sampling or {}))
            if any(s.uses_hypotheses for s in strategies) else None)
    gen = time.perf_counter() - t0
    out = {}
    for s in strategies:
        res = fit(space, Checked(data), s.name, n_hypotheses=n_hypotheses, threshold=threshold,
                  hypotheses=hyps if s.uses_hypotheses else None, rng=rng, preset="own",
                  **options.get(s.name, {}))
        out[s.name] = res.replace(diagnostics={"generation_seconds": gen})
    return out


def fit_line(points, method: str = "clap", *, n_hypotheses: int = 1000,
             threshold: float | None = None, rng=None, metric: str = "transfer",
             **options) -> ConsensusResult:
    """Fit one line to 2D points: :func:`fit` in ``LineSpace.for_data(points, metric)``.

    Parameters
    ----------
    points : ndarray of shape (N, 2)
    method : str
        ``"hough"``, ``"randomized_hough"``, ``"ransac"``, ``"clap"`` or any
        registered strategy for lines.
    n_hypotheses : int
    threshold : float, optional
        Inlier distance in data units; default 2 % of the data's RMS radius.
    rng : None, int or numpy.random.Generator
    metric : {"transfer", "chart"}
        How hypotheses are compared (:meth:`LineSpace.for_data`). The default
        ``"transfer"`` (lines compared where they cross the data region, in
        data units) lets CLAP query neighbours on a k-d tree, faster than
        ``"chart"``, the ``(theta, rho)`` distance of chapters 1 and 2, whose
        ``H x H`` matrix dominates CLAP's time (``bench/bench_lines.py``
        measures both).
    **options
        Passed to :func:`fit`.

    Examples
    --------
    >>> pts = np.c_[np.arange(5.0), np.arange(5.0)]
    >>> res = fit_line(pts, "ransac", rng=0)
    >>> [round(v, 4) for v in res.space.model_to_dict(res.model)["normal"]]
    [-0.7071, 0.7071]
    """
    check_choice(metric, "metric", {"chart", "transfer"})
    points = Checked(LineSpace().check_data(points))  # once, for the space and for fit
    space = LineSpace.for_data(points, metric=metric)
    return fit(space, points, method, n_hypotheses=n_hypotheses, threshold=threshold, rng=rng,
               **options)

