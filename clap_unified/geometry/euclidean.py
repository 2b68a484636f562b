"""Euclidean space R^d as a manifold: the flat case every chart reduces to.

Points are vectors; ``log(p, base) = p - base``, ``exp(v, base) = base + v``
and the distance is the (weighted) Euclidean norm. It is where the paper's
*input space* lives (raw observations, e.g. detections in the robot frame,
grouped before any model is fitted) and where parameter vectors without
further structure (circle centres and radii) are compared.

Examples
--------
>>> E = Euclidean(2)
>>> float(E.distance(np.array([0.0, 0.0]), np.array([3.0, 4.0])))
5.0
>>> E.mean(np.array([[0.0, 0.0], [2.0, 0.0], [1.0, 3.0]])).tolist()
[1.0, 1.0]
"""

from __future__ import annotations

import numpy as np

from .._validation import check_int
from .base import Manifold

__all__ = ["Euclidean"]


class Euclidean(Manifold):
    """R^d with the weighted Euclidean distance ``||w * (b - a)||``.

    Parameters
    ----------
    dim : int
        Dimension ``d``.
    tangent_weights : array_like of shape (d,), optional
        Per-coordinate weights of the distance (units per coordinate).
    """

    is_metric = True
    small_pairwise = 256
    name = "R^d"

    def __init__(self, dim: int, tangent_weights=None):
        self.dim = check_int(dim, "dim", minimum=1)
        self.point_shape = (self.dim,)
        super().__init__(tangent_weights)

    def __repr__(self) -> str:
        return f"Euclidean({self.dim})"

    def log(self, point, base_point) -> np.ndarray:
        return np.asarray(point, dtype=float) - np.asarray(base_point, dtype=float)

    def exp(self, tangent, base_point) -> np.ndarray:
        return np.asarray(base_point, dtype=float) + np.asarray(tangent, dtype=float)

    def reference_point(self) -> np.ndarray:
        return np.zeros(self.dim)
