"""Hypothesis space of 6-DoF poses from type-labelled 3D landmark detections.

The paper's 3D CLAP (Sec. III-A): a triplet of observed landmarks, matched to
every type-compatible ordered triplet of map landmarks, fixes one SE(3) pose
by closed-form SVD alignment (:func:`~clap_unified.geometry.rigid.kabsch`).
No data association is assumed: a detection carries only its type, so the
candidates of one triplet are all map triplets of the same type pattern whose
three pairwise distances agree with the observed ones (rigid motions preserve
distances); near-collinear triplets are rejected. Everything is batched over
triplets: first the map pairs compatible with each observed pair ``(i, j)``,
then the third landmarks compatible with both ``(i, k)`` and ``(j, k)``.

Data are observations ``(N, 4)`` rows ``(type_id, x, y, z)`` in the body
frame (metres), ``type_id`` indexing ``Landmark3DSpace.type_names``.
Models are poses ``T_world_body`` as 4 x 4 matrices: a body point ``p`` is at
``R p + t`` in the world. Residual of an observation: its distance, once moved
to the world, to the nearest map landmark of its type. When the association
is known (putative correspondences), use
:class:`~clap_unified.spaces.rigid3d.Correspondence3DSpace` instead.
"""

from __future__ import annotations

import numpy as np

from .._validation import check_array, check_points, check_positive
from ..geometry.rigid import pose_from_rt, transform_points, weighted_kabsch
from ..geometry.se3 import SE3
from ..maps.nearest import nearest_of_type
from .base import Capabilities, HypothesisSpace
from .rigid3d import (
    _refit,
    min_altitude,
    near_pose,
    pose_manifold,
    pose_to_dict,
)

__all__ = ["Landmark3DSpace"]

#: Observed triplets are matched in chunks so the (triplets, M, M) pair mask stays below this.
MASK_LIMIT = 20_000_000


class Landmark3DSpace(HypothesisSpace):
    """SE(3) poses from triplets of typed landmark observations matched to a 3D map.

    Parameters
    ----------
    positions : ndarray of shape (M, 3)
        Map landmarks in the world frame, metres.
    types : sequence of str, length M
        Their types; observations are matched to landmarks of the same type.
    distance_tolerance : float
        Observed and map pairwise distances of a triplet must agree this well (metres).
    min_altitude : float
        Triplets (observed or map) whose smallest altitude is below this
        (metres) are near-collinear and rejected.
    angle_weight : float
        lambda of the SE(3) distance, metres per radian. A rotation ``phi``
        moves a landmark at range ``r`` by about ``r phi``, so lambda near the
        typical range (a few metres) balances the two parts.
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
    >>> marks = np.array([[0.0, 0, 0], [4.0, 0, 0], [0.0, 3, 0], [4.0, 3, 2]])
    >>> space = Landmark3DSpace(marks, ["L", "L", "T", "post"])
    >>> truth = SE3.from_rt(np.eye(3), [1.0, -1.0, 0.5])
    >>> body = marks - truth[:3, 3]                  # the landmarks seen from the pose
    >>> obs = np.c_[[space.type_id(t) for t in ["L", "L", "T", "post"]], body]
    >>> models, owner = space.solve_minimal(obs, np.array([[0, 2, 3]]))
    >>> len(models), models[0][:3, 3].round(6).tolist()
    (1, [1.0, -1.0, 0.5])
    """

    min_samples = 3
    model_shape = (4, 4)
    name = "pose3d"
    #: Beyond the protocol: :meth:`near_prior` takes a pair of thresholds,
    #: :meth:`correspondences` hands the type-compatible pairs to external estimators.
    declared = Capabilities()

    def __init__(self, positions, types, *, distance_tolerance: float = 0.2,
                 min_altitude: float = 0.1, angle_weight: float = 2.0, metric: str = "relative",
                 reference_points=None, inlier_threshold: float = 0.15):
        self.positions = check_points(positions, "positions", dim=3, min_count=3)
        types = np.asarray([str(t) for t in types])
        if types.shape != (len(self.positions),):
            raise ValueError(f"types: expected {len(self.positions)} type names, one per "
                             f"landmark, got {types.shape[0] if types.ndim else 0}")
        self.types = types
        #: Sorted type names; observation type ids index this tuple.
        self.type_names = tuple(sorted(set(types.tolist())))
        self.type_ids = np.array([self.type_names.index(t) for t in types])
        self.distance_tolerance = check_positive(distance_tolerance, "distance_tolerance")
        self.min_altitude = check_positive(min_altitude, "min_altitude", allow_zero=True)
        self.inlier_threshold = check_positive(inlier_threshold, "inlier_threshold")
        self._manifold = pose_manifold(angle_weight, metric, reference_points)
        diff = self.positions[:, None] - self.positions[None]
        self._map_dist = np.linalg.norm(diff, axis=-1)
        self._by_type = [self.positions[self.type_ids == k] for k in range(len(self.type_names))]

    def __repr__(self) -> str:
        return (f"Landmark3DSpace(landmarks={len(self.positions)}, types={len(self.type_names)}, "
                f"tol={self.distance_tolerance:g}, manifold={self._manifold!r})")

    @property
    def manifold(self) -> SE3:
        return self._manifold

    def type_id(self, name: str) -> int:
        """Index of a type name in :attr:`type_names` (``ValueError`` if the map has none)."""
        try:
            return self.type_names.index(str(name))
        except ValueError:
            raise ValueError(f"type: {str(name)!r} is not a landmark type of the map; "
                             f"expected one of {list(self.type_names)}") from None

    def observations_array(self, observations) -> np.ndarray:
        """``(N, 4)`` rows ``(type_id, x, y, z)`` from ``{"type", "x", "y", "z"}`` dicts.

        Examples
        --------
        >>> space = Landmark3DSpace(np.eye(3), ["a", "b", "b"])
        >>> space.observations_array([{"type": "b", "x": 1, "y": 2, "z": 3}]).tolist()
        [[1.0, 1.0, 2.0, 3.0]]
        """
        rows = []
        for i, ob in enumerate(observations):
            try:
                kind, x, y, z = ob["type"], float(ob["x"]), float(ob["y"]), float(ob["z"])
            except (KeyError, TypeError, ValueError):
                raise ValueError(f"observations: entry {i}: expected {{'type', 'x', 'y', 'z'}} "
                                 f"with numbers, got {ob!r}") from None
            try:
                rows.append([self.type_id(kind), x, y, z])
            except ValueError as exc:
                raise ValueError(f"observations: entry {i}: {exc}") from None
        return check_array(np.array(rows, dtype=float).reshape(-1, 4), "observations")

    def check_data(self, data) -> np.ndarray:
        obs = check_points(data, "observations", dim=4, min_count=self.min_samples)
        ids = obs[:, 0]
        if np.any((ids != np.round(ids)) | (ids < 0) | (ids >= len(self.type_names))):
            raise ValueError("observations: column 0 must be a type id in "
                             f"0..{len(self.type_names) - 1} (index of space.type_names)")
        return obs

    def near_prior(self, prior, models, radius) -> np.ndarray:
        """Models within ``radius`` of ``prior``: a distance or ``(max_translation, max_rotation)``.

        See ``near_pose`` in :mod:`clap_unified.spaces.rigid3d`.
        """
        return near_pose(self.manifold, prior, models, radius)

    def correspondences(self, data):
        """Putative pairs for correspondence estimators: ``(source, target, pairs)``.

        ``source`` are the detections (body frame), ``target`` the map
        landmarks, ``pairs`` every (detection, landmark) of the same type.

        Examples
        --------
        >>> space = Landmark3DSpace(np.eye(3), ["a", "b", "b"])
        >>> space.correspondences(np.array([[1.0, 0, 0, 0], [0.0, 1, 1, 1]]))[2].tolist()
        [[0, 1], [0, 2], [1, 0]]
        """
        data = np.asarray(data, dtype=float)
        ids = data[:, 0].astype(int)
        i, m = np.nonzero(ids[:, None] == self.type_ids[None, :])
        return data[:, 1:], self.positions, np.c_[i, m].astype(np.intp)

    # ------------------------------------------------------------------ solver
    def match_triplets(self, data, samples):
        """Type- and distance-compatible map triplets of each observed triplet.

        Parameters
        ----------
        data : ndarray of shape (N, 4)
        samples : ndarray of int, shape (S, 3)
            Observation triplets.

        Returns
        -------
        owner : ndarray of int, shape (K,)
            Row of ``samples`` each match belongs to.
        landmarks : ndarray of int, shape (K, 3)
            Map indices matched, in the order of the sample's observations.
        """
        data = np.asarray(data, dtype=float)
        samples = np.asarray(samples, dtype=np.intp).reshape(-1, 3)
        m = len(self.positions)
        chunk = max(1, MASK_LIMIT // (m * m))
        if len(samples) > chunk:  # bound the (S, M, M) pair mask
            parts = [self.match_triplets(data, samples[i:i + chunk])
                     for i in range(0, len(samples), chunk)]
            owner = np.concatenate([o + i for (o, _), i in
                                    zip(parts, range(0, len(samples), chunk), strict=True)])
            return owner, np.concatenate([lm for _, lm in parts]).reshape(-1, 3)
        ids = data[:, 0].astype(int)
        P = data[samples, 1:]  # (S, 3, 3)
        keep = np.flatnonzero(min_altitude(P) >= self.min_altitude)
        i, j, k = samples[keep].T
        P = P[keep]
        d_ij = np.linalg.norm(P[:, 1] - P[:, 0], axis=1)
        d_ik = np.linalg.norm(P[:, 2] - P[:, 0], axis=1)
        d_jk = np.linalg.norm(P[:, 2] - P[:, 1], axis=1)
        tol, D, T = self.distance_tolerance, self._map_dist, self.type_ids
        # map pairs (a, b) for observation pairs (i, j)
        pair = ((T[None, :, None] == ids[i][:, None, None])
                & (T[None, None, :] == ids[j][:, None, None])
                & (np.abs(D[None] - d_ij[:, None, None]) <= tol))
        s, a, b = np.nonzero(pair)
        distinct = a != b
        s, a, b = s[distinct], a[distinct], b[distinct]
        # third landmark c, compatible with both (i, k) and (j, k)
        third = ((T[None, :] == ids[k[s]][:, None])
                 & (np.abs(D[a] - d_ik[s][:, None]) <= tol)
                 & (np.abs(D[b] - d_jk[s][:, None]) <= tol))
        third[np.arange(len(s)), a] = False
        third[np.arange(len(s)), b] = False
        r, c = np.nonzero(third)
        landmarks = np.stack([a[r], b[r], c], axis=1)
        ok = min_altitude(self.positions[landmarks]) >= self.min_altitude
        return keep[s[r]][ok], landmarks[ok]

    def solve_minimal(self, data, samples):
        """Kabsch poses for every compatible (observed triplet, map triplet) pair, batched."""
        data = np.asarray(data, dtype=float)
        samples = np.asarray(samples, dtype=np.intp).reshape(-1, 3)
        owner, landmarks = self.match_triplets(data, samples)
        if len(owner) == 0:
            return np.empty((0, 4, 4)), owner
        R, t, _ = weighted_kabsch(data[samples[owner], 1:], self.positions[landmarks],
                                  np.ones((len(owner), 3)))
        return pose_from_rt(R, t), owner

    # --------------------------------------------------------------- residuals
    def nearest_landmarks(self, models, data):
        """Nearest map landmark of the observation's type, for every pose.

        :func:`~clap_unified.maps.nearest.nearest_of_type`, the query
        :class:`~clap_unified.spaces.landmarks2d.Landmark2DSpace` shares.

        Returns
        -------
        distance : ndarray of shape (H, N)
            ``inf`` for a type the map does not have.
        index : ndarray of int, shape (H, N)
            Index into ``positions`` (-1 for a type the map does not have).
        """
        data = np.asarray(data, dtype=float)
        return nearest_of_type(transform_points(models, data[:, 1:]), data[:, 0].astype(int),
                               self.positions, self.type_ids)

    def residuals(self, models, data) -> np.ndarray:
        """Distance of each observation (moved to the world) to the nearest landmark of its type."""
        return self.nearest_landmarks(models, data)[0]

    def refit(self, data, weights=None, initial=None):
        """Weighted Kabsch to the nearest same-type landmarks under ``initial``.

        Returns None without ``initial``, with fewer than three observations,
        or when the observations are (nearly) collinear.
        """
        data = np.asarray(data, dtype=float)
        if initial is None or len(data) < 3:
            return None
        _, index = self.nearest_landmarks(np.asarray(initial)[None], data)
        if np.any(index < 0):
            return None  # some observation type has no landmark in the map
        return _refit(data[:, 1:], self.positions[index[0]], weights, self.min_altitude)

    def model_to_dict(self, model) -> dict:
        return pose_to_dict(model)

    def default_threshold(self, data) -> float:
        return self.inlier_threshold
