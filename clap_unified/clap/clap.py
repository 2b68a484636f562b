"""CLAP: Clustering to Localize Across n Possibilities.

Hypotheses are points in a space with a distance; the correct ones pile up
in a dense cluster and the wrong ones scatter. CLAP finds density centres in
hypothesis space instead of scoring each hypothesis against the data:

* **global mode**: seed at the hypothesis with the most neighbours within a
  bandwidth, take its neighbourhood, find a robust centre (trimming or MAD),
  suppress that region and repeat, so every cluster (each of the "n
  possibilities") is reported with its support and spread;
* **local mode**: keep only hypotheses within ``radius`` of an initial guess
  (the previous estimate) and find their robust centre.
"""

from __future__ import annotations

import time

import numpy as np

from .._validation import check_choice, check_int, check_positive
from ..refine import inliers_of, refit_on_inliers
from ..result import Cluster, ConsensusResult, runner_up_ratio
from ..spaces.base import HypothesisSet
from ..spaces.sampling import generate_hypotheses
from .centres import CENTRES, cluster_centre
from .density import auto_bandwidth, neighbour_counts
from .rejection import mad_centre, trimmed_centre, trimmed_medoid_index

__all__ = ["clap"]

#: Above this many hypotheses the pairwise distance matrix is not kept in memory.
DENSE_LIMIT = 4000


def _robust_centre(manifold, points, rejection, centre, rounds, discard_fraction, mad_k,
                   distances=None):
    if rejection == "trim":
        return trimmed_centre(manifold, points, rounds=rounds, discard_fraction=discard_fraction,
                              centre=centre, distances=distances)
    if rejection == "mad":
        return mad_centre(manifold, points, k=mad_k, centre=centre)
    return cluster_centre(manifold, points, centre), np.ones(len(points), bool)


def clap(space, data, *, hypotheses: HypothesisSet | None = None, n_hypotheses: int = 1000,
         mode: str = "global", initial_guess=None, radius: float | None = None,
         bandwidth: float | None = None, bandwidth_quantile: float = 0.1,
         centre: str = "medoid", rejection: str = "trim",
         rounds: int = 5, discard_fraction: float = 0.2, mad_k: float = 3.0,
         max_clusters: int = 5, min_support: int = 3, suppress: float = 3.0, refit: bool = True,
         residual_threshold: float | None = None, rng=None) -> ConsensusResult:
    """Robust estimate as the centre of the densest cluster of hypotheses.

    Parameters
    ----------
    space : HypothesisSpace
    data : array_like
        Data in the space's format.
    hypotheses : HypothesisSet, optional
        Cluster these; otherwise ``n_hypotheses`` are generated from ``data``.
    n_hypotheses : int
        Hypotheses to generate when none are given.
    mode : {"global", "local"}
        ``local`` needs ``initial_guess`` and ``radius``.
    initial_guess : ndarray, optional
        A model (e.g. the previous estimate) for local mode.
    radius : float, optional
        Local mode: hypotheses farther than this from ``initial_guess`` are ignored.
    bandwidth : float, optional
        Global mode: neighbourhood radius in hypothesis space. Default:
        :func:`~clap_unified.clap.density.auto_bandwidth`.
    bandwidth_quantile : float
        Quantile of the k-nearest-neighbour distances used as the automatic
        bandwidth; lower it when only a few percent of the hypotheses can be
        correct (homographies from 4-samples at 50 % outlier matches: 6 %).
    centre : {"medoid", "karcher", "log_euclidean", "split", "median"}
    rejection : {"trim", "mad", "none"}
        Robust centre: iterative trimming (``rounds`` x ``discard_fraction``,
        the paper uses 5 x 20 %), MAD rejection (``mad_k``), or none.
    max_clusters : int
        Global mode: clusters to report at most.
    min_support : int
        Clusters with fewer members are not reported.
    suppress : float
        Global mode: once a cluster is found, hypotheses within
        ``suppress * bandwidth`` of its seed or of its centre cannot seed
        another cluster (non-maximum suppression in hypothesis space).
    refit : bool
        Refit the best centre on its data inliers.
    residual_threshold : float, optional
        Data inlier threshold; default ``space.default_residual_threshold``.
    rng : None, int or numpy.random.Generator
        Used only to generate hypotheses.

    Returns
    -------
    ConsensusResult
        ``clusters`` lists every cluster found, best first; ``diagnostics``
        holds the bandwidth, the runner-up ratio (support of the second
        cluster over the first) and the spread.

    Examples
    --------
    >>> from clap_unified.spaces import LineSpace
    >>> rng = np.random.default_rng(0)
    >>> x = rng.uniform(-5, 5, 100)
    >>> pts = np.c_[x, 0.5 * x + 1 + rng.normal(0, 0.01, 100)]
    >>> pts[:70] = rng.uniform(-5, 5, (70, 2))   # 70 % outliers
    >>> res = clap(LineSpace.for_data(pts), pts, residual_threshold=0.05, rng=0)
    >>> normal, offset = res.space.model_to_dict(res.model).values()
    >>> print(f"slope {-normal[0] / normal[1]:.2f}, intercept {offset / normal[1]:.2f}")
    slope 0.50, intercept 1.00
    """
    t0 = time.perf_counter()
    data = space.check_data(data)
    check_choice(mode, "mode", {"global", "local"})
    check_choice(centre, "centre", set(CENTRES))
    check_choice(rejection, "rejection", {"trim", "mad", "none"})
    max_clusters = check_int(max_clusters, "max_clusters", minimum=1)
    suppress = check_positive(suppress, "suppress")
    min_support = check_int(min_support, "min_support", minimum=1)
    t = (space.default_residual_threshold(data) if residual_threshold is None
         else check_positive(residual_threshold, "residual_threshold"))
    manifold = space.manifold
    if mode == "local":
        if initial_guess is None or radius is None:
            raise ValueError("initial_guess: local mode needs initial_guess and radius")
        initial_guess = manifold.validate(initial_guess, "initial_guess")
        radius = check_positive(radius, "radius")
    if bandwidth is not None:
        bandwidth = check_positive(bandwidth, "bandwidth")
    if hypotheses is None:
        hypotheses = generate_hypotheses(space, data, n_hypotheses, rng=rng)
    models = hypotheses.models
    n, h = len(data), len(models)
    diag = {"hypotheses": h, "mode": mode, "residual_threshold": t}
    robust = dict(rejection=rejection, centre=centre, rounds=rounds,
                  discard_fraction=discard_fraction, mad_k=mad_k)

    def fail(reason):
        diag["seconds"] = time.perf_counter() - t0
        return ConsensusResult.failure("clap", reason, n, h, space, **diag)

    if h == 0:
        return fail("no hypotheses: every minimal sample was degenerate")

    clusters = []
    if mode == "local":
        full = None
        if centre == "medoid" and h < manifold.small_pairwise:
            # few candidates: one matrix holds the distances to the guess and among them
            full = manifold.pairwise_distance(np.concatenate([initial_guess[None], models]))
            d_guess = full[0, 1:]
        else:
            d_guess = manifold.distance(initial_guess, models)
        near = np.flatnonzero(d_guess <= radius)
        diag["in_radius"] = len(near)
        if len(near) < min_support:
            return fail(f"only {len(near)} hypotheses within radius {radius:g} of initial_guess "
                        f"(min_support={min_support})")
        if full is not None:
            sub = full.take(near + 1, axis=0).take(near + 1, axis=1)
        else:
            sub = manifold.pairwise_distance(models[near]) if centre == "medoid" else None
        if centre == "medoid" and rejection == "trim":  # all from the one matrix
            b, keep = trimmed_medoid_index(sub, rounds=rounds, discard_fraction=discard_fraction)
            clusters.append(Cluster(models[near[b]], len(near), _median(sub[b, keep]),
                                    near[keep]))
        else:
            c, keep = _robust_centre(manifold, models[near], distances=sub, **robust)
            clusters.append(_cluster(manifold, c, models, near[keep], support=len(near)))
    else:
        # One distance matrix when it fits in memory (~130 MB at 4000 hypotheses),
        # otherwise blocks recomputed on demand.
        dist = manifold.pairwise_distance(models) if h <= DENSE_LIMIT else None
        if bandwidth is None:
            bw = auto_bandwidth(manifold, models, quantile=bandwidth_quantile, distances=dist)
        else:
            bw = bandwidth
        diag["bandwidth"] = bw
        counts = (np.count_nonzero(dist <= bw, axis=1) if dist is not None
                  else neighbour_counts(manifold, models, bw))
        available = np.ones(h, bool)
        for seed in np.argsort(-counts, kind="stable"):
            if len(clusters) == max_clusters or counts[seed] < min_support:
                break
            if not available[seed]:
                continue
            d_seed = dist[seed] if dist is not None else manifold.distance(models[seed], models)
            near = np.flatnonzero(available & (d_seed <= bw))
            available &= d_seed > suppress * bw
            if len(near) < min_support:
                continue
            sub = dist[np.ix_(near, near)] if dist is not None else None
            if sub is not None and centre == "medoid" and rejection == "trim":
                b, keep = trimmed_medoid_index(sub, rounds=rounds,
                                               discard_fraction=discard_fraction)
                d_centre = dist[near[b]]  # the medoid is a hypothesis: its row is known
                c = models[near[b]]
                spread = _median(d_centre[near[keep]])
            else:
                c, keep = _robust_centre(manifold, models[near], distances=sub, **robust)
                d_centre = manifold.distance(c, models)
                spread = None
            # suppress around the centre too, so the rest of a wide cluster cannot
            # seed a second "possibility" that is the same answer
            available &= d_centre > suppress * bw
            clusters.append(_cluster(manifold, c, models, near[keep], support=len(near))
                            if spread is None else
                            Cluster(c, len(near), spread, near[keep]))
        if not clusters:
            return fail(f"no cluster with at least {min_support} hypotheses within bandwidth "
                        f"{bw:.3g}")
        clusters.sort(key=lambda cl: -cl.support)

    best = clusters[0]
    diag["clusters"] = len(clusters)
    diag["spread"] = best.spread
    diag["runner_up_ratio"] = runner_up_ratio(clusters)
    model = best.model
    if refit:
        model, inliers = refit_on_inliers(space, model, data, t)
    else:
        inliers = inliers_of(space, model, data, t)
    support = np.zeros(h, bool)
    support[best.members] = True
    diag["seconds"] = time.perf_counter() - t0
    return ConsensusResult("clap", True, "ok", model, inliers, support, float(best.support),
                           clusters, diag, space)


def _median(values) -> float:
    """``float(np.median(values))`` of a 1-D array, by one sort (few values, a hot path)."""
    v = np.sort(values)
    n = len(v)
    if n == 0 or np.isnan(v[-1]):
        return float(np.median(values))  # NaN (and NumPy's warning when empty)
    h = n // 2
    return float(v[h]) if n % 2 else float((v[h - 1] + v[h]) / 2)


def _cluster(manifold, c, models, members, support=None) -> Cluster:
    d = manifold.distance(c, models[members])
    spread = float(np.median(d)) if len(d) else 0.0
    return Cluster(c, int(len(members) if support is None else support), spread, members)
