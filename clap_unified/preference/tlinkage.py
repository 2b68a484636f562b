"""T-Linkage (Magri and Fusiello, CVPR 2014): the data clustered by their preferences.

Each datum is described by its *preference* for every hypothesis,
``exp(-r / tau)`` where its residual ``r`` is below ``5 tau`` and 0 beyond
(J-Linkage's 0/1 consensus sets made continuous). Agglomerative clustering
merges the two clusters whose preference vectors are closest in the Tanimoto
distance, the merged cluster preferring only what both prefer (the
element-wise minimum), until every pair is at distance 1 (no hypothesis is
preferred by both). Clusters of at least ``min_support`` data are the
structures; the rest are outliers.

The dual of CLAP: CLAP clusters the hypotheses, preference analysis the data.
"""

from __future__ import annotations

import numpy as np

from .._validation import check_int, check_positive
from ..registry import Segmenter, register_segmenter
from ..result import Segmentation

__all__ = ["run_t_linkage", "t_linkage_clusters"]


def t_linkage_clusters(preferences) -> np.ndarray:
    """Agglomerative clustering of preference vectors under the Tanimoto distance.

    Parameters
    ----------
    preferences : ndarray of shape (N, H)
        Non-negative preference of each datum for each hypothesis.

    Returns
    -------
    ndarray of int, shape (N,)
        A cluster index per datum, ``0..C-1`` by first datum.

    Examples
    --------
    >>> P = np.array([[1, 1, 0, 0], [1, 0.9, 0, 0], [0, 0, 1, 1], [0, 0, 0.8, 1.0]])
    >>> t_linkage_clusters(P).tolist()
    [0, 0, 1, 1]
    """
    P = np.array(preferences, dtype=float)
    n = len(P)
    active = np.ones(n, bool)
    owner = np.arange(n)
    sq = np.einsum("ij,ij->i", P, P)
    gram = P @ P.T
    dist = _tanimoto(gram, sq[:, None], sq[None, :])
    np.fill_diagonal(dist, np.inf)
    nearest = np.argmin(dist, axis=1)
    best = dist[np.arange(n), nearest]
    while True:
        a = int(np.argmin(np.where(active, best, np.inf)))
        if not best[a] < 1.0:
            break
        b = int(nearest[a])
        P[a] = np.minimum(P[a], P[b])
        sq[a] = P[a] @ P[a]
        active[b] = False
        owner[owner == b] = a
        dist[b, :] = np.inf
        dist[:, b] = np.inf
        row = _tanimoto(P @ P[a], sq[a], sq)
        row[~active] = np.inf
        row[a] = np.inf
        dist[a, :] = row
        dist[:, a] = row
        stale = active & ((nearest == a) | (nearest == b))
        stale[a] = True
        for i in np.flatnonzero(stale):
            nearest[i] = int(np.argmin(dist[i]))
            best[i] = dist[i, nearest[i]]
        closer = active & (row < best)
        nearest[closer] = a
        best[closer] = row[closer]
        best[b] = np.inf
    _, labels = np.unique(owner, return_inverse=True)
    return labels.astype(np.intp)


#: Tanimoto distances are rounded to this many decimals before they are compared: the dot
#: products come from BLAS, whose last bits differ between CPU kernels, and an exact tie
#: (repeated data, equal preferences) must be broken by index on every machine, not by them.
DECIMALS = 9


def _tanimoto(dot, sq_a, sq_b):
    """``1 - <p, q> / (|p|^2 + |q|^2 - <p, q>)``; 1 when both are zero; rounded (DECIMALS)."""
    den = sq_a + sq_b - dot
    with np.errstate(invalid="ignore", divide="ignore"):
        d = np.where(den > 0, 1.0 - dot / np.where(den > 0, den, 1.0), 1.0)
    return np.round(d, DECIMALS)


def run_t_linkage(space, data, hypotheses, *, threshold: float, rng=None,
                  n_hypotheses: int = 0, min_support: int, tau: float | None = None,
                  max_models: int = 20) -> Segmentation:
    """T-Linkage as a segmenter: preference clusters of ``min_support`` data or more.

    Parameters
    ----------
    tau : float, optional
        Preference scale; default ``threshold / 5`` (a datum prefers the
        hypotheses within ``threshold``).
    max_models : int
        The largest clusters kept at most.

    Returns
    -------
    Segmentation
        Models refitted on each cluster (largest first), the clusters as
        labels; ``scores``: cluster sizes.
    """
    max_models = check_int(max_models, "max_models", minimum=1)
    tau = threshold / 5.0 if tau is None else check_positive(tau, "tau")
    empty = np.empty((0, *space.model_shape))
    if hypotheses is None or len(hypotheses) == 0:
        return Segmentation(empty, np.zeros(0),
                            reason="no hypotheses: every minimal sample was degenerate")
    r = space.residuals(hypotheses.models, data).T
    prefs = np.where(r < 5 * tau, np.exp(-r / tau), 0.0)
    clusters = t_linkage_clusters(prefs)
    sizes = np.bincount(clusters)
    order = [c for c in np.argsort(-sizes, kind="stable") if sizes[c] >= min_support]
    models, scores = [], []
    labels = np.full(len(data), -1, dtype=np.intp)
    for c in order[:max_models]:
        model = space.refit(data[clusters == c])
        if model is None or not np.all(np.isfinite(model)):
            continue
        labels[clusters == c] = len(models)
        models.append(model)
        scores.append(float(sizes[c]))
    return Segmentation(np.array(models).reshape(-1, *space.model_shape), np.array(scores),
                        labels, selection=f"preference clusters of at least {min_support} data "
                                          f"({len(sizes)} clusters)",
                        diagnostics={"preference_clusters": int(len(sizes))})


register_segmenter(Segmenter(
    "t_linkage", run_t_linkage,
    summary="T-Linkage: the data clustered by the hypotheses they prefer"))
