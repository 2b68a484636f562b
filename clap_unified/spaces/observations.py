"""The input space: raw observations clustered before any model is fitted.

The paper names three spaces to cluster in: parameter space (lines,
homographies), state space (poses) and *input space*. In input space each
observation is its own hypothesis: a minimal sample is one observation and its
"model" is where that observation says something is. Observations of the same
thing (one landmark seen in several frames, or by several cameras) pile up in
a dense cluster; spurious ones stay alone. CLAP's global mode then reports
every cluster (each landmark) with its support, and the cluster centres are
cleaner observations for whatever is fitted next.

Observations carry a type (the landmark class): rows ``(type_id, x_1, ...,
x_d)``. Observations of different types never share a cluster: the type
coordinate has a weight that puts them :data:`TYPE_SEPARATION` apart.

Examples
--------
>>> from clap_unified import fit
>>> rng = np.random.default_rng(0)
>>> seen = np.r_[np.c_[np.zeros(6), 2 + rng.normal(0, 0.03, (6, 2))],    # type 0 at (2, 2)
...              np.c_[np.ones(5), [4.0, -1.0] + rng.normal(0, 0.03, (5, 2))],  # type 1
...              [[0.0, -3.0, 5.0]]]                                   # a lone false one
>>> res = fit(ObservationSpace(2), seen, "clap", threshold=0.2, bandwidth=0.2, min_support=3,
...           max_clusters=10, centre="karcher")
>>> [(int(c.model[0]), c.support) for c in res.clusters]
[(0, 6), (1, 5)]
"""

from __future__ import annotations

import numpy as np

from .._validation import check_int, check_points
from ..geometry.euclidean import Euclidean
from .base import HypothesisSpace

__all__ = ["TYPE_SEPARATION", "ObservationSpace"]

#: Distance between observations of different types (in data units per type step).
TYPE_SEPARATION = 1e6


class ObservationSpace(HypothesisSpace):
    """Typed observations ``(type_id, x_1, ..., x_d)`` as their own hypotheses.

    Parameters
    ----------
    dim : int
        Dimension of an observation's position (2 for detections on the
        ground plane, 3 in space).

    Notes
    -----
    ``min_samples`` is 1: every observation is a hypothesis, so
    ``hypotheses`` enumerates them all (in order: hypothesis ``i`` is
    observation ``i``). The residual of a datum to a model is its Euclidean
    distance (infinite across types); the refit is the mean of the inliers.
    """

    min_samples = 1
    name = "observations"

    def __init__(self, dim: int = 2):
        self.dim = check_int(dim, "dim", minimum=1)
        self.model_shape = (self.dim + 1,)
        self._manifold = Euclidean(self.dim + 1,
                                   tangent_weights=np.r_[TYPE_SEPARATION, np.ones(self.dim)])

    def __repr__(self) -> str:
        return f"ObservationSpace(dim={self.dim})"

    @property
    def manifold(self) -> Euclidean:
        return self._manifold

    def check_data(self, data) -> np.ndarray:
        obs = check_points(data, "observations", dim=self.dim + 1, min_count=1)
        ids = obs[:, 0]
        if np.any((ids != np.round(ids)) | (ids < 0)):
            raise ValueError("observations: column 0 must be a non-negative integer type id")
        return obs

    def solve_minimal(self, data, samples):
        samples = np.asarray(samples)
        return np.asarray(data, dtype=float)[samples[:, 0]], np.arange(len(samples))

    def residuals(self, models, data) -> np.ndarray:
        m = np.asarray(models, dtype=float).reshape(-1, self.dim + 1)
        d = np.asarray(data, dtype=float)
        diff = d[None, :, 1:] - m[:, None, 1:]
        r = np.sqrt(np.sum(diff * diff, axis=-1))
        return np.where(d[None, :, 0] == m[:, None, 0], r, np.inf)

    def refit(self, data, weights=None, initial=None):
        d = np.asarray(data, dtype=float)
        if len(d) == 0 or np.any(d[:, 0] != d[0, 0]):
            return None
        w = np.ones(len(d)) if weights is None else np.asarray(weights, dtype=float)
        if w.sum() <= 0:
            return None
        return np.r_[d[0, 0], (w @ d[:, 1:]) / w.sum()]

    def model_to_dict(self, model) -> dict:
        m = np.asarray(model, dtype=float)
        return {"type_id": int(m[0]), "position": m[1:].tolist()}

    def default_cell_size(self, data):
        raise ValueError("cell_size: the observations space has no default; pass the cell edge "
                         "in data units")

    def default_threshold(self, data) -> float:
        raise ValueError("threshold: the observations space has no default; pass the distance "
                         "within which two observations are of the same thing")
