"""Spatial coherence: neighbouring data prefer the same model (a Potts labelling by graph cuts).

A structure in real data is a region: the matches on one plane of a building
are neighbours of each other. Nearest-model labelling ignores this, and a
model that happens to pass near a few matches of another plane takes them.
The labelling here minimises

.. math::

    E(L) = \\sum_i D_i(L_i) + w \\sum_{(i, j) \\in G} [L_i \\neq L_j]

over labels ``L_i`` in ``{0, ..., K-1}`` (the models) and ``K`` (outlier),
where ``D_i(k) = (r_ik / t)^2`` within the threshold ``t`` (a datum cannot
join a model beyond it), ``D_i(outlier) = 1`` and ``G`` is the graph of each
datum's nearest neighbours: the energy of PEARL (Isack and Boykov, IJCV 2012)
and Progressive-X (Barath and Matas, ICCV 2019) without the label cost, which
the segmenters' own model selection carries. It is minimised by
alpha-expansion (Boykov, Veksler and Zabih, PAMI 2001): each move is one
minimum cut, computed by PyMaxflow (the Boykov-Kolmogorov max-flow library).
"""

from __future__ import annotations

import numpy as np

from ._validation import check_int, check_positive

__all__ = ["BEYOND_THRESHOLD", "TIE_TOLERANCE", "coherent_labels", "expand_labels",
           "nearest_labels", "neighbour_graph", "potts_energy"]

#: Cost of giving a datum to a model whose residual is beyond the threshold
#: (in units of an outlier's cost): high enough that no neighbour pulls it there.
BEYOND_THRESHOLD = 1e3

#: Residuals within this fraction of the threshold of a datum's smallest are a tie, which
#: goes to the first model. A datum of two models' minimal samples has a residual of
#: rounding size (1e-13) on both; which of the two is smaller is the last bit of a float
#: and differs between BLAS builds, so it must not decide the label.
TIE_TOLERANCE = 1e-9


def nearest_labels(residuals, threshold: float) -> np.ndarray:
    """Each datum's nearest model, if nearer than ``threshold``; ties to the first model.

    The labelling without coherence, and the start of :func:`coherent_labels`.

    Parameters
    ----------
    residuals : array_like of shape (K, N)
        Residual of each datum under each model.
    threshold : float

    Returns
    -------
    ndarray of int, shape (N,)
        Index of the model, ``-1`` for a datum no model explains. Residuals
        within ``TIE_TOLERANCE * threshold`` of a datum's smallest are a tie and
        go to the first of them; a non-finite residual explains nothing.

    Examples
    --------
    The second datum lies on both models to the last bit of a float: a tie.

    >>> r = np.array([[0.1, 1e-13, 0.9], [0.3, 2e-13, 0.7]])
    >>> nearest_labels(r, 0.5).tolist()
    [0, 0, -1]
    """
    r = np.asarray(residuals, dtype=float)
    n = r.shape[1]
    if r.shape[0] == 0:
        return np.full(n, -1, dtype=np.intp)
    r = np.where(np.isfinite(r), r, np.inf)
    best = np.argmax(r <= r.min(axis=0) + TIE_TOLERANCE * threshold, axis=0).astype(np.intp)
    best[~(r[best, np.arange(n)] < threshold)] = -1
    return best


def neighbour_graph(points, k: int) -> np.ndarray:
    """The undirected edges between each point and its ``k`` nearest others.

    Parameters
    ----------
    points : array_like of shape (N, d)
        Where the data are (for matches: the four coordinates ``x1, y1, x2, y2``).
    k : int
        Neighbours per point (fewer when there are fewer points).

    Returns
    -------
    ndarray of int, shape (E, 2)
        Each edge once, ``i < j``, sorted; repeated points are neighbours too.

    Examples
    --------
    >>> neighbour_graph([[0.0], [1.0], [3.0], [10.0]], 1).tolist()
    [[0, 1], [1, 2], [2, 3]]
    """
    from scipy.spatial import cKDTree

    points = np.asarray(points, dtype=float)
    points = points.reshape(len(points), -1)
    k = check_int(k, "k", minimum=1)
    n = len(points)
    k = min(k, n - 1)
    if k < 1:
        return np.zeros((0, 2), dtype=np.intp)
    _, idx = cKDTree(points).query(points, k + 1)
    # The query lists a point first unless a duplicate ties with it: drop self-pairs.
    i = np.repeat(np.arange(n), k + 1)
    j = idx.ravel()
    edges = np.sort(np.c_[i, j], axis=1)
    edges = edges[edges[:, 0] != edges[:, 1]]
    return np.unique(edges, axis=0).astype(np.intp)


def potts_energy(costs, edges, weight: float, labels) -> float:
    """``sum_i costs[labels_i, i] + weight * #{(i, j) in edges: labels_i != labels_j}``."""
    costs = np.asarray(costs)
    labels = np.asarray(labels)
    data = costs[labels, np.arange(costs.shape[1])].sum()
    return float(data + weight * np.count_nonzero(labels[edges[:, 0]] != labels[edges[:, 1]]))


def expand_labels(costs, edges, weight: float, labels, *, sweeps: int = 5) -> np.ndarray:
    """Alpha-expansion of a Potts energy from ``labels``: each move a minimum cut (PyMaxflow).

    Parameters
    ----------
    costs : ndarray of shape (L, N)
        ``costs[l, i]``: the cost of giving datum ``i`` label ``l`` (non-negative).
    edges : ndarray of int, shape (E, 2)
        The neighbour graph (:func:`neighbour_graph`).
    weight : float
        The cost of one edge whose ends have different labels.
    labels : array_like of int, shape (N,)
        The start (e.g. each datum's cheapest label).
    sweeps : int
        Passes over the labels; stops earlier when a pass changes nothing.

    Returns
    -------
    ndarray of int, shape (N,)
        Labels whose energy (:func:`potts_energy`) is at most the start's.

    Examples
    --------
    A chain of five data; the middle one slightly prefers label 1 on its own:

    >>> costs = np.array([[0, 0, 0.6, 0, 0], [1, 1, 0.4, 1, 1]], float)
    >>> edges = np.array([[0, 1], [1, 2], [2, 3], [3, 4]])
    >>> expand_labels(costs, edges, 0.5, costs.argmin(axis=0)).tolist()
    [0, 0, 0, 0, 0]
    """
    import maxflow

    costs = np.asarray(costs, dtype=float)
    n_labels, n = costs.shape
    labels = np.array(labels, dtype=np.intp, copy=True)
    edges = np.asarray(edges, dtype=np.intp).reshape(-1, 2)
    ei, ej = edges[:, 0], edges[:, 1]
    energy = potts_energy(costs, edges, weight, labels)
    for _ in range(check_int(sweeps, "sweeps", minimum=1)):
        changed = False
        for alpha in range(n_labels):
            keep = costs[labels, np.arange(n)]          # x_i = 0: keep the label
            move = costs[alpha].copy()                  # x_i = 1: take alpha
            # An edge's term E(x_i, x_j) with E00 = w[l_i != l_j], E01 = w[l_i != alpha],
            # E10 = w[alpha != l_j], E11 = 0 is E00 + (E10 - E00) x_i - E10 x_j
            # + (E01 + E10 - E00) (1 - x_i) x_j; the last factor is >= 0 for a Potts term.
            e00 = weight * (labels[ei] != labels[ej])
            e01 = weight * (labels[ei] != alpha)
            e10 = weight * (labels[ej] != alpha)
            np.add.at(move, ei, e10 - e00)
            np.add.at(move, ej, -e10)
            low = np.minimum(keep, move)
            graph = maxflow.Graph[float](n, len(ei))
            nodes = graph.add_nodes(n)
            graph.add_grid_tedges(nodes, move - low, keep - low)
            graph.add_edges(ei, ej, e01 + e10 - e00, np.zeros(len(ei)))
            graph.maxflow()
            proposal = np.where(graph.get_grid_segments(nodes), alpha, labels)
            new_energy = potts_energy(costs, edges, weight, proposal)
            if new_energy < energy - 1e-9 * max(1.0, abs(energy)):
                labels, energy, changed = proposal, new_energy, True
        if not changed:
            break
    return labels


def coherent_labels(space, models, data, threshold: float, edges, weight: float,
                    labels=None) -> np.ndarray:
    """Each datum's model (``-1``: outlier) under the Potts energy of the module.

    Parameters
    ----------
    space : HypothesisSpace
    models : ndarray of shape (K,) + model_shape
    data : ndarray
        Checked data of ``space``.
    threshold : float
    edges : ndarray of int, shape (E, 2)
        The neighbour graph of the data (:func:`neighbour_graph`).
    weight : float
        The cost of a pair of neighbours on different models, in units of an
        outlier's cost (0: each datum to its nearest model).
    labels : array_like of int, optional
        The start (default: each datum's nearest model within the threshold,
        :func:`nearest_labels`, whose tie rule it shares).

    Returns
    -------
    ndarray of int, shape (N,)

    Examples
    --------
    Two lines, the lower densely sampled; the last point, of the lower line, lies
    slightly nearer to the upper one; its neighbours bring it back:

    >>> from clap_unified.spaces import LineSpace
    >>> x0, x1 = np.arange(0, 10, 0.5), np.arange(0, 10, 3.0)
    >>> pts = np.r_[np.c_[x0, 0 * x0], np.c_[x1, 0 * x1 + 2.0], [[4.0, 1.05]]]
    >>> lines = np.array([[np.pi / 2, 0.0], [np.pi / 2, 2.0]])   # y = 0 and y = 2
    >>> edges = neighbour_graph(pts, 2)
    >>> int(coherent_labels(LineSpace(), lines, pts, 1.2, edges, 0.0)[-1])
    1
    >>> int(coherent_labels(LineSpace(), lines, pts, 1.2, edges, 0.5)[-1])
    0
    """
    models = np.asarray(models)
    n = len(data)
    k = len(models)
    if k == 0:
        return np.full(n, -1, dtype=np.intp)
    weight = check_positive(weight, "weight", allow_zero=True)
    r = space.residuals(models, data) / float(threshold)
    costs = np.vstack([np.where(r < 1.0, r * r, BEYOND_THRESHOLD), np.ones((1, n))])
    if labels is None:
        start = nearest_labels(r, 1.0)
        start = np.where(start < 0, k, start)
    else:
        start = np.asarray(labels, dtype=np.intp)
        start = np.where(start < 0, k, start)
    out = start if weight == 0 else expand_labels(costs, edges, weight, start)
    return np.where(out == k, -1, out).astype(np.intp)
