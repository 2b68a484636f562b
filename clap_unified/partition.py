"""Several models sharing one data set: assign, select and refit, on a space's protocol.

The multi-model counterpart of :mod:`clap_unified.refine`, shared by every
multi-model strategy and by :func:`~clap_unified.segment`:

* :func:`assign_labels`: each datum to its nearest model within the
  threshold (``-1``: an outlier);
* :func:`select_models`: candidate models taken in order while each explains
  enough data that the ones already taken do not (the number of models);
* :func:`select_by_label_cost`: the subset of candidates that minimises the
  truncated squared residuals of the data plus a cost per model (the number
  of models, by model selection);
* :func:`refit_partition`: assign, refit each model on its own data, drop the
  models left with too little, until the labels stop changing;
* :func:`finish_partition`: that finish as :func:`~clap_unified.segment` runs
  it, with the neighbour graph of spatial coherence built from the data;
* :func:`label_cost_energy`: the energy :func:`select_by_label_cost` minimises,
  of any set of models (to ask whether an answer is the objective's or the
  search's).
"""

from __future__ import annotations

import numpy as np

from .coherence import coherent_labels, nearest_labels, neighbour_graph

__all__ = ["assign_labels", "finish_partition", "label_cost_energy", "refine_hypotheses",
           "refit_partition", "select_by_label_cost", "select_models"]

def assign_labels(space, models, data, threshold: float) -> np.ndarray:
    """Label of each datum: the model with the smallest residual, if below ``threshold``.

    Parameters
    ----------
    space : HypothesisSpace
    models : ndarray of shape (K,) + model_shape
    data : ndarray
        Checked data of ``space``.
    threshold : float

    Returns
    -------
    ndarray of int, shape (N,)
        Index into ``models``, ``-1`` for a datum no model explains (or whose
        residuals are not finite). Ties, residuals within
        ``TIE_TOLERANCE * threshold`` of the smallest, go to the first model.

    Examples
    --------
    >>> from clap_unified.spaces import LineSpace
    >>> lines = np.array([[np.pi / 2, 0.0], [np.pi / 2, 5.0]])   # (theta, rho): y = 0, y = 5
    >>> pts = np.array([[0.0, 0.1], [1.0, 4.9], [2.0, 2.5]])
    >>> assign_labels(LineSpace(), lines, pts, 0.5).tolist()
    [0, 1, -1]
    """
    models = np.asarray(models)
    if len(models) == 0:
        return np.full(len(data), -1, dtype=np.intp)
    return nearest_labels(space.residuals(models, data), threshold)


def select_models(space, candidates, data, threshold: float, min_support: int,
                  max_models: int | None = None) -> np.ndarray:
    """Indices of the candidates kept: in order, each must explain ``min_support`` new data.

    A candidate is kept when at least ``min_support`` of its inliers are not
    inliers of a candidate kept before it: the greedy cover that decides how
    many models there are (a bridging model whose data the others already
    explain adds nothing and is dropped).

    Parameters
    ----------
    space : HypothesisSpace
    candidates : ndarray of shape (C,) + model_shape
        Best first.
    data : ndarray
    threshold : float
    min_support : int
        New data a model must explain to be kept.
    max_models : int, optional

    Returns
    -------
    ndarray of int
        Indices into ``candidates``, in order.
    """
    if len(candidates) == 0:
        return np.zeros(0, dtype=np.intp)
    inl = space.residuals(np.asarray(candidates), data) < threshold
    covered = np.zeros(len(data), bool)
    kept = []
    for i in range(len(inl)):
        if np.count_nonzero(inl[i] & ~covered) >= min_support:
            kept.append(i)
            covered |= inl[i]
            if max_models is not None and len(kept) >= max_models:
                break
    return np.asarray(kept, dtype=np.intp)


def select_by_label_cost(space, candidates, data, threshold: float, label_cost: float,
                         max_models: int | None = None) -> np.ndarray:
    """Indices of the candidates whose set minimises residual cost plus a cost per model.

    The energy of a set ``S`` of models is ``sum_i min(min_{k in S} r_ik^2,
    t^2) + label_cost * |S|``: each datum pays its truncated squared residual
    to the nearest model (an outlier pays ``t^2``), each model pays
    ``label_cost`` (the label cost of PEARL, Isack and Boykov, IJCV 2012).
    Greedy forward selection adds the candidate that lowers the energy most
    while it lowers it by more than ``label_cost``; backward elimination then
    removes any model whose removal lowers the energy. Two models that split
    two planes beat one that bridges them when the residuals they save pay
    for the second label; a model whose data another already explains does
    not pay for its own.

    Parameters
    ----------
    space : HypothesisSpace
    candidates : ndarray of shape (C,) + model_shape
    data : ndarray
    threshold : float
        ``t``: residuals beyond it cost ``t^2`` (outliers).
    label_cost : float
        The cost of one more model, in squared data units (``m * t^2`` asks a
        model to explain about ``m`` data well).
    max_models : int, optional

    Returns
    -------
    ndarray of int
        Indices into ``candidates``, in the order they were added.

    Examples
    --------
    >>> from clap_unified.spaces import LineSpace
    >>> x = np.linspace(-5, 5, 20)
    >>> pts = np.r_[np.c_[x, 0 * x], np.c_[x, 0 * x + 3]]      # y = 0 and y = 3
    >>> cands = np.array([[np.pi / 2, 1.5], [np.pi / 2, 0.0], [np.pi / 2, 3.0]])
    >>> select_by_label_cost(LineSpace(), cands, pts, 0.1, 5 * 0.1 ** 2).tolist()
    [1, 2]
    """
    if len(candidates) == 0:
        return np.zeros(0, dtype=np.intp)
    t2 = float(threshold) ** 2
    r = space.residuals(np.asarray(candidates), data)
    cost = np.minimum(r * r, t2)
    n_max = len(cost) if max_models is None else int(max_models)
    current = np.full(cost.shape[1], t2)
    chosen: list[int] = []
    while len(chosen) < n_max:
        gain = np.maximum(current[None] - cost, 0.0).sum(axis=1)
        gain[chosen] = -np.inf
        k = int(np.argmax(gain))
        if not gain[k] > label_cost:
            break
        chosen.append(k)
        current = np.minimum(current, cost[k])
    while len(chosen) > 1:  # backward: drop a model whose data the others explain
        total = _data_cost(cost[chosen], t2)
        for k in chosen:
            rest = [j for j in chosen if j != k]
            if _data_cost(cost[rest], t2) - total < label_cost:
                chosen = rest
                break
        else:
            break
    return np.asarray(chosen, dtype=np.intp)


def label_cost_energy(space, models, data, threshold: float, label_cost: float) -> float:
    """``sum_i min(min_k r_ik^2, t^2) + label_cost * K``: the energy of a set of ``K`` models.

    The objective of :func:`select_by_label_cost`, for any models (found by
    a method, or the true structures refitted on their data): when a wrong
    answer has a lower energy than the truth, the objective prefers it and no
    search can repair it; when it has a higher one, the search stopped short.

    Parameters
    ----------
    space : HypothesisSpace
    models : ndarray of shape (K,) + model_shape
    data : ndarray
    threshold : float
    label_cost : float
        In squared data units, as :func:`select_by_label_cost` takes it.

    Returns
    -------
    float

    Examples
    --------
    >>> from clap_unified.spaces import LineSpace
    >>> pts = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 1.0]])
    >>> label_cost_energy(LineSpace(), np.array([[np.pi / 2, 0.0]]), pts, 0.5, 0.1)
    0.35
    """
    models = np.asarray(models, dtype=float)
    t2 = float(threshold) ** 2
    if len(models) == 0:
        return t2 * len(data)
    r = space.residuals(models.reshape((-1, *space.model_shape)), data)
    return float(_data_cost(r * r, t2) + label_cost * len(models))


def _data_cost(squared, t2: float) -> float:
    """``sum_i min(min_k squared[k, i], t2)``: what the data pay a set of models.

    Each datum pays its squared residual to the nearest model, truncated at
    ``t2``: the first term of :func:`label_cost_energy`, and what
    :func:`select_by_label_cost` compares when it removes a model.
    """
    return np.minimum(squared.min(axis=0), t2).sum()


def refine_hypotheses(space, models, data, threshold: float, *, rounds: int = 1) -> np.ndarray:
    """Each hypothesis refitted on its own inliers, ``rounds`` times (a degenerate refit keeps it).

    Hypotheses from minimal samples of one structure scatter with the noise
    of their few data; refitted on everything they explain, they gather
    where the structure is (and several converge to the same model).

    Returns
    -------
    ndarray of shape (H,) + model_shape
    """
    models = np.array(models, dtype=float, copy=True)
    for _ in range(rounds):
        inl = space.residuals(models, data) < threshold
        for i in np.flatnonzero(inl.sum(axis=1) >= 2 * space.min_samples):
            new = space.refit(data[inl[i]], initial=models[i])
            if new is not None and np.all(np.isfinite(new)):
                models[i] = new
    return models


def refit_partition(space, models, data, threshold: float, min_support: int, *,
                    rounds: int = 5, coherence: float = 0.0, edges=None):
    """Assign and refit every model on its own data until the labels are stable.

    Each round assigns every datum to its nearest model within the
    threshold (:func:`assign_labels`), drops the models left with fewer than
    ``min_support`` data (the smallest first, then assigns again), and refits
    each model on its data (``space.refit``; a degenerate refit keeps the
    model). Stops when the labels no longer change, or after ``rounds``.

    With ``coherence > 0``, a second pass starts from that partition and
    labels by :func:`~clap_unified.coherence.coherent_labels` instead (a graph
    cut that also asks neighbours, ``edges``, to share a model), refitting and
    dropping the same way (PEARL's alternation of labelling and refitting,
    without its label cost).

    Parameters
    ----------
    space, models, data, threshold, min_support
    rounds : int
    coherence : float
        Cost of two neighbours on different models, in units of an outlier's cost.
    edges : ndarray of int, shape (E, 2), optional
        The data's neighbour graph (:func:`~clap_unified.coherence.neighbour_graph`);
        required when ``coherence > 0``.

    Returns
    -------
    models : ndarray of shape (K',) + model_shape
    labels : ndarray of int, shape (N,)
    kept : ndarray of int
        Indices into the given ``models`` of the models returned.
    """
    if coherence and edges is None:
        raise ValueError("edges: the neighbour graph is required when coherence > 0")

    def nearest(models, labels=None):
        return assign_labels(space, models, data, threshold)

    def coherent(models, labels=None):
        if len(models) == 0:
            return np.full(len(data), -1, dtype=np.intp)
        if labels is None or labels.max(initial=-1) >= len(models):
            labels = assign_labels(space, models, data, threshold)
        return coherent_labels(space, models, data, threshold, edges, coherence, labels)

    models, labels, kept = _refit_loop(space, models, data, min_support, rounds, nearest)
    if coherence and len(models):
        models, labels, again = _refit_loop(space, models, data, min_support, rounds, coherent,
                                            labels)
        kept = kept[again]
    return models, labels, kept


def finish_partition(space, models, data, threshold: float, min_support: int, *,
                     coherence: float = 0.0, coherence_neighbours: int = 8):
    """:func:`refit_partition` with the data's neighbour graph: the finish of every segmenter.

    Parameters
    ----------
    space, models, data, threshold, min_support, coherence
        As :func:`refit_partition`.
    coherence_neighbours : int
        Each datum's neighbours in the graph
        (:func:`~clap_unified.coherence.neighbour_graph`), when ``coherence > 0``.

    Returns
    -------
    models, labels, kept
        As :func:`refit_partition`.
    """
    edges = neighbour_graph(data, coherence_neighbours) if coherence else None
    return refit_partition(space, models, data, threshold, min_support, coherence=coherence,
                           edges=edges)


def _refit_loop(space, models, data, min_support, rounds, label, labels=None):
    """Label, drop the weak, refit each model on its data; until the labels are stable."""
    models = np.array(models, dtype=float, copy=True)
    kept = np.arange(len(models))
    labels = label(models, labels)
    for _ in range(rounds):
        models, labels, kept = _drop_weak(models, labels, kept, min_support, label)
        for k in range(len(models)):
            own = labels == k
            if np.count_nonzero(own) >= space.min_samples:
                new = space.refit(data[own], initial=models[k])
                if new is not None and np.all(np.isfinite(new)):
                    models[k] = new
        new_labels = label(models, labels)
        if np.array_equal(new_labels, labels):
            break
        labels = new_labels
    return _drop_weak(models, labels, kept, min_support, label)


def _drop_weak(models, labels, kept, min_support, label):
    """Drop the models with fewer than ``min_support`` data, the weakest first."""
    while len(models):
        support = np.bincount(labels[labels >= 0], minlength=len(models))
        weakest = int(np.argmin(support))
        if support[weakest] >= min_support:
            break
        models = np.delete(models, weakest, axis=0)
        kept = np.delete(kept, weakest)
        labels = label(models, np.where(labels > weakest, labels - 1,
                                        np.where(labels == weakest, -1, labels)))
    return models, labels, kept
