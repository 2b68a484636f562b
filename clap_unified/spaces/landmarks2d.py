"""Hypothesis space of planar robot poses from typed landmark observations.

The original CLAP (RoboCup 2024): a pair of observed field features, matched to
a type-compatible ordered pair of map landmarks, fixes one SE(2) pose in closed
form. Every observation pair times every compatible map pair gives the
candidate set; a pair whose observed separation disagrees with the map
separation is rejected before any pose is solved.

Data are observations ``(N, 3)`` rows ``(type_id, x, y)`` in the robot frame
(x forward, y left, metres), ``type_id`` indexing :data:`LANDMARK_TYPES`.
Models are poses ``T_field_robot`` as SE(2) matrices: a robot-frame point ``p``
is at ``R p + t`` on the field.
"""

from __future__ import annotations

import numpy as np

from .._validation import check_points, check_positive
from ..geometry.rigid import pose_from_rt, transform_points, weighted_kabsch
from ..geometry.se2 import SE2
from ..maps.field import LANDMARK_TYPES, Field
from ..maps.nearest import nearest_of_type
from .base import Capabilities, HypothesisSet, HypothesisSpace

__all__ = ["HOUGH_CELL", "Landmark2DSpace", "observations_array"]

#: Randomized Hough grid cell of planar poses: 0.25 m x 0.25 m x 5 degrees.
HOUGH_CELL = (0.25, 0.25, np.radians(5.0))


def observations_array(observations) -> np.ndarray:
    """``(N, 3)`` array ``(type_id, x, y)`` from a list of ``{"type", "x", "y"}`` dicts.

    Examples
    --------
    >>> observations_array([{"type": "X", "x": 1.0, "y": 2.0}]).tolist()
    [[2.0, 1.0, 2.0]]
    """
    rows = []
    for i, ob in enumerate(observations):
        try:
            kind, x, y = ob["type"], float(ob["x"]), float(ob["y"])
        except (KeyError, TypeError, ValueError):
            raise ValueError(f"observations: entry {i}: expected {{'type', 'x', 'y'}} with "
                             f"numbers, got {ob!r}") from None
        if kind not in LANDMARK_TYPES:
            raise ValueError(f"observations: entry {i}: unknown type {kind!r}; expected one of "
                             f"{list(LANDMARK_TYPES)}")
        rows.append([LANDMARK_TYPES.index(kind), x, y])
    return np.array(rows, dtype=float).reshape(-1, 3)


class Landmark2DSpace(HypothesisSpace):
    """SE(2) poses from pairs of typed landmark observations matched to a field map.

    Parameters
    ----------
    field : Field
        The landmark map.
    distance_tolerance : float
        A pair is solved only if ``|observed separation - map separation|``
        is below this (metres).
    angle_weight : float
        lambda of the SE(2) distance, metres per radian.
    range_noise : (float, float) or None
        ``(sigma0, growth)`` of the detection noise ``sigma(r) = sigma0 +
        growth * r**2`` (the simulator's :class:`~clap_unified.localization.Camera`
        default). The refit weighs each observation by ``1 / sigma(r)**2``;
        ``None`` weighs them equally.
    on_field : bool
        Reject candidate poses outside the field and its border (the robot
        stands on the carpet); needs ``field.dimensions``.

    Examples
    --------
    >>> from clap_unified.maps import load_field
    >>> space = Landmark2DSpace(load_field("adult"))
    >>> truth = SE2.from_xytheta(2.0, -1.0, 0.3)
    >>> marks = space.field.positions[space.field.types == "goal_post"][2:]
    >>> local = (np.linalg.inv(truth) @ np.c_[marks, np.ones(2)].T).T[:, :2]
    >>> obs = np.c_[np.full(2, 3.0), local]
    >>> models, owner = space.solve_minimal(obs, np.array([[0, 1]]))
    >>> np.round(SE2.to_xytheta(models), 3).tolist()  # both goals, both orders of the posts
    [[-2.0, 1.0, -2.842], [2.0, -1.0, 0.3]]
    """

    min_samples = 2
    model_shape = (3, 3)
    name = "pose2d"
    #: A prior's association gives the local candidates; the refit reuses the
    #: inlier test's association; the randomized Hough grid is ``(x, y, theta)``.
    declared = Capabilities(prior_hypotheses=True, local_refit=True, grid=True)

    def __init__(self, field: Field, *, distance_tolerance: float = 0.3,
                 angle_weight: float = 1.0, range_noise=(0.01, 0.004), on_field: bool = True):
        self.field = field
        if range_noise is not None:
            range_noise = (check_positive(range_noise[0], "range_noise"),
                           check_positive(range_noise[1], "range_noise", allow_zero=True))
        self.range_noise = range_noise
        self.bounds = None
        if on_field:
            dims = field.dimensions
            try:
                border = dims.get("border", 0.0)
                self.bounds = (dims["length"] / 2 + border, dims["width"] / 2 + border)
            except KeyError:
                raise ValueError("on_field: the field has no length/width dimensions; "
                                 "pass on_field=False") from None
        self.distance_tolerance = check_positive(distance_tolerance, "distance_tolerance")
        self._manifold = SE2(angle_weight=angle_weight)
        self._type_ids = np.array([LANDMARK_TYPES.index(t) for t in field.types])
        a, b = np.nonzero(~np.eye(len(field.positions), dtype=bool))  # ordered map pairs
        self._map_pairs = (a, b, np.linalg.norm(field.positions[b] - field.positions[a], axis=1),
                           self._type_ids[a], self._type_ids[b])
        self._pairs = {}  # n -> upper-triangle index pairs of n associated observations

    def __repr__(self) -> str:
        return f"Landmark2DSpace(field={self.field.name!r}, tol={self.distance_tolerance:g})"

    @property
    def manifold(self) -> SE2:
        return self._manifold

    def check_data(self, data) -> np.ndarray:
        obs = check_points(data, "observations", dim=3, min_count=self.min_samples)
        ids = obs[:, 0]
        if np.any((ids != np.round(ids)) | (ids < 0) | (ids >= len(LANDMARK_TYPES))):
            raise ValueError("observations: column 0 must be a type id in "
                             f"0..{len(LANDMARK_TYPES) - 1}")
        return obs

    def solve_minimal(self, data, samples):
        """Every type-compatible ordered map pair for every observation pair, batched."""
        data = np.asarray(data, dtype=float)
        ids = data[:, 0].astype(int)
        a, b, sep_map, ta, tb = self._map_pairs
        i, j = samples[:, 0], samples[:, 1]
        sep_obs = np.linalg.norm(data[j, 1:] - data[i, 1:], axis=1)
        ok = ((ids[i][:, None] == ta) & (ids[j][:, None] == tb) &
              (np.abs(sep_obs[:, None] - sep_map) <= self.distance_tolerance) &
              (sep_obs[:, None] > 1e-9))
        s, k = np.nonzero(ok)
        return self._poses(data[i[s], 1:], data[j[s], 1:], a[k], b[k], s)

    def _poses(self, p, q, a, b, owner):
        """Poses mapping observed points ``p, q`` onto map landmarks ``a, b`` (closed form)."""
        maps = self.field.positions
        m, n = maps[a], maps[b]
        theta = (np.arctan2(*(n - m)[:, ::-1].T) - np.arctan2(*(q - p)[:, ::-1].T))
        c, sn = np.cos(theta), np.sin(theta)
        mid_obs, mid_map = (p + q) / 2, (m + n) / 2
        tx = mid_map[:, 0] - (c * mid_obs[:, 0] - sn * mid_obs[:, 1])
        ty = mid_map[:, 1] - (sn * mid_obs[:, 0] + c * mid_obs[:, 1])
        if self.bounds is not None:
            inside = (np.abs(tx) <= self.bounds[0]) & (np.abs(ty) <= self.bounds[1])
            if not inside.all():
                tx, ty, theta, owner = tx[inside], ty[inside], theta[inside], owner[inside]
                c, sn = c[inside], sn[inside]
        if not (np.isfinite(tx).all() and np.isfinite(ty).all() and np.isfinite(theta).all()):
            return SE2.from_xytheta(tx, ty, theta), owner  # raises, naming the value
        # SE2.from_xytheta(tx, ty, theta) from the cosines and sines already at hand
        T = np.zeros((len(theta), 3, 3))
        T[:, 0, 0], T[:, 0, 1], T[:, 0, 2] = c, -sn, tx
        T[:, 1, 0], T[:, 1, 1], T[:, 1, 2] = sn, c, ty
        T[:, 2, 2] = 1.0
        return T, owner

    def associate(self, data, pose, gate: float) -> np.ndarray:
        """Map landmark of each observation under ``pose``: the nearest of its type.

        Returns
        -------
        ndarray of int, shape (N,)
            Landmark index, -1 where none of the observation's type lies within
            ``gate`` metres.
        """
        data = np.asarray(data, dtype=float)
        world = self._world(np.asarray(pose)[None], data)[0]
        diff = world[:, None, :] - self.field.positions[None]
        d2 = np.einsum("nmk,nmk->nm", diff, diff)
        d2[data[:, 0].astype(int)[:, None] != self._type_ids[None]] = np.inf
        return np.where(d2.min(axis=1) <= gate**2, d2.argmin(axis=1), -1)

    def hypotheses(self, data, n: int, *, rng=None, prior=None, radius=None,
                   **sampling) -> HypothesisSet:
        """Candidate poses: with a ``prior``, those of the association it implies.

        Without a prior, every type-compatible map pair for every observation
        pair (the base default: all pairs while there are no more than ``n``,
        otherwise ``n`` random pairs). With one, :meth:`local_hypotheses` with
        the gate ``radius`` (metres).
        """
        if prior is None:
            return super().hypotheses(data, n, rng=rng, **sampling)
        if sampling:
            raise ValueError(f"sampling: the {self.name} space takes no sampling options, "
                             f"got {sorted(sampling)}")
        if radius is None:
            raise ValueError("radius: a prior needs a radius (the association gate, metres)")
        return self.local_hypotheses(data, prior, gate=check_positive(radius, "radius"))

    def hough_grid(self):
        """``(x, y, theta)`` coordinates for the randomized Hough grid; theta has period 2 pi."""
        return SE2.to_xytheta, (None, None, 2 * np.pi)

    def default_cell_size(self, data=None):
        """:data:`HOUGH_CELL`: 0.25 m x 0.25 m x 5 degrees."""
        return HOUGH_CELL

    def local_hypotheses(self, data, pose, gate: float) -> HypothesisSet:
        """Candidates consistent with a prior: one pose per pair of associated observations.

        Local mode needs only the candidates near the prior, and those come
        from the association the prior implies: each observation is paired
        with its nearest same-type landmark under ``pose`` (within ``gate``
        metres), and every pair of associated observations whose separation
        agrees with its landmarks' gives one pose, instead of every
        type-compatible map pair.

        Examples
        --------
        >>> from clap_unified.maps import load_field
        >>> space = Landmark2DSpace(load_field("adult"))
        >>> truth = SE2.from_xytheta(4.0, 1.0, 0.1)
        >>> marks = space.field.positions[space.field.types == "goal_post"][2:]
        >>> local = (np.linalg.inv(truth) @ np.c_[marks, np.ones(2)].T).T[:, :2]
        >>> obs = np.c_[np.full(2, 3.0), local]
        >>> hyps = space.local_hypotheses(obs, SE2.from_xytheta(3.8, 1.2, 0.15), gate=1.0)
        >>> np.round(SE2.to_xytheta(hyps.models), 3).tolist()
        [[4.0, 1.0, 0.1]]
        """
        data = np.asarray(data, dtype=float)
        mark = self.associate(data, pose, gate)
        idx = np.flatnonzero(mark >= 0)
        pairs = self._pairs.get(len(idx))
        if pairs is None:
            pairs = self._pairs[len(idx)] = np.triu_indices(len(idx), 1)
        i, j = idx[pairs[0]], idx[pairs[1]]
        maps = self.field.positions
        sep_obs = np.linalg.norm(data[j, 1:] - data[i, 1:], axis=1)
        sep_map = np.linalg.norm(maps[mark[j]] - maps[mark[i]], axis=1)
        ok = (np.abs(sep_obs - sep_map) <= self.distance_tolerance) & (sep_obs > 1e-9)
        i, j = i[ok], j[ok]
        models, owner = self._poses(data[i, 1:], data[j, 1:], mark[i], mark[j],
                                    np.arange(len(i)))
        samples = np.stack((i, j), axis=1)[owner]
        n_pairs = len(data) * (len(data) - 1) // 2
        return HypothesisSet(models, samples, n_pairs, n_pairs - len(models), True, self)

    def _world(self, models, data):
        return transform_points(models, data[:, 1:])

    def _nearest_landmarks(self, world, ids):
        """Nearest map landmark of the same type for observations on the field.

        Parameters
        ----------
        world : ndarray of shape (H, N, 2)
            Observations moved to the field by H poses.
        ids : ndarray of int, shape (N,)

        Returns
        -------
        distance : ndarray of shape (H, N)
            ``inf`` where the map has no landmark of that type.
        target : ndarray of shape (H, N, 2)
            The nearest landmark (NaN where there is none).

        See :func:`~clap_unified.maps.nearest.nearest_of_type`, the query
        :class:`~clap_unified.spaces.Landmark3DSpace` shares.
        """
        distance, index = nearest_of_type(world, ids, self.field.positions, self._type_ids)
        target = self.field.positions[index]
        target[index < 0] = np.nan
        return distance, target

    def residuals(self, models, data) -> np.ndarray:
        """Distance of each observation (moved to the field) to the nearest landmark of its type."""
        data = np.asarray(data, dtype=float)
        return self._nearest_landmarks(self._world(models, data), data[:, 0].astype(int))[0]

    def refit(self, data, weights=None, initial=None):
        """Weighted least-squares pose (2D Kabsch) to the nearest same-type landmarks.

        Weights multiply the range-noise weights ``1 / sigma(r)**2`` (see
        ``range_noise``).

        The association needs a pose: each observation is moved to the field by
        ``initial`` and paired with the nearest landmark of its type. Returns
        None without ``initial``, with fewer than two observations, or when
        the observations coincide.
        """
        data = np.asarray(data, dtype=float)
        if initial is None or len(data) < 2:
            return None
        w = np.ones(len(data)) if weights is None else np.asarray(weights, dtype=float)
        w = self._noise_weights(w, data)
        distance, target = self._nearest_landmarks(self._world(initial, data),
                                                   data[:, 0].astype(int))
        if not np.all(np.isfinite(distance)):
            return None  # some observation type has no landmark in the map
        return self._kabsch(data[:, 1:], target[0], w)

    def refit_steps(self, data, threshold: float):
        """Inlier test and refit sharing one association pass per pose.

        The functions ``inliers(model)`` and ``refit(inliers, model)`` give
        the results of :func:`~clap_unified.refine.inliers_of` and
        ``refit(data[inliers], initial=model)``; the refit reuses the nearest
        landmarks found for the inlier test of the same model instead of
        searching them again (see :func:`~clap_unified.refine.refit_on_inliers`).

        Parameters
        ----------
        data : ndarray of shape (N, 3)
            Observations ``(type_id, x, y)``.
        threshold : float
            Inlier distance to a landmark of the same type (metres).

        Returns
        -------
        inliers : callable
            ``inliers(model) -> ndarray of bool, shape (N,)``.
        refit : callable
            ``refit(inliers, model) -> ndarray of shape (3, 3) or None``.

        Examples
        --------
        >>> from clap_unified.maps import load_field
        >>> space = Landmark2DSpace(load_field("adult"))
        >>> marks = space.field.positions[:4]
        >>> truth = SE2.from_xytheta(1.0, 2.0, 0.1)
        >>> local = (np.linalg.inv(truth) @ np.c_[marks, np.ones(4)].T).T[:, :2]
        >>> ids = [LANDMARK_TYPES.index(t) for t in space.field.types[:4]]
        >>> obs = np.c_[ids, local]
        >>> inliers, refit = space.refit_steps(obs, 0.3)
        >>> start = SE2.from_xytheta(1.05, 1.95, 0.12)
        >>> inl = inliers(start)
        >>> bool(np.array_equal(refit(inl, start), space.refit(obs[inl], initial=start)))
        True
        """
        data = np.asarray(data, dtype=float)
        ids = data[:, 0].astype(int)
        w_all = self._noise_weights(np.ones(len(data)), data)
        last = [None, None]  # model of the latest inlier test and its nearest landmarks

        def inliers(model):
            distance, target = self._nearest_landmarks(self._world(model, data), ids)
            last[0], last[1] = model, target[0]
            return distance[0] < threshold

        def refit(inl, model):
            if last[0] is not model:
                return self.refit(data[inl], initial=model)
            sub = data[inl]
            if len(sub) < 2:
                return None
            # inliers lie within the threshold of a landmark: every target exists
            return self._kabsch(sub[:, 1:], last[1][inl], w_all[inl])

        return inliers, refit

    def _noise_weights(self, w, data):
        """``w`` times the range-noise weights ``1 / sigma(r)**2`` of the observations."""
        if self.range_noise is None:
            return w
        r2 = np.einsum("ij,ij->i", data[:, 1:], data[:, 1:])
        with np.errstate(over="ignore"):  # a range beyond ~1e77 m: sigma inf, weight 0
            return w / (self.range_noise[0] + self.range_noise[1] * r2) ** 2

    @staticmethod
    def _kabsch(src, target, w):
        """Weighted 2D Kabsch pose taking ``src`` onto ``target``; None when degenerate.

        :func:`~clap_unified.geometry.rigid.weighted_kabsch`, shared with the 3D spaces.
        """
        R, t, H = weighted_kabsch(src, target, w)
        if not np.linalg.norm(H) > 1e-12:  # also None for NaN (zero weights)
            return None
        return pose_from_rt(R, t)

    def model_to_dict(self, model) -> dict:
        x, y, theta = SE2.to_xytheta(model)
        return {"x": float(x), "y": float(y), "theta": float(theta)}

    def default_threshold(self, data) -> float:
        return 0.3
