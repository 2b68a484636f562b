"""Hypothesis space of fundamental matrices: two views of a rigid scene.

Convention: ``x2^T F x1 = 0`` for matches ``(x1, y1, x2, y2)`` (the rows
:class:`~clap_unified.spaces.homography.HomographySpace` takes). Models are
scaled to unit Frobenius norm with their entry of largest magnitude positive.
The arithmetic lives on the geometry floor
(:mod:`clap_unified.geometry.fundamental`): the 7-point minimal solver
(one to three models per sample), the normalised 8-point refit and the Sampson
error; the hypotheses are compared on
:class:`~clap_unified.geometry.projective.ProjectiveMatrices` (the angle
between matrices up to scale and sign).
"""

from __future__ import annotations

import numpy as np

from .._validation import check_points, unwrap_checked
from ..geometry.fundamental import eight_point, sampson_denominator, sampson_error, seven_point
from ..geometry.homography_arithmetic import normalise_points
from ..geometry.projective import ProjectiveMatrices, normalise_projective
from .base import HypothesisSpace

__all__ = ["FundamentalSpace"]

#: Refits of :meth:`FundamentalSpace.refine` at most.
REFINE_ROUNDS = 10


class FundamentalSpace(HypothesisSpace):
    """Fundamental matrices ``F`` (``x2^T F x1 = 0``) from matches ``(N, 4)``.

    Hypotheses come from uniform random 7-match samples
    (:func:`~clap_unified.geometry.fundamental.seven_point`: up to three
    models per sample, none for a degenerate one); residuals are the square
    root of the Sampson distance, in pixels
    (:func:`~clap_unified.geometry.fundamental.sampson_error`); the refit is
    the normalised weighted 8-point algorithm on the inliers (``None`` with
    fewer than 8 or when they do not determine ``F``).

    The manifold is :class:`~clap_unified.geometry.projective.ProjectiveMatrices`:
    without a frame (this constructor) it compares the pixel matrices, whose
    entries differ by orders of magnitude; for CLAP use :meth:`for_data`,
    which compares them in the Hartley frame of the matches.

    A 7-match sample is clean with probability ``w^7`` (``w`` the inlier
    ratio: 0.8 % at ``w = 0.5``), so few hypotheses are near the answer and
    a cluster of wrong ones can be larger. On the synthetic scenes of
    ``tests/test_fundamental_space.py`` at 50 % outliers CLAP's defaults
    (seeds by neighbour count, the largest cluster) fail, and
    ``density="knn", select="consensus"`` with 3000 hypotheses recovers ``F``
    (``bench/bench_fundamental.py`` measures both against RANSAC and the
    peers).

    Examples
    --------
    >>> from clap_unified import fit
    >>> rng = np.random.default_rng(0)
    >>> X = np.c_[rng.uniform(-2, 2, (150, 2)), rng.uniform(4, 8, 150)]
    >>> x1 = 800 * X[:, :2] / X[:, 2:] + 320
    >>> Y = X + [1.0, 0.2, 0.1]                      # the second camera, translated
    >>> x2 = 800 * Y[:, :2] / Y[:, 2:] + 320 + rng.normal(0, 0.3, (150, 2))
    >>> x2[:45] = rng.uniform(0, 640, (45, 2))       # 30 % outliers
    >>> matches = np.c_[x1, x2]
    >>> res = fit(FundamentalSpace(), matches, "ransac", threshold=1.0, rng=0)
    >>> res.success, bool(res.inliers[45:].mean() > 0.95), int(res.inliers[:45].sum()) < 5
    (True, True, True)
    >>> sorted(FundamentalSpace().model_to_dict(res.model))
    ['F']
    """

    min_samples = 7
    model_shape = (3, 3)
    name = "fundamental"

    def __init__(self):
        self._manifold = None

    @classmethod
    def for_data(cls, matches) -> FundamentalSpace:
        """A space that compares hypotheses in the Hartley frame of ``matches``.

        With ``T1``, ``T2`` the Hartley normalisations of the points of image
        1 and image 2, hypotheses are compared as ``T2^-T F T1^-1`` (``F`` in
        normalised coordinates, entries of order one); models, residuals and
        refits stay in pixels.

        Examples
        --------
        >>> rng = np.random.default_rng(0)
        >>> src = rng.uniform(0, 640, (50, 2))
        >>> FundamentalSpace.for_data(np.c_[src, src + 5.0]).manifold
        ProjectiveMatrices(framed=True)
        """
        data = unwrap_checked(matches, cls().check_data)
        T1, T2 = normalise_points(data.reshape(-1, 2, 2).transpose(1, 0, 2))[1]
        space = cls()
        try:
            frame = ProjectiveMatrices(left=np.linalg.inv(T2).T, right=np.linalg.inv(T1))
        except (ValueError, np.linalg.LinAlgError):
            return space  # the points of an image coincide: no frame, every sample degenerate
        space._manifold = frame
        return space

    def __repr__(self) -> str:
        return "FundamentalSpace()"

    @property
    def manifold(self) -> ProjectiveMatrices:
        if self._manifold is None:
            self._manifold = ProjectiveMatrices()
        return self._manifold

    def check_data(self, data) -> np.ndarray:
        return check_points(data, "matches", dim=4, min_count=self.min_samples)

    def solve_minimal(self, data, samples):
        data = np.asarray(data, dtype=float)
        samples = np.asarray(samples)
        if samples.ndim != 2 or samples.shape[1] != 7:
            raise ValueError(f"samples: expected shape (S, 7), got {samples.shape}")
        rows = data[samples]  # (S, 7, 4)
        return seven_point(rows[..., :2], rows[..., 2:])

    def refit(self, data, weights=None, initial=None):
        data = np.asarray(data, dtype=float)
        if len(data) < 8:
            return None
        return eight_point(data[:, :2], data[:, 2:], weights)

    def residuals(self, models, data) -> np.ndarray:
        F = np.asarray(models, dtype=float).reshape(-1, 3, 3)
        data = np.asarray(data, dtype=float)
        return sampson_error(F, data[:, :2], data[:, 2:])

    def refine(self, model, data, threshold):
        """Sampson-weighted 8-point refits on the inliers (Sampson's iteration), at most 10.

        Each round refits on the current inliers with weights ``1 / g_i``
        (``g_i`` the Sampson denominator at the current model: the weighted
        algebraic error is then the squared Sampson error of the current
        model, so the iteration moves the linear fit towards the Sampson
        optimum); a round is kept while the inlier set does not shrink and the
        iteration stops when it no longer changes. The first refit is the
        plain one (weights 1), as in :func:`~clap_unified.refine.refit_on_inliers`.
        """
        data = np.asarray(data, dtype=float)
        x1, x2 = data[:, :2], data[:, 2:]
        inliers = sampson_error(model, x1, x2) < threshold
        weights = None
        for round_ in range(REFINE_ROUNDS):
            if np.count_nonzero(inliers) < 8:
                break
            new = eight_point(x1[inliers], x2[inliers], weights)
            if new is None:
                break
            new_inliers = sampson_error(new, x1, x2) < threshold
            if round_ > 0 and np.count_nonzero(new_inliers) < np.count_nonzero(inliers):
                break
            changed = not np.array_equal(new_inliers, inliers)
            model, inliers = new, new_inliers
            if not changed and weights is not None:
                break
            weights = 1.0 / np.maximum(sampson_denominator(model, x1[inliers], x2[inliers]),
                                       1e-300)
        return model, inliers

    def model_to_dict(self, model) -> dict:
        return {"F": normalise_projective(np.asarray(model, dtype=float)).tolist()}

    def default_threshold(self, data) -> float:
        """1 pixel of Sampson error (PoseLib's default ``max_epipolar_error``)."""
        return 1.0

    def default_cell_size(self, data) -> float:
        """Randomized Hough cell edge: 0.05 rad in the manifold's chart."""
        return 0.05
