"""Simulated 6-DoF localization scenes: a MoCap-like trajectory and typed detections.

The paper's MoCap recordings are not public, so this module simulates them:

* :func:`mocap_trajectory`: ground-truth poses ``T_world_body`` of a humanoid's
  head walking a loop on the lab field (body frame: x forward, y left, z up),
  with the head height bobbing and small roll and pitch sway at the step
  frequency, as a motion-capture system records them;
* :func:`simulate_detections`: the landmarks in the camera's view cone,
  detected with probability ``1 - miss_rate``, reported in the body frame
  with isotropic Gaussian noise ``sigma + range_growth * r``, plus false
  detections so that a fraction ``outlier_ratio`` of all detections is wrong.

Two kinds of false detection: ``"random"`` (a random type at a random place
in the view cone) and ``"wrong_type"`` (a visible landmark reported with
another type). Everything is seeded.

Each frame is a :class:`Detections3D` with two frozen parts: ``input``, what
an estimator may see (the typed detections and, on request, a pose guess and
the association a front end derives from it), and ``truth``, for scoring only
(the true pose, the landmark and kind behind each detection, the noise-free
points).

**Putative association.** Earlier versions attached to every detection "the
map landmark a front end would pair it with": the *true* landmark for a
correct detection, a random one of its type for a false one. The lab's
landmarks are typed but not identified (several L corners, several markers),
so no real front end can know which L corner it sees without already knowing
the pose: that association was derived from the truth, and an estimator fed it
got every correct detection correctly matched for free. It is gone. The
association now comes from what a tracking front end has: a pose guess
(``prior_error``: the true pose moved by a stated error in a random
direction, as a filter's prediction would be) and, for each detection, the
nearest map landmark of its reported type under that guess
(:func:`associate_nearest`). Both are input; how many of the resulting
correspondences are wrong is measured against ``truth.landmark``, not set.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validation import as_generator, check_fraction, check_int, check_positive
from ..datatypes import freeze_arrays, readonly
from ..geometry.se3 import SE3
from ..geometry.so3 import so3_exp
from .map3d import LandmarkMap3D

__all__ = ["View3D", "Detections3D", "DetectionInput3D", "DetectionTruth3D", "mocap_trajectory",
           "simulate_detections", "associate_nearest", "correspondence_scene"]


@dataclass(frozen=True)
class View3D:
    """The camera's view cone and noise.

    Parameters
    ----------
    hfov, vfov : float
        Horizontal and vertical field of view, radians.
    min_range, max_range : float
        Metres.
    sigma : float
        Position noise (per axis) at zero range, metres.
    range_growth : float
        Noise growth per metre of range: ``sigma(r) = sigma + range_growth * r``.
    """

    hfov: float = np.radians(120.0)
    vfov: float = np.radians(90.0)
    min_range: float = 0.3
    max_range: float = 9.0
    sigma: float = 0.01
    range_growth: float = 0.003

    def __post_init__(self):
        for name in ("hfov", "vfov", "max_range"):
            check_positive(getattr(self, name), name)
        for name in ("min_range", "sigma", "range_growth"):
            check_positive(getattr(self, name), name, allow_zero=True)
        if self.min_range >= self.max_range:
            raise ValueError("min_range: must be below max_range")

    def sees(self, body) -> np.ndarray:
        """Which body-frame points ``(N, 3)`` are inside the view cone."""
        p = np.asarray(body, dtype=float).reshape(-1, 3)
        r = np.linalg.norm(p, axis=1)
        az = np.arctan2(p[:, 1], p[:, 0])
        el = np.arctan2(p[:, 2], np.hypot(p[:, 0], p[:, 1]))
        return ((r >= self.min_range) & (r <= self.max_range) & (np.abs(az) <= self.hfov / 2)
                & (np.abs(el) <= self.vfov / 2))

    def random_points(self, n: int, rng) -> np.ndarray:
        """``n`` random body-frame points inside the view cone."""
        r = rng.uniform(max(self.min_range, 0.5), self.max_range, n)
        az = rng.uniform(-self.hfov / 2, self.hfov / 2, n)
        el = rng.uniform(-self.vfov / 2, self.vfov / 2, n)
        return np.c_[r * np.cos(el) * np.cos(az), r * np.cos(el) * np.sin(az), r * np.sin(el)]


@dataclass(frozen=True)
class DetectionInput3D:
    """What a localizer may see of one frame.

    Attributes
    ----------
    data : ndarray of shape (N, 4)
        Rows ``(type_id, x, y, z)`` in the body frame; ``type_id`` indexes
        ``type_names``.
    type_names : tuple of str
        Sorted type names of the map (as :class:`~clap_unified.spaces.Landmark3DSpace`).
    prior : ndarray of shape (4, 4) or None
        A pose guess ``T_world_body`` (a tracking filter's prediction), when
        the frame was simulated with ``prior_error``.
    association : ndarray of int, shape (N,), or None
        The front end's putative map landmark of each detection: the nearest
        landmark of its reported type once moved by ``prior``
        (:func:`associate_nearest`); None without a prior.
    """

    data: np.ndarray
    type_names: tuple
    prior: np.ndarray | None = None
    association: np.ndarray | None = None

    def __post_init__(self):
        object.__setattr__(self, "type_names", tuple(self.type_names))
        freeze_arrays(self)

    def __len__(self) -> int:
        return len(self.data)

    def to_json(self) -> list[dict]:
        """The detections as the command line reads them: ``[{"type", "x", "y", "z"}, ...]``."""
        return [{"type": self.type_names[int(k)], "x": float(x), "y": float(y), "z": float(z)}
                for k, x, y, z in self.data]

    def correspondences(self, landmark_map: LandmarkMap3D) -> np.ndarray:
        """Putative correspondences ``(N, 6)``: body point, associated map point.

        Raises
        ------
        ValueError
            Without an association (simulate with ``prior_error``).
        """
        if self.association is None:
            raise ValueError("association: none in this input; simulate the frame with "
                             "prior_error= or call associate_nearest with a pose guess")
        return np.c_[self.data[:, 1:], landmark_map.positions[self.association]]


@dataclass(frozen=True)
class DetectionTruth3D:
    """Evaluation data of one frame: for scoring only, never for an estimator.

    Attributes
    ----------
    pose : ndarray of shape (4, 4)
        True ``T_world_body``.
    landmark : ndarray of int, shape (N,)
        True map landmark of each detection (row of ``input.data``), -1 for a
        false one.
    kind : ndarray of str, shape (N,)
        ``"landmark"``, ``"random"`` or ``"wrong_type"``.
    clean : ndarray of shape (N, 3)
        Noise-free body-frame position of the landmark behind each detection
        (the real landmark of a ``"wrong_type"`` one); NaN for ``"random"``.
    """

    pose: np.ndarray
    landmark: np.ndarray
    kind: np.ndarray
    clean: np.ndarray

    def __post_init__(self):
        freeze_arrays(self)

    @property
    def is_outlier(self) -> np.ndarray:
        """True for false detections."""
        return self.landmark < 0

    @property
    def outlier_ratio(self) -> float:
        return float(np.mean(self.is_outlier)) if len(self.landmark) else 0.0


@dataclass(frozen=True)
class Detections3D:
    """One simulated frame: the estimator's ``input`` and the evaluation ``truth``, apart.

    Attributes
    ----------
    input : DetectionInput3D
    truth : DetectionTruth3D
    """

    input: DetectionInput3D
    truth: DetectionTruth3D

    def __post_init__(self):
        if not isinstance(self.input, DetectionInput3D):
            raise ValueError(f"input: expected a DetectionInput3D, got {type(self.input).__name__}")
        if not isinstance(self.truth, DetectionTruth3D):
            raise ValueError(f"truth: expected a DetectionTruth3D, got {type(self.truth).__name__}")

    def __len__(self) -> int:
        return len(self.input)


def associate_nearest(data, landmark_map: LandmarkMap3D, prior) -> np.ndarray:
    """Each detection's nearest map landmark of its type once moved by the pose guess ``prior``.

    The association a tracking front end makes from what it has (the
    detections, the map, a predicted pose); no truth enters.

    Parameters
    ----------
    data : ndarray of shape (N, 4)
        Rows ``(type_id, x, y, z)``, ``type_id`` indexing the map's sorted type names.
    landmark_map : LandmarkMap3D
    prior : ndarray of shape (4, 4)
        ``T_world_body`` guess.

    Returns
    -------
    ndarray of int, shape (N,)

    Examples
    --------
    >>> from clap_unified.localization.map3d import LandmarkMap3D
    >>> m = LandmarkMap3D(np.array(["a", "a", "b"]), np.array([[0.0, 0, 0], [2, 0, 0], [1, 1, 0]]))
    >>> associate_nearest(np.array([[0.0, 1.8, 0.1, 0.0], [1.0, 0.9, 1.0, 0.0]]), m,
    ...                   np.eye(4)).tolist()
    [1, 2]
    """
    names = tuple(sorted(set(landmark_map.types.tolist())))
    tid = np.array([names.index(t) for t in landmark_map.types])
    d = np.asarray(data, dtype=float).reshape(-1, 4)
    T = SE3().validate(prior, "prior")
    if T.shape != (4, 4):
        raise ValueError(f"prior: expected one 4 x 4 pose, got shape {T.shape}")
    ids = d[:, 0].astype(int)
    if np.any((ids < 0) | (ids >= len(names))):
        raise ValueError(f"data: type ids must be in [0, {len(names)})")
    world = d[:, 1:] @ T[:3, :3].T + T[:3, 3]
    dist = np.linalg.norm(world[:, None, :] - landmark_map.positions[None, :, :], axis=2)
    dist[ids[:, None] != tid[None, :]] = np.inf
    return np.argmin(dist, axis=1).astype(int)


def mocap_trajectory(n_frames: int = 100, *, height: float = 1.25, rng=None) -> np.ndarray:
    """Ground-truth head poses ``T_world_body`` of a robot walking a loop on the lab half-field.

    The robot walks an ellipse around ``(3.5, 0)`` (semi-axes 2 m and 2.5 m)
    looking roughly towards the goal at ``x = 7`` (yaw swinging +-40 degrees
    around that direction), the camera pitched 15 degrees down, with step-rate
    bobbing (+-2 cm) and sway (roll +-2, pitch +-3 degrees) and a little
    seeded jitter, as a motion-capture system would record.

    Parameters
    ----------
    n_frames : int
    height : float
        Mean head height, metres.
    rng : None, int or numpy.random.Generator

    Returns
    -------
    ndarray of shape (n_frames, 4, 4)
        Read-only. Ground truth only (what the simulated MoCap records):
        :func:`simulate_detections` turns a pose into a frame whose ``input``
        is all an estimator may see.

    Examples
    --------
    >>> T = mocap_trajectory(5, rng=0)
    >>> T.shape, bool(np.all(np.abs(T[:, 2, 3] - 1.25) < 0.05))
    ((5, 4, 4), True)
    """
    n = check_int(n_frames, "n_frames", minimum=1)
    height = check_positive(height, "height")
    g = as_generator(rng)
    s = np.arange(n) / n
    x = 3.5 + 2.0 * np.cos(2 * np.pi * s)
    y = 2.5 * np.sin(2 * np.pi * s)
    steps = 2 * np.pi * 12 * s  # twelve steps per lap
    to_goal = np.arctan2(-y, 7.0 - x)
    yaw = to_goal + np.radians(40.0) * np.sin(2 * np.pi * 3 * s) + g.normal(0, 0.02, n)
    pitch = np.radians(15.0) + np.radians(3.0) * np.sin(steps) + g.normal(0, 0.005, n)
    roll = np.radians(2.0) * np.sin(steps / 2) + g.normal(0, 0.005, n)
    z = height + 0.02 * np.cos(steps) + g.normal(0, 0.002, n)
    ez = np.array([0.0, 0.0, 1.0])
    ey = np.array([0.0, 1.0, 0.0])
    ex = np.array([1.0, 0.0, 0.0])
    R = so3_exp(yaw[:, None] * ez) @ so3_exp(pitch[:, None] * ey) @ so3_exp(roll[:, None] * ex)
    return readonly(SE3.from_rt(R, np.c_[x, y, z]))


def simulate_detections(landmark_map: LandmarkMap3D, pose, *, outlier_ratio: float = 0.0,
                        view: View3D | None = None, miss_rate: float = 0.1,
                        wrong_type_fraction: float = 0.3, prior_error=None,
                        rng=None) -> Detections3D:
    """Typed detections of the map from one pose, with noise, misses and false detections.

    Parameters
    ----------
    landmark_map : LandmarkMap3D
    pose : ndarray of shape (4, 4)
        True ``T_world_body``.
    outlier_ratio : float in [0, 1)
        Fraction of all detections that are false: ``round(n_true * o / (1 - o))``
        false detections are added to the ``n_true`` correct ones.
    view : View3D, optional
    miss_rate : float in [0, 1)
        Probability that a visible landmark is not detected.
    wrong_type_fraction : float in [0, 1]
        Share of false detections that are real landmarks with a wrong type
        (the rest are random points in the view cone with a random type).
    prior_error : (float, float), optional
        ``(metres, radians)``: also hand the estimator a pose guess this far
        from the truth (translation and rotation of exactly these sizes, in
        random directions, drawn after the detections so that they do not
        change) and the association a front end makes with it
        (:func:`associate_nearest`), in ``input.prior`` and ``input.association``.
    rng : None, int or numpy.random.Generator

    Returns
    -------
    Detections3D
        ``input``: detections in random order (and the guess and association
        when asked for); ``truth``: the pose, the landmark, kind and
        noise-free point behind each detection.

    Examples
    --------
    >>> from clap_unified.localization.map3d import lab_map
    >>> T = mocap_trajectory(10, rng=0)[3]
    >>> det = simulate_detections(lab_map(), T, outlier_ratio=0.6, rng=1)
    >>> len(det.input), round(det.truth.outlier_ratio, 2)
    (37, 0.59)
    """
    o = check_fraction(outlier_ratio, "outlier_ratio")
    miss = check_fraction(miss_rate, "miss_rate")
    wt = check_fraction(wrong_type_fraction, "wrong_type_fraction", inclusive=(True, True))
    view = View3D() if view is None else view
    T = SE3().validate(pose, "pose")
    if T.shape != (4, 4):
        raise ValueError(f"pose: expected one 4 x 4 pose, got shape {T.shape}")
    if prior_error is not None:
        try:
            err_t, err_r = (float(v) for v in prior_error)
        except (TypeError, ValueError):
            raise ValueError(f"prior_error: expected (metres, radians), "
                             f"got {prior_error!r}") from None
        check_positive(err_t, "prior_error", allow_zero=True)
        check_positive(err_r, "prior_error", allow_zero=True)
    g = as_generator(rng)
    names = tuple(sorted(set(landmark_map.types.tolist())))
    tid = np.array([names.index(t) for t in landmark_map.types])
    R, t = T[:3, :3], T[:3, 3]
    body = (landmark_map.positions - t) @ R  # R^T (q - t)
    seen = np.flatnonzero(view.sees(body) & (g.random(len(body)) >= miss))
    r = np.linalg.norm(body[seen], axis=1)
    noisy = body[seen] + g.normal(size=(len(seen), 3)) * (view.sigma
                                                          + view.range_growth * r)[:, None]
    n_true = len(seen)
    n_false = int(round(n_true * o / (1.0 - o)))
    n_wrong = min(int(round(n_false * wt)), n_true) if len(names) > 1 else 0
    n_random = n_false - n_wrong
    # wrong type: a visible landmark reported with another type
    pick = g.choice(seen, n_wrong, replace=True) if n_wrong else np.empty(0, int)
    shift = g.integers(1, len(names), n_wrong) if n_wrong else np.empty(0, int)
    wrong_types = (tid[pick] + shift) % len(names)
    wrong_pts = body[pick] + g.normal(size=(n_wrong, 3)) * view.sigma
    rand_types = g.integers(0, len(names), n_random)
    rand_pts = view.random_points(n_random, g)
    types = np.r_[tid[seen], wrong_types, rand_types]
    points = np.vstack([noisy, wrong_pts, rand_pts]).reshape(-1, 3)
    clean = np.vstack([body[seen], body[pick], np.full((n_random, 3), np.nan)]).reshape(-1, 3)
    landmark = np.r_[seen, np.full(n_false, -1)]
    kind = np.array(["landmark"] * n_true + ["wrong_type"] * n_wrong + ["random"] * n_random)
    order = g.permutation(len(types))
    data = np.c_[types[order], points[order]].astype(float).reshape(-1, 4)
    prior = association = None
    if prior_error is not None:
        axis = g.normal(size=3)
        direction = g.normal(size=3)
        prior = T @ SE3.from_rt(so3_exp(err_r * axis / np.linalg.norm(axis)),
                                err_t * direction / np.linalg.norm(direction))
        association = associate_nearest(data, landmark_map, prior)
    truth = DetectionTruth3D(T.copy(), landmark[order].astype(int), kind[order], clean[order])
    return Detections3D(DetectionInput3D(data, names, prior, association), truth)


def correspondence_scene(n: int, outlier_ratio: float, seed: int):
    """Putative 3D correspondences ``(n, 6)`` rows ``(p_body, q_world)`` and the true pose.

    The pose is frame ``seed % 50`` of :func:`mocap_trajectory` (50 frames,
    ``rng=seed``); ``p`` are random points in the view of :class:`View3D`,
    ``q`` their world positions with the view's range-dependent noise; a
    fraction ``outlier_ratio`` of the ``q`` are replaced by uniform points in
    the lab. The benchmark ``bench/bench_localize3d.py`` and the performance
    chapter use it. The pose is evaluation data: only the correspondences go
    to an estimator.

    Parameters
    ----------
    n : int
        Number of correspondences.
    outlier_ratio : float
        Share of wrong correspondences, in ``[0, 1]``.
    seed : int

    Returns
    -------
    data : ndarray of shape (n, 6)
    truth : ndarray of shape (4, 4)

    Examples
    --------
    >>> data, T = correspondence_scene(50, 0.6, 0)
    >>> data.shape, T.shape
    ((50, 6), (4, 4))
    """
    from .._validation import check_fraction, check_int

    n = check_int(n, "n", minimum=3)
    outlier_ratio = check_fraction(outlier_ratio, "outlier_ratio")
    view = View3D()
    g = np.random.default_rng(seed)
    truth = mocap_trajectory(50, rng=seed)[seed % 50]
    p = view.random_points(n, g)
    r = np.linalg.norm(p, axis=1)
    q = p @ truth[:3, :3].T + truth[:3, 3]
    q += g.normal(size=(n, 3)) * (view.sigma + view.range_growth * r)[:, None]
    bad = g.permutation(n)[:int(round(outlier_ratio * n))]
    q[bad] = g.uniform([0.0, -5.0, 0.0], [8.0, 5.0, 2.5], (len(bad), 3))
    return np.c_[p, q], truth
