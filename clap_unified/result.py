"""The result type shared by the three consensus strategies."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["Cluster", "ConsensusResult", "runner_up_ratio"]


@dataclass
class Cluster:
    """One dense group of hypotheses: one of the "n possibilities".

    Attributes
    ----------
    model : ndarray
        The cluster centre (a model of the hypothesis space).
    support : int
        Hypotheses behind the cluster: votes in a Hough cell, for CLAP the
        hypotheses in the neighbourhood the centre was computed from (within
        the bandwidth of the seed, or within the radius of the guess in local
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

    def to_dict(self, space=None) -> dict:
        model = (space.model_to_dict(self.model) if space is not None
                 else np.asarray(self.model).tolist())
        return {"model": model, "support": int(self.support), "spread": float(self.spread)}


def runner_up_ratio(clusters) -> float:
    """Support of the second cluster over the first (0 when there is one): near 1 = ambiguous."""
    if len(clusters) < 2 or clusters[0].support == 0:
        return 0.0
    return clusters[1].support / clusters[0].support


@dataclass
class ConsensusResult:
    """What every strategy returns.

    A failed estimate is a value, not an exception: ``success`` is False,
    ``reason`` says why, and ``model`` is None. The result tests false then.

    Attributes
    ----------
    method : str
        ``"hough"``, ``"randomized_hough"``, ``"ransac"`` or ``"clap"``.
    success : bool
    reason : str
        Why it failed, or ``"ok"``.
    model : ndarray or None
        The estimate.
    inliers : ndarray of bool, shape (N,)
        Data within the residual threshold of ``model``.
    support : ndarray of bool, shape (H,)
        Hypotheses that support the estimate (cluster members, the cell's
        voters, or the winning hypothesis for RANSAC).
    score : float
        The strategy's own score of the estimate (inlier count, MSAC score,
        votes, cluster support).
    clusters : list of Cluster
        Every cluster or peak found, best first.
    diagnostics : dict
        Counts, iterations, spreads, runner-up ratio, timings.
    space : HypothesisSpace
        The space the model belongs to.
    """

    method: str
    success: bool
    reason: str
    model: np.ndarray | None
    inliers: np.ndarray
    support: np.ndarray
    score: float
    clusters: list = field(default_factory=list)
    diagnostics: dict = field(default_factory=dict)
    space: object = field(default=None, repr=False)

    def __bool__(self) -> bool:
        return bool(self.success)

    @property
    def n_inliers(self) -> int:
        return int(np.count_nonzero(self.inliers))

    @classmethod
    def failure(cls, method: str, reason: str, n_data: int = 0, n_hypotheses: int = 0,
                space=None, **diagnostics) -> ConsensusResult:
        """A failed result with a reason."""
        return cls(method, False, reason, None, np.zeros(n_data, bool),
                   np.zeros(n_hypotheses, bool), 0.0, [], dict(diagnostics), space)

    def to_dict(self) -> dict:
        """JSON-friendly summary (model described by its space)."""
        model = None
        if self.model is not None:
            model = (self.space.model_to_dict(self.model) if self.space is not None
                     else np.asarray(self.model).tolist())
        return {
            "method": self.method,
            "success": bool(self.success),
            "reason": self.reason,
            "model": model,
            "inliers": self.n_inliers,
            "score": float(self.score),
            "clusters": [c.to_dict(self.space) for c in self.clusters],
        }

    def __repr__(self) -> str:
        if not self.success:
            return f"ConsensusResult(method={self.method!r}, success=False, reason={self.reason!r})"
        return (f"ConsensusResult(method={self.method!r}, success=True, "
                f"inliers={self.n_inliers}/{len(self.inliers)}, score={self.score:.4g}, "
                f"clusters={len(self.clusters)})")
