"""Hypothesis space of circles in the plane: three points make a circle.

This module is also the library's worked example of a new space
(``ARCHITECTURE.md``, "How to add a space"): a subclass of
:class:`~clap_unified.spaces.base.HypothesisSpace` that sets ``min_samples``,
``model_shape`` and ``name`` and implements ``manifold``, ``check_data``,
``solve_minimal``, ``residuals`` and ``refit``, in a few dozen lines. Every
general strategy (CLAP, RANSAC, randomized Hough) then runs on it through
:func:`~clap_unified.fit` and :func:`~clap_unified.compare`.
"""

from __future__ import annotations

import numpy as np

from .._validation import check_array, check_points
from ..geometry.euclidean import Euclidean
from .base import HypothesisSpace

__all__ = ["CircleSpace"]


class CircleSpace(HypothesisSpace):
    """Circles ``(cx, cy, r)`` fitted to 2D points ``(N, 2)``.

    The minimal solver is the circumcircle of three points (collinear samples
    have none); residuals are distances to the circle; the refit is the
    algebraic (Kasa) least-squares circle. Both work in the frame of their own
    points (centred, scaled by a power of two of their spread), so a circle is
    found alike wherever it is and whatever the unit. Hypotheses live on the flat
    manifold ``Euclidean(3)``: two circles are as far apart as their centres
    and radii, in data units.

    Examples
    --------
    >>> from clap_unified import fit
    >>> t = np.linspace(0, 2 * np.pi, 60, endpoint=False)
    >>> pts = np.c_[2 + 3 * np.cos(t), -1 + 3 * np.sin(t)]
    >>> pts[::3] = np.random.default_rng(0).uniform(-3, 7, (20, 2))  # 20 outliers, 1 near
    >>> res = fit(CircleSpace(), pts, "clap", threshold=0.05, rng=0)
    >>> print(f"centre ({res.model[0]:.3f}, {res.model[1]:.3f}), radius {res.model[2]:.3f}, "
    ...       f"{res.n_inliers} inliers")
    centre (2.000, -1.000), radius 3.000, 41 inliers
    """

    min_samples = 3
    model_shape = (3,)
    name = "circle"

    def __init__(self):
        self._manifold = Euclidean(3)

    def __repr__(self) -> str:
        return "CircleSpace()"

    @property
    def manifold(self) -> Euclidean:
        return self._manifold

    def check_data(self, data) -> np.ndarray:
        return check_points(data, "points", dim=2, min_count=self.min_samples)

    def solve_minimal(self, data, samples):
        pts = data[samples]  # (S, 3, 2)
        # each sample in its own frame: centred on its mean, in a power-of-two unit of its
        # spread (exact scaling), so neither where the circle is (1e5 away from the origin)
        # nor its size (1e-100 or 1e150) changes which samples count as degenerate
        centre, unit = _frame(pts)
        a, b, c = ((pts[:, k] - centre) / unit[:, None] for k in range(3))
        d = 2 * (a[:, 0] * (b[:, 1] - c[:, 1]) + b[:, 0] * (c[:, 1] - a[:, 1])
                 + c[:, 0] * (a[:, 1] - b[:, 1]))
        ok = np.abs(d) > 1e-9  # collinear (or coincident) samples have no circle
        a, b, c, d = a[ok], b[ok], c[ok], d[ok]
        sa, sb, sc = (np.sum(p * p, axis=1) for p in (a, b, c))
        cx = (sa * (b[:, 1] - c[:, 1]) + sb * (c[:, 1] - a[:, 1])
              + sc * (a[:, 1] - b[:, 1])) / d
        cy = (sa * (c[:, 0] - b[:, 0]) + sb * (a[:, 0] - c[:, 0])
              + sc * (b[:, 0] - a[:, 0])) / d
        r = np.hypot(a[:, 0] - cx, a[:, 1] - cy)
        u = unit[ok, None]
        return np.c_[centre[ok] + u * np.c_[cx, cy], u[:, 0] * r], np.flatnonzero(ok)

    def residuals(self, models, data) -> np.ndarray:
        m = np.asarray(models, dtype=float).reshape(-1, 3)
        dx = data[None, :, 0] - m[:, None, 0]
        dy = data[None, :, 1] - m[:, None, 1]
        return np.abs(np.hypot(dx, dy) - m[:, None, 2])

    def refit(self, data, weights=None, initial=None):
        """Algebraic (Kasa) circle of the weighted data, solved in the data's own frame."""
        w = np.ones(len(data)) if weights is None else np.asarray(weights, float)
        data = np.asarray(data, float)[w > 0]
        w = np.sqrt(w[w > 0])
        if len(data) < 3:
            return None
        centre, unit = _frame(data[None])
        x = (data - centre[0]) / unit[0]  # centred, spread about 1: no cancellation
        A = np.c_[2 * x, np.ones(len(x))] * w[:, None]
        sol, _, _, sv = np.linalg.lstsq(A, np.sum(x * x, axis=1) * w, rcond=None)
        r2 = sol[2] + sol[0] ** 2 + sol[1] ** 2
        if not (sv[-1] > 1e-9 * sv[0] and np.isfinite(r2) and r2 > 0):
            return None  # collinear data (a line: infinite radius) or a point: no circle
        return np.r_[centre[0] + unit[0] * sol[:2], unit[0] * np.sqrt(r2)]

    @staticmethod
    def predict(model, angles) -> np.ndarray:
        """Points of the circle ``model`` at ``angles`` (radians), shape ``(..., 2)``.

        ``(cx + r cos t, cy + r sin t)``, as scikit-image's ``CircleModel.predict_xy``.

        Examples
        --------
        >>> CircleSpace.predict([0.0, 0.0, 5.0], [0, np.pi / 2]).round(12).tolist()
        [[5.0, 0.0], [0.0, 5.0]]
        """
        cx, cy, r = check_array(model, "model", shape=(3,))
        t = np.asarray(angles, dtype=float)
        return np.stack([cx + r * np.cos(t), cy + r * np.sin(t)], axis=-1)

    def model_to_dict(self, model) -> dict:
        cx, cy, r = (float(v) for v in model)
        return {"centre": [cx, cy], "radius": r}

    def default_threshold(self, data) -> float:
        # 1 % of the data's RMS radius: a scale-free default; pass a value for real units.
        centre = data.mean(axis=0)
        return 0.01 * max(float(np.sqrt(np.mean(np.sum((data - centre) ** 2, axis=1)))), 1e-12)


def _frame(points):
    """Per stack of points ``(S, k, 2)``: their mean ``(S, 2)`` and a power of two ``(S,)``
    at least their largest centred coordinate (1 for coincident points)."""
    centre = points.mean(axis=1)
    spread = np.max(np.abs(points - centre[:, None]), axis=(1, 2))
    _, exponent = np.frexp(np.where(spread > 0, spread, 1.0))
    return centre, np.ldexp(1.0, exponent)
