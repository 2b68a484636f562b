"""The worked example of ARCHITECTURE.md: a new hypothesis space in one file.

Circles ``(cx, cy, r)`` from 2D points. Three points make a circle (the
circumcircle); the residual is the distance to the circle; the refit is the
algebraic (Kasa) least-squares circle. The manifold is flat, R^3. Nothing else
in the library changes, and every registered strategy that applies to any
space runs on it through ``fit`` and ``compare``.
"""

from __future__ import annotations

import numpy as np
import pytest

from clap_unified import compare, fit, strategy_names
from clap_unified._validation import check_points
from clap_unified.geometry import Euclidean
from clap_unified.spaces import HypothesisSpace


class CircleSpace(HypothesisSpace):
    """Circles ``(cx, cy, r)`` fitted to points ``(N, 2)``."""

    min_samples = 3
    model_shape = (3,)
    name = "circle"

    def __init__(self):
        self._manifold = Euclidean(3)

    @property
    def manifold(self):
        return self._manifold

    def check_data(self, data):
        return check_points(data, "points", dim=2, min_count=self.min_samples)

    def solve_minimal(self, data, samples):
        a, b, c = (data[samples[:, k]] for k in range(3))
        d = 2 * (a[:, 0] * (b[:, 1] - c[:, 1]) + b[:, 0] * (c[:, 1] - a[:, 1])
                  + c[:, 0] * (a[:, 1] - b[:, 1]))
        ok = np.abs(d) > 1e-9  # collinear samples have no circle
        a, b, c, d = a[ok], b[ok], c[ok], d[ok]
        sa, sb, sc = (np.sum(p * p, axis=1) for p in (a, b, c))
        cx = (sa * (b[:, 1] - c[:, 1]) + sb * (c[:, 1] - a[:, 1]) + sc * (a[:, 1] - b[:, 1])) / d
        cy = (sa * (c[:, 0] - b[:, 0]) + sb * (a[:, 0] - c[:, 0]) + sc * (b[:, 0] - a[:, 0])) / d
        r = np.hypot(a[:, 0] - cx, a[:, 1] - cy)
        return np.c_[cx, cy, r], np.flatnonzero(ok)

    def residuals(self, models, data):
        m = np.asarray(models, dtype=float).reshape(-1, 3)
        dx = data[None, :, 0] - m[:, None, 0]
        dy = data[None, :, 1] - m[:, None, 1]
        return np.abs(np.hypot(dx, dy) - m[:, None, 2])

    def refit(self, data, weights=None, initial=None):
        if len(data) < 3:
            return None
        A = np.c_[2 * data, np.ones(len(data))]
        sol, *_ = np.linalg.lstsq(A, np.sum(data * data, axis=1), rcond=None)
        r2 = sol[2] + sol[0] ** 2 + sol[1] ** 2
        return None if not np.isfinite(r2) or r2 <= 0 else np.r_[sol[:2], np.sqrt(r2)]

    def default_threshold(self, data):
        return 0.05


def scene(seed=0, n=200, outliers=0.6):
    rng = np.random.default_rng(seed)
    t = rng.uniform(0, 2 * np.pi, n)
    pts = np.c_[2.0 + 3.0 * np.cos(t), -1.0 + 3.0 * np.sin(t)] + rng.normal(0, 0.01, (n, 2))
    k = int(outliers * n)
    pts[:k] = rng.uniform(-3, 7, (k, 2))
    return pts


def test_a_new_space_works_with_every_general_strategy():
    space = CircleSpace()
    names = strategy_names(space)
    assert {"clap", "ransac", "randomized_hough"} <= set(names) and "hough" not in names
    pts = scene()
    out = compare(space, pts, methods=("randomized_hough", "ransac", "clap"), n_hypotheses=800,
                  rng=0, options={"randomized_hough": {"cell_size": 0.1},
                                  "clap": {"bandwidth": 0.05}})
    for name, res in out.items():
        assert res.success, (name, res.reason)
        assert np.allclose(res.model, [2.0, -1.0, 3.0], atol=0.02), (name, res.model)
        assert res.n_inliers >= 75


def test_a_new_space_meets_the_contract():
    space, pts = CircleSpace(), scene(1)
    a, b = fit(space, pts, "clap", rng=3), fit(space, pts, "clap", rng=3)
    assert np.array_equal(a.model, b.model)
    collinear = np.c_[np.arange(10.0), np.arange(10.0)]
    assert not fit(space, collinear, "clap", rng=0)
    with pytest.raises(ValueError, match="points"):
        fit(space, np.full((10, 2), np.nan), "ransac")
