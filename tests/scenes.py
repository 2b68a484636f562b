"""Synthetic line scenes shared by the tests."""

import numpy as np


def line_scene(n=200, outlier_ratio=0.5, theta=0.3, intercept=1.0, noise=0.02, seed=0,
               extent=5.0):
    """Points on y = tan(theta) x + intercept plus uniform outliers; returns (points, is_inlier)."""
    rng = np.random.default_rng(seed)
    x = rng.uniform(-extent, extent, n)
    pts = np.c_[x, np.tan(theta) * x + intercept + rng.normal(0, noise, n)]
    k = int(round(outlier_ratio * n))
    pts[:k] = rng.uniform(-extent - 1, extent + 1, (k, 2))
    inlier = np.ones(n, bool)
    inlier[:k] = False
    return pts, inlier


def line_errors(space, model, theta=0.3, intercept=1.0):
    """Angle error (degrees) and offset error of a fitted line against the truth."""
    d = space.model_to_dict(model)
    a, b = d["normal"]
    c = d["offset"]
    true_normal = np.array([-np.sin(theta), np.cos(theta)])
    true_offset = intercept * np.cos(theta)
    s = np.sign(np.dot([a, b], true_normal)) or 1.0
    cosang = np.clip(abs(np.dot([a, b], true_normal)), 0, 1)
    return np.degrees(np.arccos(cosang)), abs(s * c - true_offset)
