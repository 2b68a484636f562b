"""The worked example of ARCHITECTURE.md: a new hypothesis space in one file.

:class:`clap_unified.spaces.circles.CircleSpace`: circles ``(cx, cy, r)`` from
2D points, in about fifty lines. Nothing else in the library knows about it,
and every registered strategy that applies to any space runs on it through
``fit`` and ``compare``.
"""

from __future__ import annotations

import numpy as np
import pytest

from clap_unified import compare, fit, strategy_names
from clap_unified.spaces import CircleSpace


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


def test_weighted_refit_and_model_description():
    t = np.linspace(0, 2 * np.pi, 30, endpoint=False)
    pts = np.c_[1 + 2 * np.cos(t), 2 * np.sin(t)]
    space = CircleSpace()
    np.testing.assert_allclose(space.refit(pts), [1.0, 0.0, 2.0], atol=1e-12)
    np.testing.assert_allclose(space.refit(pts, weights=np.linspace(0.1, 1, 30)),
                               [1.0, 0.0, 2.0], atol=1e-12)
    assert space.refit(pts[:2]) is None
    assert space.model_to_dict([1.0, 0.0, 2.0]) == {"centre": [1.0, 0.0], "radius": 2.0}
    # residuals are distances to the circle, in data units
    assert np.allclose(space.residuals([[1.0, 0.0, 2.0]], np.array([[1.0, 0.0], [4.0, 0.0]])),
                       [[2.0, 1.0]])
