"""Rigid motions of space from point correspondences: the correspondence space.

The weighted Kabsch alignment lives on the geometry floor
(:func:`~clap_unified.geometry.rigid.kabsch`, one for the plane and space).
Convention: ``q = R p + t``; a pose ``T_world_body`` maps body points ``p`` to
world points ``q``.

:class:`Correspondence3DSpace` is the hypothesis space of putative point
correspondences ``(p, q)``: every triplet gives one pose, after two cheap
checks (the triplet is not near-collinear, and its three pairwise distances
agree in both frames, as a rigid motion preserves them).
"""

from __future__ import annotations

import numpy as np

from .._validation import Checked, check_points, check_positive
from ..geometry.rigid import pose_from_rt, transform_points, weighted_kabsch
from ..geometry.se3 import SE3
from .base import Capabilities, HypothesisSpace

__all__ = ["min_altitude", "Correspondence3DSpace", "near_pose", "pose_to_dict",
           "pose_manifold"]

#: Reference points for ``metric="point_set"`` when none are given: +-3 m on each axis.
DEFAULT_REFERENCE_POINTS = 3.0 * np.vstack([np.eye(3), -np.eye(3)])


def min_altitude(triangles) -> np.ndarray:
    """Smallest altitude of triangles ``(..., 3, 3)``: twice the area over the longest side.

    Zero for collinear (or coincident) points; a triplet whose smallest
    altitude is a few centimetres does not fix the rotation about its line.

    Examples
    --------
    >>> tri = np.array([[[0.0, 0, 0], [4.0, 0, 0], [2.0, 0.5, 0]],
    ...                 [[0.0, 0, 0], [1.0, 0, 0], [2.0, 0.0, 0]]])
    >>> min_altitude(tri).round(6).tolist()
    [0.5, 0.0]
    """
    T = np.asarray(triangles, dtype=float)
    e = T[..., [1, 2, 0], :] - T  # sides 01, 12, 20
    area2 = np.linalg.norm(np.cross(e[..., 0, :], -e[..., 2, :]), axis=-1)
    longest = np.linalg.norm(e, axis=-1).max(axis=-1)
    return np.divide(area2, longest, out=np.zeros_like(area2), where=longest > 0)


def pose_manifold(angle_weight: float, metric: str, reference_points) -> SE3:
    """The SE(3) a pose space clusters in (default point-set reference when none is given)."""
    if metric == "point_set" and reference_points is None:
        reference_points = DEFAULT_REFERENCE_POINTS
    return SE3(angle_weight, metric=metric, reference_points=reference_points)


def near_pose(manifold, prior, models, radius) -> np.ndarray:
    """Mask of the ``models`` within ``radius`` of ``prior``: the pose spaces' local gate.

    ``radius`` is a float (the manifold's distance) or a pair ``(max_translation,
    max_rotation)`` (metres, radians) bounding the two parts of the relative
    transform error (Sec. III-C of the paper).

    Examples
    --------
    >>> from clap_unified.geometry import so3_exp
    >>> g = SE3(2.0)
    >>> T = np.stack([SE3.from_rt(so3_exp([0, 0, a]), [x, 0, 0]) for x, a in
    ...               [(0.1, 0.0), (0.1, 0.3), (0.8, 0.0)]])
    >>> near_pose(g, np.eye(4), T, (0.5, np.radians(10))).tolist()
    [True, False, False]
    """
    if np.ndim(radius) == 0:
        return manifold.distance(prior, models) <= check_positive(radius, "radius")
    r = np.asarray(radius, dtype=float)
    if r.shape != (2,):
        raise ValueError(f"radius: expected a distance or a pair (max_translation, "
                         f"max_rotation), got {radius!r}")
    max_t, max_r = check_positive(r[0], "radius"), check_positive(r[1], "radius")
    e_t, e_r = manifold.relative_error(prior, models)
    return (e_t <= max_t) & (e_r <= max_r)


def pose_to_dict(model) -> dict:
    """``{"rotation": 3 x 3 row-major, "translation": [x, y, z]}`` of a 4 x 4 pose."""
    T = np.asarray(model, dtype=float)
    return {"rotation": T[:3, :3].tolist(), "translation": T[:3, 3].tolist()}


class Correspondence3DSpace(HypothesisSpace):
    """SE(3) poses from triplets of putative 3D point correspondences.

    Data are rows ``(px, py, pz, qx, qy, qz)``: a point ``p`` in the body
    frame and the world point ``q`` it is believed to be. Models are poses
    ``T_world_body`` (``q = R p + t``) as 4 x 4 matrices.

    Parameters
    ----------
    distance_tolerance : float
        A triplet is solved only if each of its three pairwise distances
        agrees within this (metres) between the frames.
    min_altitude : float
        A triplet whose smallest triangle altitude (in either frame) is below
        this (metres) is near-collinear and rejected.
    angle_weight : float
        lambda of the SE(3) distance, metres per radian.
    metric : {"relative", "lie", "point_set"}
        Distance between poses (see :class:`~clap_unified.geometry.SE3`):
        the default ``sqrt(e_t^2 + lambda^2 e_r^2)`` is a true metric and
        several times cheaper than the Lie-log one.
    reference_points : ndarray of shape (P, 3), optional
        Body-frame points of the ``point_set`` metric (default: +-3 m on each axis).
    inlier_threshold : float
        Default data inlier threshold, metres.

    Examples
    --------
    >>> from clap_unified.geometry import so3_exp
    >>> rng = np.random.default_rng(0)
    >>> p = rng.uniform(-3, 3, (6, 3))
    >>> q = p @ so3_exp([0.0, 0.0, 0.5]).T + [1.0, 0.0, 0.0]
    >>> q[5] += 2.0                                  # one wrong correspondence
    >>> space = Correspondence3DSpace()
    >>> models, owner = space.solve_minimal(np.c_[p, q], np.array([[0, 1, 2], [0, 1, 5]]))
    >>> owner.tolist(), models[0][:3, 3].round(6).tolist()   # the wrong triplet is rejected
    ([0], [1.0, 0.0, 0.0])
    """

    min_samples = 3
    model_shape = (4, 4)
    name = "rigid3d"
    #: Beyond the protocol: :meth:`near_prior` takes a pair of thresholds,
    #: :meth:`correspondences` hands the putative pairs to external estimators.
    declared = Capabilities()

    def __init__(self, *, distance_tolerance: float = 0.2, min_altitude: float = 0.1,
                 angle_weight: float = 2.0, metric: str = "relative", reference_points=None,
                 inlier_threshold: float = 0.15):
        self.distance_tolerance = check_positive(distance_tolerance, "distance_tolerance")
        self.min_altitude = check_positive(min_altitude, "min_altitude", allow_zero=True)
        self.inlier_threshold = check_positive(inlier_threshold, "inlier_threshold")
        self._manifold = pose_manifold(angle_weight, metric, reference_points)

    def __repr__(self) -> str:
        return (f"Correspondence3DSpace(tol={self.distance_tolerance:g}, "
                f"manifold={self._manifold!r})")

    @property
    def manifold(self) -> SE3:
        return self._manifold

    def check_data(self, data) -> np.ndarray:
        return check_points(data, "correspondences", dim=6, min_count=self.min_samples)

    def hypotheses(self, data, n: int, *, rng=None, prior=None, radius=None,
                   **sampling):
        """Poses from random triplets; ``sampling`` may set ``exhaustive`` and ``max_draws``.

        ``exhaustive=False, max_draws=n`` draws exactly ``n`` triplets (the
        budget of :func:`~clap_unified.localization.align_correspondences`),
        keeping those that pass the checks (see
        :func:`~clap_unified.spaces.generate_hypotheses`). ``data`` is checked
        (:meth:`~clap_unified.spaces.base.HypothesisSpace.check_data`).
        """
        from .sampling import generate_hypotheses

        unknown = sorted(set(sampling) - {"exhaustive", "max_draws"})
        if unknown:
            raise ValueError(f"sampling: the {self.name} space takes exhaustive and max_draws, "
                             f"got {unknown}")
        return generate_hypotheses(self, Checked(np.asarray(data, dtype=float)), n, rng=rng,
                                   **sampling)

    def near_prior(self, prior, models, radius) -> np.ndarray:
        """Models within ``radius`` of ``prior`` (a distance or a pair, see ``near_pose``)."""
        return near_pose(self.manifold, prior, models, radius)

    def correspondences(self, data):
        """Putative pairs for correspondence estimators: ``(source, target, pairs)``.

        Here the rows are the pairs: ``source = p``, ``target = q`` and
        ``pairs`` the identity ``(i, i)``.
        """
        data = np.asarray(data, dtype=float)
        i = np.arange(len(data), dtype=np.intp)
        return data[:, :3], data[:, 3:], np.c_[i, i]

    def solve_minimal(self, data, samples):
        """One Kabsch pose per triplet that passes the collinearity and distance checks."""
        data = np.asarray(data, dtype=float)
        P, Q = data[samples, :3], data[samples, 3:]  # (S, 3, 3)
        dP = np.linalg.norm(P[:, [1, 2, 0]] - P, axis=-1)
        dQ = np.linalg.norm(Q[:, [1, 2, 0]] - Q, axis=-1)
        owner = np.flatnonzero(np.all(np.abs(dP - dQ) <= self.distance_tolerance, axis=1))
        # the cheap distance check first: the collinearity check sees its survivors only
        owner = owner[(min_altitude(P[owner]) >= self.min_altitude)
                      & (min_altitude(Q[owner]) >= self.min_altitude)]
        if len(owner) == 0:
            return np.empty((0, 4, 4)), owner
        R, t, _ = weighted_kabsch(P[owner], Q[owner], np.ones((len(owner), 3)))
        return pose_from_rt(R, t), owner

    def residuals(self, models, data) -> np.ndarray:
        """``|R p + t - q|`` for every model and correspondence, shape ``(H, N)``."""
        data = np.asarray(data, dtype=float)
        return np.linalg.norm(transform_points(models, data[:, :3]) - data[None, :, 3:], axis=-1)

    def refit(self, data, weights=None, initial=None):
        """Weighted Kabsch on all the given correspondences; None when degenerate."""
        data = np.asarray(data, dtype=float)
        return _refit(data[:, :3], data[:, 3:], weights, self.min_altitude)

    def model_to_dict(self, model) -> dict:
        return pose_to_dict(model)

    def default_threshold(self, data) -> float:
        return self.inlier_threshold


def _refit(source, target, weights, min_alt):
    """Weighted Kabsch with a degeneracy check (None below 3 points or when collinear)."""
    if len(source) < 3:
        return None
    w = np.ones(len(source)) if weights is None else np.asarray(weights, dtype=float)
    centred = source - (w @ source) / w.sum()
    sv = np.linalg.svd(centred, compute_uv=False)
    if sv[1] / np.sqrt(len(source)) < 0.5 * max(min_alt, 1e-9):  # collinear spread
        return None
    R, t, _ = weighted_kabsch(source, target, w)
    return pose_from_rt(R, t)
