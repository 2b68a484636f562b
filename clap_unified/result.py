"""The result types shared by every strategy, frozen once built.

* one model: a strategy returns a :class:`Consensus`, :func:`~clap_unified.fit`
  builds the :class:`ConsensusResult`;
* several models: a segmenter returns a :class:`Segmentation`,
  :func:`~clap_unified.segment` builds the :class:`SegmentationResult`.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from .datatypes import ReadOnlyDict

__all__ = ["Cluster", "Consensus", "ConsensusResult", "Segmentation", "SegmentationResult",
           "runner_up_ratio"]


@dataclass(frozen=True)
class Cluster:
    """One dense group of hypotheses: one of the "n possibilities".

    Attributes
    ----------
    model : ndarray
        The cluster's centre, a point of hypothesis space (a cell's mean, a
        robust centre, RANSAC's winning hypothesis). The result's model is
        the best cluster's centre after refinement on its data inliers.
    support : int
        Hypotheses behind the cluster: votes in a Hough cell, for CLAP the
        hypotheses in the neighbourhood the centre was computed from (within
        the bandwidth of the seed, or within the radius of the prior in local
        mode; before trimming), data inliers for RANSAC.
    spread : float
        Median distance of the members to the centre, in the manifold's
        distance (0 for a single member).
    members : ndarray of int
        Indices of the hypotheses the centre rests on (after trimming).
    """

    model: np.ndarray
    support: int
    spread: float
    members: np.ndarray = field(default_factory=lambda: np.empty(0, dtype=np.intp))

    def __post_init__(self):
        object.__setattr__(self, "model", _locked(self.model))
        object.__setattr__(self, "members", _locked(self.members))

    def __reduce__(self):  # unpickling runs __post_init__: the copy is frozen too
        return (Cluster, (self.model, self.support, self.spread, self.members))


def _locked(value):
    """A read-only view of an array built for a result (no copy); other values as they are."""
    if isinstance(value, np.ndarray):
        value = value.view()
        value.flags.writeable = False
    return value


def runner_up_ratio(clusters) -> float:
    """Support of the second cluster over the first (0 when there is one): near 1 = ambiguous."""
    if len(clusters) < 2 or clusters[0].support == 0:
        return 0.0
    return clusters[1].support / clusters[0].support


@dataclass(frozen=True)
class Consensus:
    """What a strategy hands back to :func:`~clap_unified.fit`, before refinement.

    A strategy finds where the consensus is; :func:`~clap_unified.fit` then
    refines that model on its data inliers and builds the
    :class:`ConsensusResult`, so every strategy's result is finished the same
    way.

    Attributes
    ----------
    model : ndarray or None
        The consensus model; ``None`` when the strategy failed (``reason``
        says why).
    clusters : tuple of Cluster
        Every cluster or peak found, best first (the best one's centre is
        ``model``).
    support : ndarray of bool, shape (H,)
        Hypotheses behind the model (cluster members, a cell's voters, the
        winning hypothesis); empty for strategies that use no hypotheses.
    score : float
        The strategy's own score of the consensus (cluster support, votes,
        inlier count or MSAC score).
    reason : str
        ``"ok"`` or why there is no model.
    diagnostics : dict
        Strategy-specific counts (bandwidth, occupied cells, trials...).
    """

    model: np.ndarray | None
    clusters: tuple = ()
    support: np.ndarray = field(default_factory=lambda: np.zeros(0, bool))
    score: float = 0.0
    reason: str = "ok"
    diagnostics: dict = field(default_factory=dict)

    @classmethod
    def failed(cls, reason: str, **diagnostics) -> Consensus:
        """No consensus, with the reason."""
        return cls(None, reason=reason, diagnostics=diagnostics)


@dataclass(frozen=True)
class ConsensusResult:
    """What :func:`~clap_unified.fit` returns, for every strategy and space.

    A failed estimate is a value, not an exception: ``success`` is False,
    ``reason`` says why, and ``model`` is None. The result tests false then.
    Results are frozen: arrays are read-only and ``diagnostics`` is a
    read-only mapping; :func:`dataclasses.replace` makes a changed copy.

    Every field describes the returned model: ``inliers`` are the data within
    ``threshold`` of ``model``; ``model`` is ``clusters[0].model`` refined on
    its inliers (equal to it with ``refine=False``); ``score`` is the
    strategy's score of it (for RANSAC, scored again after refinement; for
    CLAP and Hough, the support of the cluster it was refined from).

    Attributes
    ----------
    method : str
        The registered strategy name (``"clap"``, ``"ransac"``,
        ``"randomized_hough"``, ``"hough"``, ...).
    success : bool
    reason : str
        Why it failed, or ``"ok"``.
    model : ndarray or None
        The estimate.
    inliers : ndarray of bool, shape (N,)
        Data within ``threshold`` of ``model``.
    support : ndarray of bool, shape (H,)
        Hypotheses that support the estimate (cluster members, the cell's
        voters, or the winning hypothesis for RANSAC).
    score : float
        The strategy's own score of the estimate.
    clusters : tuple of Cluster
        Every cluster or peak found, best first.
    diagnostics : mapping
        Counts, spreads, runner-up ratio, timings (``"seconds"``,
        ``"generation_seconds"``).
    space : HypothesisSpace
        The space the model belongs to.
    threshold : float or None
        The inlier threshold, in data units.
    """

    method: str
    success: bool
    reason: str
    model: np.ndarray | None
    inliers: np.ndarray
    support: np.ndarray
    score: float
    clusters: tuple = ()
    diagnostics: ReadOnlyDict = field(default_factory=ReadOnlyDict)
    space: object = field(default=None, repr=False)
    threshold: float | None = None

    def __post_init__(self):
        for name in ("model", "inliers", "support"):
            object.__setattr__(self, name, _locked(getattr(self, name)))
        object.__setattr__(self, "clusters", tuple(self.clusters))
        object.__setattr__(self, "diagnostics", ReadOnlyDict(self.diagnostics))

    def __reduce__(self):  # unpickling runs __post_init__: the copy is frozen too
        return (ConsensusResult, tuple(getattr(self, f.name) for f in dataclasses.fields(self)))

    def __bool__(self) -> bool:
        return bool(self.success)

    @property
    def n_inliers(self) -> int:
        return int(np.count_nonzero(self.inliers))

    @classmethod
    def failure(cls, method: str, reason: str, n_data: int = 0, n_hypotheses: int = 0,
                space=None, threshold: float | None = None, **diagnostics) -> ConsensusResult:
        """A failed result with a reason."""
        return cls(method, False, reason, None, np.zeros(n_data, bool),
                   np.zeros(n_hypotheses, bool), 0.0, (), diagnostics, space, threshold)

    def replace(self, **changes) -> ConsensusResult:
        """A copy with some fields changed (``diagnostics`` entries are merged in)."""
        if "diagnostics" in changes:
            changes["diagnostics"] = {**self.diagnostics, **changes["diagnostics"]}
        return dataclasses.replace(self, **changes)

    def to_dict(self) -> dict:
        """The one JSON form of a result, used by every command of the CLI.

        Keys: ``method``, ``success``, ``reason``, ``model`` (described by the
        space, e.g. ``{"normal", "offset"}`` for a line, ``{"x", "y",
        "theta"}`` for a planar pose), ``inliers`` (count), ``data`` (count),
        ``threshold``, ``score``, ``clusters`` (each with its model, support
        and spread) and ``seconds``.

        Examples
        --------
        >>> from clap_unified import fit, LineSpace
        >>> pts = np.c_[np.arange(5.0), np.arange(5.0)]
        >>> d = fit(LineSpace(), pts, "ransac", threshold=0.1, rng=0).to_dict()
        >>> sorted(d)  # doctest: +NORMALIZE_WHITESPACE
        ['clusters', 'data', 'inliers', 'method', 'model', 'reason', 'score', 'seconds',
         'success', 'threshold']
        """
        def describe(model):
            return (self.space.model_to_dict(model) if self.space is not None
                    else np.asarray(model).tolist())

        return {
            "method": self.method,
            "success": bool(self.success),
            "reason": self.reason,
            "model": None if self.model is None else describe(self.model),
            "inliers": self.n_inliers,
            "data": int(len(self.inliers)),
            "threshold": None if self.threshold is None else float(self.threshold),
            "score": float(self.score),
            "clusters": [{"model": describe(c.model), "support": int(c.support),
                          "spread": float(c.spread)} for c in self.clusters],
            "seconds": round(float(self.diagnostics.get("seconds", 0.0)), 6),
        }

    def __repr__(self) -> str:
        if not self.success:
            return f"ConsensusResult(method={self.method!r}, success=False, reason={self.reason!r})"
        return (f"ConsensusResult(method={self.method!r}, success=True, "
                f"inliers={self.n_inliers}/{len(self.inliers)}, score={self.score:.4g}, "
                f"clusters={len(self.clusters)})")


@dataclass(frozen=True)
class Segmentation:
    """What a multi-model strategy hands back to :func:`~clap_unified.segment`.

    Attributes
    ----------
    models : ndarray of shape (K,) + model_shape
        The structures found, in the strategy's order of preference (best
        first); ``K`` may be 0.
    scores : ndarray of shape (K,)
        The strategy's own score of each (cluster support, votes, inliers).
    labels : ndarray of int, shape (N,), optional
        The strategy's own assignment of the data (``-1``: outlier); ``None``
        lets :func:`~clap_unified.segment` assign each datum to its nearest
        model within the threshold.
    reason : str
        ``"ok"``, or why there is no model.
    selection : str
        How the number of models was chosen, in words.
    diagnostics : dict
    """

    models: np.ndarray
    scores: np.ndarray
    labels: np.ndarray | None = None
    reason: str = "ok"
    selection: str = ""
    diagnostics: dict = field(default_factory=dict)


@dataclass(frozen=True)
class SegmentationResult:
    """What :func:`~clap_unified.segment` returns: several models and the data they explain.

    Frozen like :class:`ConsensusResult`. Finding no structure is an answer,
    not an exception: ``models`` is empty, every label is ``-1``, ``success``
    is False and ``reason`` says why.

    Attributes
    ----------
    method : str
        The registered segmenter name.
    success : bool
        At least one model was found.
    reason : str
    models : ndarray of shape (K,) + model_shape
    labels : ndarray of int, shape (N,)
        The model each datum belongs to, ``-1`` for an outlier.
    scores : ndarray of shape (K,)
        The strategy's score of each model.
    selection : str
        How the number of models was chosen.
    diagnostics : mapping
        Counts and timings (``"seconds"``, ``"generation_seconds"``).
    space : HypothesisSpace
    threshold : float or None
    """

    method: str
    success: bool
    reason: str
    models: np.ndarray
    labels: np.ndarray
    scores: np.ndarray
    selection: str = ""
    diagnostics: ReadOnlyDict = field(default_factory=ReadOnlyDict)
    space: object = field(default=None, repr=False)
    threshold: float | None = None

    def __post_init__(self):
        for name in ("models", "labels", "scores"):
            object.__setattr__(self, name, _locked(getattr(self, name)))
        object.__setattr__(self, "diagnostics", ReadOnlyDict(self.diagnostics))

    def __reduce__(self):  # unpickling runs __post_init__: the copy is frozen too
        return (SegmentationResult,
                tuple(getattr(self, f.name) for f in dataclasses.fields(self)))

    def __bool__(self) -> bool:
        return bool(self.success)

    @property
    def n_models(self) -> int:
        return int(len(self.models))

    @property
    def support(self) -> np.ndarray:
        """Data per model, shape (K,)."""
        return np.bincount(self.labels[self.labels >= 0], minlength=self.n_models)[:self.n_models]

    def inliers(self, k: int) -> np.ndarray:
        """Boolean mask of the data labelled ``k``."""
        if not 0 <= int(k) < self.n_models:
            raise ValueError(f"k: expected a model index in [0, {self.n_models}), got {k}")
        return self.labels == int(k)

    def replace(self, **changes) -> SegmentationResult:
        """A copy with some fields changed (``diagnostics`` entries are merged in)."""
        if "diagnostics" in changes:
            changes["diagnostics"] = {**self.diagnostics, **changes["diagnostics"]}
        return dataclasses.replace(self, **changes)

    def to_dict(self) -> dict:
        """The common JSON form, as ``clap-unified segment`` prints it.

        Keys: ``method``, ``success``, ``reason``, ``models`` (each described
        by the space, with its ``support`` and ``score``), ``labels`` (one
        integer per datum, ``-1`` for an outlier), ``selection``, ``data``,
        ``threshold`` and ``seconds``.
        """
        def describe(model):
            return (self.space.model_to_dict(model) if self.space is not None
                    else np.asarray(model).tolist())

        support = self.support
        return {
            "method": self.method,
            "success": bool(self.success),
            "reason": self.reason,
            "models": [{"model": describe(m), "support": int(s), "score": float(c)}
                       for m, s, c in zip(self.models, support, self.scores, strict=True)],
            "labels": [int(v) for v in self.labels],
            "selection": self.selection,
            "data": int(len(self.labels)),
            "threshold": None if self.threshold is None else float(self.threshold),
            "seconds": round(float(self.diagnostics.get("seconds", 0.0)), 6),
        }

    def __repr__(self) -> str:
        if not self.success:
            return (f"SegmentationResult(method={self.method!r}, success=False, "
                    f"reason={self.reason!r})")
        return (f"SegmentationResult(method={self.method!r}, models={self.n_models}, "
                f"support={self.support.tolist()}, outliers={int(np.sum(self.labels < 0))})")
