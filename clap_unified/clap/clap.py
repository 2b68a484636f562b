"""CLAP: Clustering to Localize Across n Possibilities.

Hypotheses are points in a space with a distance; the correct ones pile up
in a dense cluster and the wrong ones scatter. CLAP finds density centres in
hypothesis space instead of scoring each hypothesis against the data:

* **global mode**: seed at the hypothesis with the most neighbours within a
  bandwidth, take its neighbourhood, find a robust centre (trimming or MAD),
  suppress that region and repeat, so every cluster (each of the "n
  possibilities") is reported with its support and spread;
* **local mode**: keep only hypotheses within ``radius`` of a prior (the
  previous estimate) and find their robust centre.

:func:`run_clap` is the strategy registered as ``"clap"``; :func:`clap` is
:func:`~clap_unified.fit` with that method.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from .._validation import check_choice, check_int, check_positive
from ..fitting import describe_radius, fit
from ..registry import Strategy, register_strategy
from ..result import Cluster, Consensus, ConsensusResult, runner_up_ratio
from ..spaces.base import HypothesisSet
from .centres import CENTRES, cluster_centre
from .density import (
    EmbeddedNeighbours,
    auto_bandwidth,
    dense_candidates,
    even_subset,
    knn_distance,
    neighbour_counts,
)
from .rejection import mad_centre, trimmed_centre, trimmed_medoid_index

__all__ = ["clap", "run_clap"]

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


def clap(space, data, **options) -> ConsensusResult:
    """CLAP: :func:`~clap_unified.fit` with ``method="clap"``.

    Parameters
    ----------
    space : HypothesisSpace
    data : array_like
    **options
        :func:`~clap_unified.fit`'s arguments (``n_hypotheses``, ``threshold``,
        ``rng``, ``hypotheses``, ``prior``, ``radius``, ``refine``) and CLAP's
        own, documented at :func:`run_clap`.

    Examples
    --------
    >>> from clap_unified.spaces import LineSpace
    >>> rng = np.random.default_rng(0)
    >>> x = rng.uniform(-5, 5, 100)
    >>> pts = np.c_[x, 0.5 * x + 1 + rng.normal(0, 0.01, 100)]
    >>> pts[:70] = rng.uniform(-5, 5, (70, 2))   # 70 % outliers
    >>> res = clap(LineSpace.for_data(pts), pts, threshold=0.05, rng=0)
    >>> normal, offset = res.space.model_to_dict(res.model).values()
    >>> print(f"slope {-normal[0] / normal[1]:.2f}, intercept {offset / normal[1]:.2f}")
    slope 0.50, intercept 1.00
    """
    return fit(space, data, "clap", **options)


def run_clap(space, data, hypotheses: HypothesisSet, *, threshold: float, prior=None,
             radius=None, rng=None, n_hypotheses: int = 0, bandwidth: float | None = None,
             bandwidth_quantile: float = 0.1, centre: str = "medoid", rejection: str = "trim",
             rounds: int = 5, discard_fraction: float = 0.2, mad_k: float = 3.0,
             max_clusters: int = 5, min_support: int = 3, suppress: float = 3.0,
             prune: bool = False, density: str = "count", k: int = 2, select: str = "support",
             n_refine: int = 3, neighbourhood: str = "bandwidth") -> Consensus:
    """The CLAP strategy: the centre of the densest cluster of hypotheses.

    Called by :func:`~clap_unified.fit`, which generates the hypotheses, gates
    them around a prior and refines the centre on its data inliers.

    Parameters
    ----------
    space : HypothesisSpace
    data : ndarray
        Checked data (read only with ``select="consensus"``: otherwise CLAP works
        in hypothesis space alone).
    hypotheses : HypothesisSet
    threshold : float
        The data-space inlier threshold (used by ``select="consensus"``;
        otherwise applied by :func:`~clap_unified.fit` only).
    rng, n_hypotheses
        Unused.
    prior : ndarray, optional
        Local mode: the hypotheses within ``radius`` of the prior
        (``space.near_prior``; CLAP applies the gate itself, computing the
        distances to the prior with those among the hypotheses) are one
        neighbourhood; their robust centre is the estimate.
        Without it, global mode: seed at the hypothesis with the most
        neighbours within ``bandwidth``, take its neighbourhood, find a robust
        centre, suppress that region and repeat.
    radius : float or what ``space.near_prior`` accepts, optional
        Local mode: the gate around the prior.
    bandwidth : float, optional
        Global mode: neighbourhood radius in hypothesis space. Default:
        :func:`~clap_unified.clap.density.auto_bandwidth`.
    bandwidth_quantile : float
        Quantile of the k-nearest-neighbour distances used as the automatic
        bandwidth; lower it when only a few percent of the hypotheses can be
        correct (homographies from 4-samples at 50 % outlier matches: at most
        ``0.5 ** 4``, about 6 %, of the samples are all inliers).
    centre : {"medoid", "karcher", "log_euclidean", "split", "median"}
        ``"split"`` needs a space whose capabilities include ``split_mean``.
    rejection : {"trim", "mad", "none"}
        Robust centre: iterative trimming (``rounds`` x ``discard_fraction``,
        the paper uses 5 x 20 %), MAD rejection (``mad_k``), or none.
    max_clusters : int
        Global mode: clusters to report at most.
    min_support : int
        Clusters with fewer members are not reported. When the hypotheses
        enumerate every minimal subset of the data (``hypotheses.exhaustive``)
        and there are fewer than ``min_support`` of them, all of them are
        asked instead (four matches give one homography: CLAP fits it).
    suppress : float
        Global mode: once a cluster is found, hypotheses within
        ``suppress * bandwidth`` of its seed or of its centre cannot seed
        another cluster (non-maximum suppression in hypothesis space).
    prune : bool
        Global mode, spaces with ``chordal_embedding``: first drop hypotheses
        with fewer than ``min_support`` others within ``2 * bandwidth``
        (:func:`~clap_unified.clap.density.dense_candidates`); they cannot join
        a cluster, and the pairwise matrix shrinks to the dense few.
    density : {"count", "knn"}
        Global mode: how seeds are ordered. ``"count"`` (the paper): by the
        number of hypotheses within ``bandwidth``. ``"knn"``: by the distance
        to the ``k``-th nearest other hypothesis, smallest first (a density
        estimate that needs no bandwidth and ranks even a tight pair of
        hypotheses when correct ones are rare); ``bandwidth`` then only sets
        the cluster around a seed and, with ``suppress``, the region it
        suppresses.
    k : int
        With ``density="knn"``: the neighbour whose distance ranks the seeds.
    select : {"support", "consensus"}
        Which cluster is the answer. ``"support"`` (the paper): the one with
        the most hypotheses. ``"consensus"``: the clusters' centres are scored
        against the data by their truncated squared residuals (MSAC:
        ``sum(min(r^2, threshold^2))``, lower is better); the ``n_refine``
        best are refined by ``space.refine`` (local optimisation on their
        inliers) and scored again; the clusters are reported in that order
        (``diagnostics["consensus_costs"]``). Density then proposes a few
        candidate answers and the data decide between them; a second,
        coherent motion in the data stays visible as a second cluster.
    n_refine : int
        With ``select="consensus"``: cluster centres refined before the final
        ranking.
    neighbourhood : {"bandwidth", "all"}
        Global mode: what the robust centre is found over. ``"bandwidth"``:
        the hypotheses within ``bandwidth`` of each seed (clusters by
        density, as above). ``"all"``: every hypothesis is one neighbourhood;
        the answer is the robust single centre of all of them (with
        ``rejection="trim"``: the medoid of all, then ``rounds`` rounds each
        discarding the ``discard_fraction`` farthest from the current
        centre), one cluster, no bandwidth, seeds or suppression (the
        options ``bandwidth``, ``bandwidth_quantile``, ``density``, ``k``,
        ``suppress``, ``max_clusters`` and ``prune`` then play no part).
        This is the paper's homography protocol read literally ("iterative
        clustering for 5 rounds, and discard 20 % of the outliers at each
        iteration" over the 400 candidates); it fails with fewer than
        ``min_support`` hypotheses. Ignored in local mode (the prior's gate
        is the neighbourhood).

    Returns
    -------
    Consensus
        ``clusters`` lists every cluster found, best first; ``diagnostics``
        holds the bandwidth, the runner-up ratio (support of the second
        cluster over the first) and the spread.
    """
    check_choice(centre, "centre", set(CENTRES))
    check_choice(rejection, "rejection", {"trim", "mad", "none"})
    check_choice(select, "select", {"support", "consensus"})
    check_choice(density, "density", {"count", "knn"})
    check_choice(neighbourhood, "neighbourhood", {"bandwidth", "all"})
    k = check_int(k, "k", minimum=1)
    n_refine = check_int(n_refine, "n_refine", minimum=0)
    max_clusters = check_int(max_clusters, "max_clusters", minimum=1)
    suppress = check_positive(suppress, "suppress")
    min_support = check_int(min_support, "min_support", minimum=1)
    caps = space.capabilities
    if centre == "split" and not caps.split_mean:
        raise ValueError(f"centre: 'split' needs a space with a split mean; the {space.name} "
                         "space has none")
    if prune and not caps.chordal_embedding:
        raise ValueError(f"prune: needs a space with a chordal embedding; the {space.name} "
                         "space has none")
    if bandwidth is not None:
        bandwidth = check_positive(bandwidth, "bandwidth")
    manifold = space.manifold
    models = hypotheses.models
    h = len(models)
    diag = {"mode": "global" if prior is None else "local"}
    exhaustive = bool(getattr(hypotheses, "exhaustive", False))
    if exhaustive and 0 < h < min_support:
        # every minimal subset of the data was enumerated and there are fewer than
        # min_support of them (4 matches: one homography): no cluster can have more
        # support than the data allow, so the support asked is what exists
        min_support = h
        diag["min_support"] = h
    robust = dict(rejection=rejection, centre=centre, rounds=rounds,
                  discard_fraction=discard_fraction, mad_k=mad_k)

    clusters = []
    if prior is not None:
        # the prior's gate is applied here (the strategy declares gates_prior): with few
        # hypotheses one matrix holds the distances to the prior and among them
        if centre == "medoid" and np.ndim(radius) == 0 and h < manifold.small_pairwise:
            full = manifold.pairwise_distance(np.concatenate([prior[None], models]))
            near = np.flatnonzero(full[0, 1:] <= radius)
            sub = full.take(near + 1, axis=0).take(near + 1, axis=1)
            support = len(near)
        else:
            near = np.flatnonzero(space.near_prior(prior, models, radius))
            support = len(near)
            near = even_subset(near, DENSE_LIMIT)  # a giant cluster: centred on a subset
            sub = manifold.pairwise_distance(models[near]) if centre == "medoid" else None
        diag["near_prior"] = support
        if support < min_support:
            return Consensus.failed(f"only {support} hypotheses within radius "
                                    f"{describe_radius(radius)} of the prior "
                                    f"(min_support={min_support})", **diag)
        local = models[near]
        if centre == "medoid" and rejection == "trim":  # all from the one matrix
            b, keep = trimmed_medoid_index(sub, rounds=rounds, discard_fraction=discard_fraction)
            clusters.append(Cluster(local[b], support, _median(sub[b, keep]), near[keep]))
        else:
            c, keep = _robust_centre(manifold, local, distances=sub, **robust)
            kept = np.flatnonzero(keep)
            clusters.append(_cluster(manifold, c, local, kept, support=support,
                                     members=near[kept]))
    elif neighbourhood == "all":
        diag["neighbourhood"] = "all"
        if h < min_support:
            return Consensus.failed(f"only {h} hypotheses (min_support={min_support})", **diag)
        near = even_subset(np.arange(h), DENSE_LIMIT)  # a giant set: centred on a subset
        if centre == "medoid" and rejection == "trim":  # all from the one matrix
            sub = manifold.pairwise_distance(models[near])
            b, keep = trimmed_medoid_index(sub, rounds=rounds, discard_fraction=discard_fraction)
            clusters.append(Cluster(models[near[b]], h, _median(sub[b, keep]), near[keep]))
        else:
            sub = manifold.pairwise_distance(models[near]) if centre == "medoid" else None
            c, keep = _robust_centre(manifold, models[near], distances=sub, **robust)
            kept = np.flatnonzero(keep)
            clusters.append(_cluster(manifold, c, models[near], kept, support=h,
                                     members=near[kept]))
    else:
        index = np.arange(h)
        if prune:
            if bandwidth is None:
                raise ValueError("bandwidth: prune needs a bandwidth")
            index = dense_candidates(manifold, models, 2 * bandwidth, min_support)
            diag["dense_candidates"] = len(index)
            if len(index) == 0:
                return Consensus.failed(f"no hypothesis has {min_support} others within "
                                        f"{2 * bandwidth:g}", **diag)
            models = models[index]
            h = len(models)
        # Neighbour queries: a k-d tree when the manifold's embedding distance is its
        # distance (no H x H matrix at any size); else one distance matrix when it fits in
        # memory (~130 MB at 4000 hypotheses); beyond, a k-d tree on an embedding that
        # bounds the distance (candidates checked with the distance), else blocks
        # recomputed on demand.
        tree = (EmbeddedNeighbours(manifold, models)
                if manifold.embedding_is_distance
                or (manifold.embedding_bounds_distance and h > DENSE_LIMIT) else None)
        dist = manifold.pairwise_distance(models) if tree is None and h <= DENSE_LIMIT else None
        if bandwidth is not None:
            bw = bandwidth
        elif tree is not None:
            bw = tree.auto_bandwidth(quantile=bandwidth_quantile)
        else:
            bw = auto_bandwidth(manifold, models, quantile=bandwidth_quantile, distances=dist)
        diag["bandwidth"] = bw
        if density == "knn":  # seeds by their k-th neighbour distance, any support
            if tree is not None:
                knn = np.full(h, np.inf)
                seeds = tree.budget_rows(k)  # all, unless H is very large
                knn[seeds] = tree.knn(k, seeds)
            else:
                knn = knn_distance(manifold, models, k, distances=dist)
            if exhaustive and h <= k:  # every subset enumerated, fewer than k others exist
                knn = np.zeros(h)
            order = np.argsort(knn, kind="stable")
            counts = np.where(np.isfinite(knn), min_support, 0)
        else:
            if tree is not None:  # neighbourhoods of ~1 % of H at the bandwidth
                counts = np.zeros(h, dtype=np.intp)
                seeds = tree.budget_rows(max(3, int(np.ceil(0.01 * h))))
                counts[seeds] = tree.counts(bw, seeds)
            elif dist is not None:
                counts = np.count_nonzero(dist <= bw, axis=1)
            else:
                counts = neighbour_counts(manifold, models, bw)
            order = np.argsort(-counts, kind="stable")
        available = np.ones(h, bool)
        for seed in order:
            if len(clusters) == max_clusters or counts[seed] < min_support:
                break
            if not available[seed]:
                continue
            if tree is not None:
                near = tree.ball(seed, bw)
                near = near[available[near]]
                available[tree.ball(seed, suppress * bw)] = False
                sub = tree.pairwise(near) if 0 < len(near) <= DENSE_LIMIT else None
            else:
                d_seed = (dist[seed] if dist is not None
                          else manifold.distance(models[seed], models))
                near = np.flatnonzero(available & (d_seed <= bw))
                available &= d_seed > suppress * bw
                sub = dist[np.ix_(near, near)] if dist is not None else None
            if len(near) < min_support:
                continue
            support = len(near)
            if support > DENSE_LIMIT:  # a giant cluster: centred on an even subset of it
                near = even_subset(near, DENSE_LIMIT)
                sub = tree.pairwise(near) if tree is not None else None
            if sub is not None and centre == "medoid" and rejection == "trim":
                b, keep = trimmed_medoid_index(sub, rounds=rounds,
                                               discard_fraction=discard_fraction)
                c = models[near[b]]  # the medoid is a hypothesis: its row is known
                spread = _median(sub[b, keep])
                d_centre = dist[near[b]] if dist is not None else None
                centre_index = near[b]
            else:
                c, keep = _robust_centre(manifold, models[near], distances=sub, **robust)
                d_centre = manifold.distance(c, models) if tree is None else None
                spread = centre_index = None
            # suppress around the centre too, so the rest of a wide cluster cannot
            # seed a second "possibility" that is the same answer
            if tree is not None:
                available[tree.ball(centre_index, suppress * bw) if centre_index is not None
                          else tree.ball_of(c, suppress * bw)] = False
            else:
                available &= d_centre > suppress * bw
            members = index[near[keep]]
            clusters.append(_cluster(manifold, c, models, near[keep], support=support,
                                     members=members)
                            if spread is None else
                            Cluster(c, support, spread, members))
        if not clusters:
            return Consensus.failed(f"no cluster with at least {min_support} hypotheses within "
                                    f"bandwidth {bw:.3g}", **diag)
        clusters.sort(key=lambda cl: -cl.support)

    if select == "consensus":
        clusters, costs = _by_consensus(space, data, clusters, threshold, n_refine,
                                        diag.get("bandwidth"))
        diag["consensus_costs"] = costs
    best = clusters[0]
    diag["clusters"] = len(clusters)
    diag["spread"] = best.spread
    diag["runner_up_ratio"] = runner_up_ratio(clusters)
    support = np.zeros(len(hypotheses), bool)
    support[best.members] = True
    return Consensus(best.model, tuple(clusters), support, float(best.support), "ok", diag)


register_strategy(Strategy(
    "clap", run_clap, gates_prior=True,
    summary="density centres of the hypotheses in their own space (the paper's method)"))


def _msac_cost(space, models, data, threshold) -> np.ndarray:
    """Truncated squared residuals ``sum(min(r^2, t^2))`` of each model (lower is better)."""
    r = space.residuals(models, data)
    return np.minimum(r * r, threshold * threshold).sum(axis=1)


def _by_consensus(space, data, clusters, threshold, n_refine, bandwidth=None):
    """Clusters ordered by the MSAC cost of their centres, the best few refined first.

    Refinement can carry several clusters to one answer; a cluster whose
    model ends within ``bandwidth`` of a better one's is merged into it
    (support and members added), so every reported cluster is a distinct
    answer.
    """
    cost = _msac_cost(space, np.stack([c.model for c in clusters]), data, threshold)
    clusters = list(clusters)
    for j in np.argsort(cost, kind="stable")[:n_refine]:
        model, _ = space.refine(clusters[j].model, data, threshold)
        refined = _msac_cost(space, model[None], data, threshold)[0]
        if refined < cost[j]:
            clusters[j] = dataclasses.replace(clusters[j], model=model)
            cost[j] = refined
    order = np.argsort(cost, kind="stable")
    # every distance between the (few) answers in one broadcast call of the manifold's
    # distance (not pairwise_distance, whose arithmetic may differ in the last bits and
    # decide a merge at exactly the bandwidth differently)
    if bandwidth is not None and len(clusters) > 1:
        M = np.stack([c.model for c in clusters])
        between = space.manifold.distance(M[:, None], M[None])
    else:
        between = None
    kept, kept_at, costs = [], [], []
    for j in order:
        c = clusters[j]
        if between is not None and kept:
            near = np.flatnonzero(between[j, kept_at] <= bandwidth)
            if len(near):
                k = int(near[0])
                kept[k] = dataclasses.replace(
                    kept[k], support=kept[k].support + c.support,
                    members=np.union1d(kept[k].members, c.members))
                continue
        kept.append(c)
        kept_at.append(j)
        costs.append(cost[j])
    return kept, np.array(costs)


def _median(values) -> float:
    """``float(np.median(values))`` of a 1-D array, by one sort (few values, a hot path)."""
    v = np.sort(values)
    n = len(v)
    if n == 0 or np.isnan(v[-1]):
        return float(np.median(values))  # NaN (and NumPy's warning when empty)
    h = n // 2
    return float(v[h]) if n % 2 else float((v[h - 1] + v[h]) / 2)


def _cluster(manifold, c, models, near, support=None, members=None) -> Cluster:
    """A cluster centred at ``c`` on ``models[near]`` (``members``: their indices)."""
    d = manifold.distance(c, models[near])
    spread = float(np.median(d)) if len(d) else 0.0
    return Cluster(c, int(len(near) if support is None else support), spread,
                   near if members is None else members)
