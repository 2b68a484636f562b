"""Synthetic line scenes shared by the tests.

Scenes come split like every data set of the package: ``scene.input.points``
is all an estimator gets, ``scene.truth`` (labels, true line) scores it.
"""

import numpy as np

from clap_unified.geometry import canonical_lines
from clap_unified.viz import LineInput, LineScene, LineTruth


def true_line(theta=0.3, intercept=1.0):
    """``y = tan(theta) x + intercept`` as a canonical ``(theta, rho)`` line."""
    return canonical_lines([theta + np.pi / 2, intercept * np.cos(theta)])


def line_scene(n=200, outlier_ratio=0.5, theta=0.3, intercept=1.0, noise=0.02, seed=0,
               extent=5.0):
    """Noisy points on ``y = tan(theta) x + intercept`` plus uniform outliers.

    Returns
    -------
    LineScene
        ``input.points`` of shape (n, 2), the first ``round(outlier_ratio * n)``
        of them outliers; ``truth.label`` 0 for inliers and -1 for outliers,
        ``truth.line`` the true line.
    """
    rng = np.random.default_rng(seed)
    x = rng.uniform(-extent, extent, n)
    pts = np.c_[x, np.tan(theta) * x + intercept + rng.normal(0, noise, n)]
    k = int(round(outlier_ratio * n))
    pts[:k] = rng.uniform(-extent - 1, extent + 1, (k, 2))
    label = np.zeros(n, int)
    label[:k] = -1
    return LineScene(LineInput(pts), LineTruth(label, true_line(theta, intercept)[None]))


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
