"""Synthetic line scenes with ground truth, and the errors the book reports.

These are teaching data, not estimators: points on a known line with
Gaussian noise across it, plus uniform outliers in a square. A scene keeps
what an estimator may see (:class:`LineInput`, the noisy points) apart from
what scores it (:class:`LineTruth`, labels and true lines), as every loader
of the package does (:mod:`clap_unified.datatypes`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validation import as_generator, check_fraction, check_int, check_positive
from ..datatypes import freeze_arrays
from ..geometry.lines import Line2D, canonical_lines

__all__ = ["DEFAULT_LINE", "LineInput", "LineScene", "LineTruth", "line_errors", "line_scene"]

#: The line ``y = 0.3 x + 1`` as ``(theta, rho)``.
DEFAULT_LINE = (np.pi / 2 + np.arctan(0.3), np.cos(np.arctan(0.3)))


@dataclass(frozen=True)
class LineInput:
    """What an estimator may see of a line scene: the noisy points, nothing else.

    Attributes
    ----------
    points : ndarray of shape (N, 2)
        Noisy inliers and outliers in random order (read-only).
    """

    points: np.ndarray

    def __post_init__(self):
        freeze_arrays(self)


@dataclass(frozen=True)
class LineTruth:
    """Evaluation data of a line scene, for scoring only.

    Attributes
    ----------
    label : ndarray of int, shape (N,)
        Index of the line each input point was drawn from, ``-1`` for an
        outlier (read-only, aligned with ``LineInput.points``).
    lines : ndarray of shape (L, 2)
        The true lines ``(theta, rho)``, canonical (``theta`` in ``[0, pi)``).
    """

    label: np.ndarray
    lines: np.ndarray

    def __post_init__(self):
        freeze_arrays(self)

    @property
    def is_inlier(self) -> np.ndarray:
        """True for points drawn from a line (a new array)."""
        return self.label >= 0

    @property
    def line(self) -> np.ndarray:
        """The first true line (the only one in a single-line scene)."""
        return self.lines[0]


@dataclass(frozen=True)
class LineScene:
    """A synthetic line scene, split into estimator input and evaluation data.

    Pass ``scene.input.points`` to an estimator; score its answer with
    ``scene.truth``. The scene has no shortcut to either part's fields, so an
    experiment has to say which one it uses.

    Attributes
    ----------
    input : LineInput
        The noisy points.
    truth : LineTruth
        Labels and true lines.

    Examples
    --------
    >>> from dataclasses import fields
    >>> scene = line_scene(10, 0.5, rng=0)
    >>> [f.name for f in fields(scene.input)]
    ['points']
    >>> scene.input.points.flags.writeable
    False
    """

    input: LineInput
    truth: LineTruth

    def __post_init__(self):
        if not isinstance(self.input, LineInput) or not isinstance(self.truth, LineTruth):
            raise TypeError("LineScene: expected a LineInput and a LineTruth")
        if len(self.input.points) != len(self.truth.label):
            raise ValueError(f"LineScene: {len(self.input.points)} points but "
                             f"{len(self.truth.label)} labels")


def line_scene(n: int = 200, outlier_ratio: float = 0.5, *, lines=(DEFAULT_LINE,),
               share=None, noise: float = 0.05, half_length: float = 5.0,
               extent: float = 6.0, rng=None) -> LineScene:
    """Noisy points on one or more lines and uniform outliers.

    Parameters
    ----------
    n : int
        Total number of points.
    outlier_ratio : float in [0, 1]
        Fraction of the points that are outliers (rounded to a whole number).
    lines : array_like of shape (L, 2)
        True lines ``(theta, rho)``: ``x cos(theta) + y sin(theta) = rho``.
        The default is ``DEFAULT_LINE``, ``y = 0.3 x + 1``.
    share : array_like of shape (L,), optional
        How the inliers are split between the lines (default: equally).
    noise : float
        Standard deviation of the Gaussian noise across the line (data units).
    half_length : float
        Inliers are uniform along the line within this distance of the foot
        of the perpendicular from the origin.
    extent : float
        Outliers are uniform in ``[-extent, extent]^2``.
    rng : None, int or numpy.random.Generator

    Returns
    -------
    LineScene
        ``input.points``: the noisy points in random order, the only thing to
        give an estimator; ``truth``: their labels and the true lines. The
        noise-free positions of the inliers are not kept anywhere.

    Examples
    --------
    >>> scene = line_scene(100, 0.3, rng=0)
    >>> points, truth = scene.input.points, scene.truth
    >>> points.shape, int(truth.is_inlier.sum())
    ((100, 2), 70)
    >>> from clap_unified.spaces import LineSpace
    >>> res = LineSpace().residuals(truth.line, points[truth.is_inlier])
    >>> bool(res.max() < 5 * 0.05)
    True
    """
    n = check_int(n, "n", minimum=2)
    ratio = check_fraction(outlier_ratio, "outlier_ratio")
    noise = check_positive(noise, "noise", allow_zero=True)
    half_length = check_positive(half_length, "half_length")
    extent = check_positive(extent, "extent")
    true = canonical_lines(np.atleast_2d(np.asarray(lines, dtype=float)))
    if true.ndim != 2 or true.shape[1] != 2:
        raise ValueError(f"lines: expected shape (L, 2), got {np.shape(lines)}")
    g = as_generator(rng)
    n_out = int(round(ratio * n))
    n_in = n - n_out
    w = np.ones(len(true)) if share is None else np.asarray(share, dtype=float)
    if w.shape != (len(true),) or np.any(w < 0) or w.sum() <= 0:
        raise ValueError(f"share: expected {len(true)} non-negative weights with a positive sum")
    counts = np.floor(n_in * w / w.sum()).astype(int)
    counts[0] += n_in - counts.sum()
    pts, label = [], []
    for k, ((theta, rho), m) in enumerate(zip(true, counts, strict=True)):
        normal = np.array([np.cos(theta), np.sin(theta)])
        along = np.array([-normal[1], normal[0]])
        t = g.uniform(-half_length, half_length, m)
        e = g.normal(0.0, noise, m) if noise > 0 else np.zeros(m)
        pts.append(rho * normal + t[:, None] * along + e[:, None] * normal)
        label.append(np.full(m, k))
    pts.append(g.uniform(-extent, extent, (n_out, 2)))
    label.append(np.full(n_out, -1))
    pts, label = np.concatenate(pts), np.concatenate(label)
    order = g.permutation(n)
    return LineScene(LineInput(pts[order]), LineTruth(label[order], true))


def line_errors(models, truth):
    """Angle and offset errors of fitted lines against a true line.

    Parameters
    ----------
    models : array_like of shape (..., 2)
        Fitted lines ``(theta, rho)``.
    truth : array_like of shape (2,)
        The true line.

    Returns
    -------
    angle : ndarray of shape (...)
        Angle between the lines in degrees, in ``[0, 90]``.
    offset : ndarray of shape (...)
        ``|rho - rho_true|`` once the normals point the same way (data units):
        the distance between the lines at the coordinate origin, measured
        along the true normal.

    Examples
    --------
    >>> a, o = line_errors([np.pi - 0.01, -1.0], [0.0, 1.0])
    >>> print(f"{float(a):.3f} deg, {float(o):.3f}")
    0.573 deg, 0.000
    """
    m = np.asarray(models, dtype=float)
    normal, rho = Line2D.normal_offset(m)
    t_normal, t_rho = Line2D.normal_offset(np.asarray(truth, dtype=float))
    c = normal @ t_normal
    sign = np.where(c < 0, -1.0, 1.0)
    angle = np.degrees(np.arccos(np.clip(np.abs(c), 0.0, 1.0)))
    return angle, np.abs(sign * rho - t_rho)
