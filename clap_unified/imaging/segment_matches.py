"""Several planes or motions in one image pair: :func:`~clap_unified.segment` on matches.

:func:`segment_matches` builds the space of ``kind`` and calls
:func:`~clap_unified.segment` with the kind's segmentation preset
(:func:`segment_preset`, :mod:`clap_unified.presets`: the one home of the
multi-model defaults the command line, the benchmark and the book share;
:data:`SEGMENT_DEFAULTS` is its read-only view). :func:`evaluate_adelaidermf`
runs methods on the AdelaideRMF sequences and scores them by the
misclassification error (the labels reach only the score);
:func:`explain_errors` asks, sequence by sequence, whether a
method's error is its objective's or its search's, against the annotated
structures (an oracle: for the diagnosis, never for an estimator).
"""

from __future__ import annotations

import time

import numpy as np

from .._validation import Checked, check_choice
from ..presets import Settings, get_preset
from ..segmenting import segment
from ..spaces.fundamental import FundamentalSpace
from ..spaces.homography import HomographySpace

__all__ = ["SEGMENT_DEFAULTS", "SPACES", "evaluate_adelaidermf", "explain_errors", "trial_order",
           "segment_matches", "segment_preset"]

#: Space of each kind of match segmentation, built for the matches (hypotheses compared in
#: the normalised frame of the matches; residuals and models in pixels).
SPACES = {"homography": HomographySpace.for_data, "fundamental": FundamentalSpace.for_data}

def segment_preset(kind: str, method: str | None = None):
    """The defaults of :func:`segment_matches` for ``kind`` and ``method``: the
    segmentation preset (:func:`~clap_unified.presets.get_preset` with
    ``task="segment"``), their one home.

    Examples
    --------
    >>> p = segment_preset("homography", "clap")
    >>> p.fit["threshold"], p.fit["neighbours"], segment_preset("fundamental").fit["threshold"]
    (5.0, 20, 2.0)
    """
    kind = check_choice(kind, "kind", set(SPACES))
    return get_preset(kind, method, task="segment")


#: Defaults of :func:`segment_matches`, per kind: a read-only view of the segmentation
#: presets (:func:`segment_preset`; change a default there). The inlier threshold
#: (pixels, the space's residual), the hypotheses drawn and how (local samples: a match
#: and others among its ``neighbours`` nearest) and the spatial coherence of the common
#: finish (:mod:`clap_unified.coherence`). Chosen on AdelaideRMF by the benchmark
#: ``bench/bench_adelaidermf.py``.
SEGMENT_DEFAULTS = Settings({kind: Settings(segment_preset(kind).fit) for kind in SPACES})


def segment_matches(matches, kind: str = "homography", method: str = "clap", *,
                    threshold: float | None = None, rng=None, n_hypotheses: int | None = None,
                    neighbours: int | None = None, coherence: float | None = None,
                    **options):
    """The planes (or motions) in matches ``(x1, y1, x2, y2)``, and which match is on which.

    Parameters
    ----------
    matches : array_like of shape (N, 4)
    kind : {"homography", "fundamental"}
        The model of one structure: a plane (homography) or a rigid motion
        (fundamental matrix).
    method : str
        A segmenter (:func:`~clap_unified.registry.segmenter_names`).
    threshold, n_hypotheses, neighbours, coherence : optional
        Default the preset (:func:`segment_preset`); ``neighbours=0`` draws uniform
        samples, ``coherence=0`` gives each match to its nearest model.
    rng : None, int or numpy.random.Generator
    **options
        Passed to :func:`~clap_unified.segment` (``min_support``, the
        segmenter's own options).

    Returns
    -------
    SegmentationResult

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> src = rng.uniform(0, 640, (200, 2))
    >>> dst = np.where(np.arange(200)[:, None] < 100, src + 20.0, 1.1 * src)
    >>> res = segment_matches(np.c_[src, dst], rng=0)
    >>> res.n_models, sorted(res.support.tolist())
    (2, [100, 100])
    """
    kind = check_choice(kind, "kind", set(SPACES))
    defaults = segment_preset(kind, method).fit
    threshold = defaults["threshold"] if threshold is None else threshold
    n_hypotheses = defaults["n_hypotheses"] if n_hypotheses is None else n_hypotheses
    neighbours = defaults["neighbours"] if neighbours is None else neighbours
    coherence = defaults["coherence"] if coherence is None else coherence
    options.setdefault("coherence_neighbours", defaults["coherence_neighbours"])
    local = {"neighbours": int(neighbours)} if neighbours else None
    # checked once, for the space's frame and for segment
    matches = Checked(SPACES[kind].__self__().check_data(matches))
    space = SPACES[kind](matches)
    from ..registry import get_segmenter

    segmenter = get_segmenter(method, space)
    if segmenter.uses_hypotheses:
        options["sampling"] = local
    elif method == "ransac" and local:
        options.setdefault("neighbours", local["neighbours"])
    return segment(space, matches, method, threshold=threshold, rng=rng,
                   n_hypotheses=n_hypotheses, coherence=coherence, **options)


def trial_order(n: int, seed: int) -> np.ndarray:
    """The order of ``n`` matches in the trial ``seed`` of an AdelaideRMF evaluation.

    OpenCV's estimators (the MAGSAC++ loop) are deterministic for a given list of
    matches but depend on its order; a trial is one seed of the library's
    estimators *and* one order of the matches, so every method gets as many
    different runs as there are seeds. The truth labels are permuted alike.

    Examples
    --------
    >>> trial_order(5, 0).tolist() == trial_order(5, 0).tolist()
    True
    >>> sorted(trial_order(5, 1).tolist())
    [0, 1, 2, 3, 4]
    """
    return np.random.default_rng([int(seed), 0x5EED]).permutation(int(n))


def evaluate_adelaidermf(kind: str = "homography", methods=("clap",), *, thresholds=None,
                         seeds=(0,), names=None, options=None, progress: bool = False):
    """Each method on each AdelaideRMF sequence, scored by the misclassification error.

    Parameters
    ----------
    kind : {"homography", "fundamental"}
    methods : sequence of str
    thresholds : sequence of float, optional
        Default: the kind's default threshold only.
    seeds : sequence of int
        One trial per seed: the seed of the library's estimators and of the order of the
        matches (:func:`trial_order`), the same for every method.
    names : sequence of str, optional
        Sequences (default all present).
    options : dict, optional
        Per-method options of :func:`segment_matches`.
    progress : bool
        A progress bar (tqdm).

    Returns
    -------
    list of dict
        One row per sequence, method, threshold and seed: ``error`` (a
        fraction), ``models`` found, ``true_models``, ``seconds``.
    """
    from .datasets.adelaidermf import adelaidermf_names, load_adelaidermf
    from .segmentation_metrics import misclassification_error

    kind = check_choice(kind, "kind", set(SPACES))
    thresholds = ((segment_preset(kind).fit["threshold"],) if thresholds is None
                  else thresholds)
    names = adelaidermf_names(kind) if names is None else list(names)
    options = options or {}
    jobs = [(n, m, t, s) for n in names for m in methods for t in thresholds for s in seeds]
    if progress:
        from tqdm import tqdm

        jobs = tqdm(jobs, desc=f"AdelaideRMF {kind}", leave=False)
    rows, pairs = [], {}
    for name, method, t, seed in jobs:
        if name not in pairs:
            pairs = {name: load_adelaidermf(name, kind, images=False)}
        pair = pairs[name]
        order = trial_order(len(pair.truth.labels), seed)
        t0 = time.perf_counter()
        res = segment_matches(np.asarray(pair.input.matches)[order], kind, method,
                              threshold=t, rng=seed, **options.get(method, {}))
        seconds = time.perf_counter() - t0
        rows.append({"sequence": name, "method": method, "threshold": float(t),
                     "seed": int(seed), "error": misclassification_error(
                         res.labels, np.asarray(pair.truth.labels)[order]),
                     "models": res.n_models, "true_models": pair.truth.n_structures,
                     "seconds": seconds})
    return rows


def explain_errors(kind: str = "homography", *, threshold: float, seed: int = 0, names=None,
                   options=None) -> list[dict]:
    """Why the library's CLAP errs on each AdelaideRMF sequence: its objective or its search.

    For each sequence, the library's CLAP (:func:`segment_matches`, method
    ``"clap"``, with ``options``) and an **oracle**: the annotated structures,
    each refitted on its own annotated matches, then the same finish
    (:func:`~clap_unified.partition.finish_partition`: nearest model, refit,
    spatial coherence, the same minimum support). The oracle's error is the
    floor the finish leaves when the models are right. Both answers are
    scored by CLAP's own objective, the label-cost energy
    (:func:`~clap_unified.partition.label_cost_energy`): when CLAP's answer
    has the lower energy, the objective prefers it to the truth and no better
    search would repair it (``"objective"``); otherwise the search stopped
    short (``"search"``). The labels serve the oracle and the score only;
    CLAP never sees them.

    Parameters
    ----------
    kind : {"homography", "fundamental"}
    threshold : float
    seed : int
    names : sequence of str, optional
        Sequences (default all present).
    options : dict, optional
        Options of :func:`segment_matches` for CLAP (e.g. ``label_cost``,
        ``min_support``; the oracle's finish takes the same). Not
        ``select="cover"`` nor ``refine=False``: the verdict compares label-cost
        energies after the finish, which those answers do not minimise.

    Returns
    -------
    list of dict
        Per sequence: ``error`` and ``oracle_error`` (fractions), ``models``
        and ``true_models``, ``energy`` and ``oracle_energy`` (in units of
        ``threshold**2``), ``cause`` (``"objective"``, ``"search"``, or
        ``"floor"`` when CLAP is within a match of the oracle).
    """
    from ..clap.segment import DEFAULT_LABEL_COST, label_cost_of
    from ..partition import finish_partition, label_cost_energy
    from ..segmenting import default_min_support
    from .datasets.adelaidermf import adelaidermf_names, load_adelaidermf
    from .segmentation_metrics import misclassification_error

    kind = check_choice(kind, "kind", set(SPACES))
    options = dict(options or {})
    if options.get("select", "label_cost") != "label_cost":
        raise ValueError("options: select must be 'label_cost' (the verdict compares "
                         "label-cost energies)")
    if options.get("refine", True) is False:
        raise ValueError("options: refine=False leaves no finish to compare with the oracle's")
    names = adelaidermf_names(kind) if names is None else list(names)
    defaults = segment_preset(kind, "clap").fit
    coherence = options.get("coherence", defaults["coherence"])
    rows = []
    for name in names:
        pair = load_adelaidermf(name, kind, images=False)
        order = trial_order(len(pair.truth.labels), seed)  # the trial evaluate_adelaidermf ran
        matches = np.asarray(pair.input.matches)[order]
        truth = np.asarray(pair.truth.labels)[order]
        res = segment_matches(matches, kind, "clap", threshold=threshold, rng=seed, **options)
        space, data = res.space, np.asarray(matches, dtype=float)
        min_support = options.get("min_support") or default_min_support(space, len(data))
        structures = [k for k in range(1, truth.max() + 1) if np.count_nonzero(truth == k)]
        fitted = [space.refit(data[truth == k]) for k in structures]
        oracle = np.array([m for m in fitted if m is not None]).reshape(-1, *space.model_shape)
        oracle, oracle_labels, _ = finish_partition(
            space, oracle, data, threshold, min_support, coherence=coherence,
            coherence_neighbours=options.get("coherence_neighbours",
                                             defaults["coherence_neighbours"]))
        cost = label_cost_of(options.get("label_cost", DEFAULT_LABEL_COST), min_support,
                             threshold)
        energy = label_cost_energy(space, res.models, data, threshold, cost) / threshold ** 2
        floor = label_cost_energy(space, oracle, data, threshold, cost) / threshold ** 2
        error = misclassification_error(res.labels, truth)
        oracle_error = misclassification_error(oracle_labels, truth)
        cause = ("floor" if (error - oracle_error) * len(data) <= 1 else
                 "objective" if energy <= floor else "search")
        rows.append({"sequence": name, "error": error, "oracle_error": oracle_error,
                     "models": res.n_models, "true_models": len(structures),
                     "energy": energy, "oracle_energy": floor, "cause": cause})
    return rows


def summarise(rows) -> dict:
    """Per method and threshold: mean and median over sequences of the seed-mean error (%)."""
    out = {}
    keys = sorted({(r["method"], r["threshold"]) for r in rows})
    for key in keys:
        mine = [r for r in rows if (r["method"], r["threshold"]) == key]
        seqs = sorted({r["sequence"] for r in mine})
        per = np.array([np.mean([r["error"] for r in mine if r["sequence"] == s]) for s in seqs])
        out[key] = {"mean": 100 * float(per.mean()), "median": 100 * float(np.median(per)),
                    "models": float(np.mean([r["models"] for r in mine])),
                    "true_models": float(np.mean([r["true_models"] for r in mine])),
                    "seconds": float(np.median([r["seconds"] for r in mine])),
                    "per_sequence": dict(zip(seqs, (100 * per).tolist(), strict=True))}
    return out
