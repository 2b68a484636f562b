"""Synthetic two-view scenes: rigid motions seen by a pinhole camera, with exact truth.

Random 3D points in front of a camera ``K [I | 0]`` (focal 800 px, a
640 x 480 image) are seen again after a rigid motion ``(R, t)``, drawn like a
small hand-held movement (a rotation of about 0.15 rad per axis, a mostly
sideways translation). With ``motions > 1`` the points form that many
objects, each moved by its own ``(R_k, t_k)``: the two-view motion
segmentation of AdelaideRMF's F sequences, with a known answer. Each motion's
matches agree with one fundamental matrix ``F_k = K^-T [t_k]_x R_k K^-1``.

Outliers are matches whose two points are drawn independently and uniformly
in the bounding boxes of the true matches of each view. Gaussian noise of
``noise`` px is added to both points of every true match.

The result is a :class:`~clap_unified.imaging.datasets.MultiModelPair` like
AdelaideRMF's: ``input.matches`` is what an estimator sees (outliers first,
then each motion's matches; no order is a hint: shuffle them if it matters),
``truth`` (a :class:`TwoViewTruth`) holds the labels (0 outlier, ``k`` for
motion ``k``) and the true fundamental matrices, for scoring only.

Examples
--------
>>> pair = synthetic_two_view(200, outliers=0.25, motions=2, rng=0)
>>> pair.input.matches.shape, pair.truth.n_structures, pair.truth.F.shape
((200, 4), 2, (2, 3, 3))
>>> np.bincount(pair.truth.labels).tolist()
[50, 75, 75]
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..._validation import as_generator, check_fraction, check_int, check_positive
from ...datatypes import freeze_arrays
from ...geometry import normalise_projective
from .adelaidermf import MultiModelInput, MultiModelPair, MultiModelTruth

__all__ = ["CAMERA", "TwoViewTruth", "synthetic_two_view"]

#: The camera of both views: focal 800 px, principal point at the centre of 640 x 480.
CAMERA = np.array([[800.0, 0.0, 320.0], [0.0, 800.0, 240.0], [0.0, 0.0, 1.0]])


@dataclass(frozen=True)
class TwoViewTruth(MultiModelTruth):
    """:class:`~clap_unified.imaging.datasets.MultiModelTruth` plus the true motions.

    Attributes
    ----------
    labels : ndarray of int, shape (N,)
        0 for an outlier, ``k`` for a match of motion ``k``.
    F : ndarray of shape (K, 3, 3)
        The fundamental matrix of each motion (unit Frobenius norm, the
        library's sign convention), ``x2^T F x1 = 0``.
    """

    F: np.ndarray = None

    def __post_init__(self):
        super().__post_init__()
        F = np.asarray(self.F, dtype=float)
        if F.shape != (self.n_structures, 3, 3):
            raise ValueError(f"F: expected shape ({self.n_structures}, 3, 3), got {F.shape}")
        object.__setattr__(self, "F", F)
        freeze_arrays(self)


def _rotation(v) -> np.ndarray:
    """The rotation of angle ``|v|`` about ``v`` (Rodrigues)."""
    a = float(np.linalg.norm(v))
    if a == 0:
        return np.eye(3)
    k = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]]) / a
    return np.eye(3) + np.sin(a) * k + (1 - np.cos(a)) * k @ k


def synthetic_two_view(n: int = 300, outliers: float = 0.5, noise: float = 0.5, *,
                       motions: int = 1, rng=None, motion=None) -> MultiModelPair:
    """A two-view scene of ``motions`` rigid motions and outliers (see the module).

    Parameters
    ----------
    n : int
        Matches in all.
    outliers : float
        Their share that are outliers, in [0, 1).
    noise : float
        Standard deviation of the Gaussian noise on each coordinate, in pixels.
    motions : int
        Rigid motions (objects); the true matches are split evenly among them.
    rng : None, int or numpy.random.Generator
    motion : (array_like, array_like), optional
        ``(rotation vector, translation)`` of the one motion, instead of a drawn one
        (``motions`` must be 1); the rotation vector's norm is the angle in radians.

    Returns
    -------
    MultiModelPair
        ``kind="fundamental"``; ``input.score`` is all zeros (no matching score).
    """
    n = check_int(n, "n", minimum=7)
    outliers = check_fraction(outliers, "outliers")
    noise = check_positive(noise, "noise", allow_zero=True)
    motions = check_int(motions, "motions", minimum=1)
    g = as_generator(rng)
    if motion is not None:
        if motions != 1:
            raise ValueError(f"motion: given for one motion, but motions={motions}")
        try:
            given = [np.asarray(v, dtype=float).reshape(3) for v in motion]
        except (TypeError, ValueError):
            raise ValueError("motion: expected (rotation vector, translation), 3 numbers "
                             "each") from None
        if len(given) != 2 or not all(np.all(np.isfinite(v)) for v in given):
            raise ValueError("motion: expected (rotation vector, translation), 3 finite "
                             "numbers each")
    k_out = int(round(outliers * n))
    sizes = np.full(motions, (n - k_out) // motions)
    sizes[: (n - k_out) % motions] += 1
    if sizes.min() < 7:
        raise ValueError(f"n: {n - k_out} true matches for {motions} motions, fewer than 7 "
                         "(a minimal sample) each")
    Ki = np.linalg.inv(CAMERA)
    x1s, x2s, Fs = [], [], []
    for size in sizes:
        if motion is None:
            R = _rotation(g.normal(0, 0.15, 3))
            t = g.normal(0, 1, 3)
            t[2] *= 0.2
        else:
            R, t = _rotation(given[0]), given[1]
        X = np.c_[g.uniform(-2, 2, (size, 2)), g.uniform(4, 8, size)]
        p1, p2 = X @ CAMERA.T, (X @ R.T + t) @ CAMERA.T
        x1s.append(p1[:, :2] / p1[:, 2:] + g.normal(0, noise, (size, 2)))
        x2s.append(p2[:, :2] / p2[:, 2:] + g.normal(0, noise, (size, 2)))
        tx = np.array([[0, -t[2], t[1]], [t[2], 0, -t[0]], [-t[1], t[0], 0]])
        Fs.append(normalise_projective(Ki.T @ tx @ R @ Ki))
    x1, x2 = np.vstack(x1s), np.vstack(x2s)
    out1 = g.uniform(x1.min(0), x1.max(0), (k_out, 2))
    out2 = g.uniform(x2.min(0), x2.max(0), (k_out, 2))
    matches = np.r_[np.c_[out1, out2], np.c_[x1, x2]]
    labels = np.r_[np.zeros(k_out, np.int64), np.repeat(np.arange(1, motions + 1), sizes)]
    name = f"synthetic two-view, {motions} motion(s), {100 * outliers:g} % outliers"
    return MultiModelPair(name, "fundamental", MultiModelInput(matches, np.zeros(n)),
                          TwoViewTruth(labels, np.array(Fs)))
