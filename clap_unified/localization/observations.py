"""Simulated landmark detections of a robot on a RoboCup field.

A robot at pose ``T_field_robot`` (SE(2)) sees, through a camera with a
horizontal field of view and a maximum range, the map landmarks in front of
it. Each visible landmark is detected with probability ``1 - miss_rate`` and
reported in the robot frame (x forward, y left) with noise that grows with
range: stereo depth error grows roughly with the square of the distance, so
the range noise is ``sigma_range + range_growth * r**2`` and the bearing
noise is constant. False detections are then added so that a fraction
``false_positive_rate`` of all detections is false. Three kinds exist:

* ``"random"``: a random type at a random place in the field of view;
* ``"wrong_type"``: a visible landmark reported with another type;
* ``"neighbour"``: a landmark of a neighbouring field (the same layout,
  shifted beside this one), seen across the border.

Everything is seeded.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validation import as_generator, check_fraction, check_int, check_positive
from ..datatypes import freeze_arrays, readonly
from ..geometry.se2 import SE2
from ..maps.field import LANDMARK_TYPES, Field

__all__ = ["Camera", "Observations", "ObservationInput", "ObservationTruth", "frames_at_rates",
           "random_frames", "simulate_observations", "visible_landmarks", "FALSE_POSITIVE_KINDS"]

FALSE_POSITIVE_KINDS = ("random", "wrong_type", "neighbour")


@dataclass(frozen=True)
class Camera:
    """What the robot sees and how well.

    Parameters
    ----------
    fov : float
        Horizontal field of view, radians (default 90 degrees).
    max_range, min_range : float
        Landmarks outside ``[min_range, max_range]`` metres are not seen.
    sigma_range : float
        Range noise at zero distance, metres.
    range_growth : float
        Range noise growth, metres per metre squared: ``sigma(r) = sigma_range
        + range_growth * r**2``.
    sigma_bearing : float
        Bearing noise, radians.
    """

    fov: float = np.radians(90.0)
    max_range: float = 6.0
    min_range: float = 0.3
    sigma_range: float = 0.01
    range_growth: float = 0.004
    sigma_bearing: float = np.radians(0.5)

    def __post_init__(self):
        check_positive(self.fov, "fov")
        if self.fov > 2 * np.pi:
            raise ValueError(f"fov: must be at most 2 pi radians, got {self.fov}")
        check_positive(self.max_range, "max_range")
        check_positive(self.min_range, "min_range", allow_zero=True)
        if self.min_range >= self.max_range:
            raise ValueError("min_range: must be below max_range")
        for name in ("sigma_range", "range_growth", "sigma_bearing"):
            check_positive(getattr(self, name), name, allow_zero=True)

    def range_sigma(self, r):
        """Standard deviation of the range at distance ``r`` (metres)."""
        return self.sigma_range + self.range_growth * np.asarray(r, dtype=float) ** 2

    def sees(self, local) -> np.ndarray:
        """Which robot-frame points ``(N, 2)`` are in the field of view and range."""
        local = np.asarray(local, dtype=float).reshape(-1, 2)
        r = np.hypot(local[:, 0], local[:, 1])
        bearing = np.arctan2(local[:, 1], local[:, 0])
        return (r >= self.min_range) & (r <= self.max_range) & (np.abs(bearing) <= self.fov / 2)


@dataclass(frozen=True)
class ObservationInput:
    """What a localizer may see of one frame: the detections, nothing else.

    Attributes
    ----------
    data : ndarray of shape (N, 3)
        Rows ``(type_id, x, y)`` in the robot frame (``type_id`` indexes
        :data:`~clap_unified.maps.field.LANDMARK_TYPES`): the input of
        :class:`~clap_unified.spaces.landmarks2d.Landmark2DSpace` and of ``localize2d``.
        Read-only.
    """

    data: np.ndarray

    def __post_init__(self):
        object.__setattr__(self, "data", readonly(np.asarray(self.data, float).reshape(-1, 3)))

    def __len__(self) -> int:
        return len(self.data)

    def to_dicts(self) -> list[dict]:
        """The JSON form read by ``clap-unified localize2d``."""
        return [{"type": LANDMARK_TYPES[int(t)], "x": float(x), "y": float(y)}
                for t, x, y in self.data]


@dataclass(frozen=True)
class ObservationTruth:
    """Evaluation data of one frame: for scoring only, never for an estimator.

    Attributes
    ----------
    pose : ndarray of shape (3, 3)
        True ``T_field_robot``.
    landmark : ndarray of int, shape (N,)
        Index of the map landmark behind each detection (row of
        ``input.data``), -1 for a false one.
    kind : ndarray of str, shape (N,)
        ``"true"`` or the false-positive kind (``"random"``, ``"wrong_type"``,
        ``"neighbour"``).
    clean : ndarray of shape (N, 2)
        Noise-free robot-frame position of the landmark behind each
        detection (for ``"wrong_type"`` the real landmark, for
        ``"neighbour"`` the neighbouring field's landmark); NaN for
        ``"random"`` detections, which have no landmark behind them.
    """

    pose: np.ndarray
    landmark: np.ndarray
    kind: np.ndarray
    clean: np.ndarray

    def __post_init__(self):
        freeze_arrays(self)

    @property
    def is_false(self) -> np.ndarray:
        """True for false detections."""
        return self.landmark < 0

    @property
    def false_positive_rate(self) -> float:
        return float(self.is_false.mean()) if len(self.landmark) else 0.0


@dataclass(frozen=True)
class Observations:
    """One simulated frame: the estimator's ``input`` and the evaluation ``truth``, apart.

    Pass ``obs.input`` (or ``obs.input.data``) to an estimator and score with
    ``obs.truth``; the two parts are frozen and their arrays read-only, so
    one cannot stand in for the other.

    Attributes
    ----------
    input : ObservationInput
    truth : ObservationTruth
    """

    input: ObservationInput
    truth: ObservationTruth

    def __post_init__(self):
        if not isinstance(self.input, ObservationInput):
            raise ValueError(f"input: expected an ObservationInput, got "
                             f"{type(self.input).__name__}")
        if not isinstance(self.truth, ObservationTruth):
            raise ValueError(f"truth: expected an ObservationTruth, got "
                             f"{type(self.truth).__name__}")
        if len(self.truth.landmark) != len(self.input):
            raise ValueError("truth: one landmark index per detection expected")

    def __len__(self) -> int:
        return len(self.input)


def visible_landmarks(field: Field, pose, camera: Camera | None = None) -> np.ndarray:
    """Indices of the map landmarks the camera sees from ``pose``.

    Examples
    --------
    >>> from clap_unified.localization import load_field
    >>> f = load_field("adult")
    >>> idx = visible_landmarks(f, SE2.from_xytheta(4.0, 0.0, 0.0))  # facing the goal
    >>> sorted(set(f.types[idx].tolist()))
    ['L', 'T', 'goal_post', 'penalty_mark']
    """
    camera = Camera() if camera is None else camera
    local = _to_robot(field.positions, pose)
    return np.flatnonzero(camera.sees(local))


def _to_robot(points, pose):
    T = np.asarray(pose, dtype=float)
    R, t = T[:2, :2], T[:2, 2]
    return (np.asarray(points, dtype=float) - t) @ R


def _noisy(local, camera, rng):
    r = np.hypot(local[:, 0], local[:, 1])
    b = np.arctan2(local[:, 1], local[:, 0])
    r = np.maximum(r + rng.normal(size=len(r)) * camera.range_sigma(r), 0.0)
    b = b + rng.normal(size=len(b)) * camera.sigma_bearing
    return np.c_[r * np.cos(b), r * np.sin(b)]


def _random_in_view(n, camera, rng):
    r = np.sqrt(rng.uniform(camera.min_range**2, camera.max_range**2, n))
    b = rng.uniform(-camera.fov / 2, camera.fov / 2, n)
    return np.c_[r * np.cos(b), r * np.sin(b)]


def simulate_observations(field: Field, pose, *, camera: Camera | None = None,
                          miss_rate: float = 0.1, false_positive_rate: float = 0.0,
                          false_kinds=FALSE_POSITIVE_KINDS, rng=None) -> Observations:
    """Detections a robot at ``pose`` makes of ``field``'s landmarks.

    Parameters
    ----------
    field : Field
    pose : ndarray of shape (3, 3)
        ``T_field_robot``.
    camera : Camera, optional
    miss_rate : float in [0, 1]
        Probability that a visible landmark is not detected.
    false_positive_rate : float in [0, 1)
        Fraction of the returned detections that are false:
        ``round(n_true * rate / (1 - rate))`` are added (at least one when the
        rate is positive and nothing true is seen).
    false_kinds : sequence of {"random", "wrong_type", "neighbour"}
        Kinds of false detections, drawn uniformly.
    rng : None, int or numpy.random.Generator

    Returns
    -------
    Observations
        ``input.data``: the detections ``(type_id, x, y)`` in a random order,
        all an estimator may see; ``truth``: the pose, the landmark and kind
        behind each detection and its noise-free position, for scoring.

    Examples
    --------
    >>> from clap_unified.localization import load_field
    >>> f = load_field("adult")
    >>> obs = simulate_observations(f, SE2.from_xytheta(3.0, 1.0, 0.2),
    ...                             false_positive_rate=0.4, rng=1)
    >>> len(obs.input), int(obs.truth.is_false.sum())
    (12, 5)
    >>> sorted(set(obs.truth.kind.tolist()))
    ['random', 'true', 'wrong_type']
    """
    camera = Camera() if camera is None else camera
    pose = SE2().validate(pose, "pose")
    miss_rate = check_fraction(miss_rate, "miss_rate")
    fp = check_fraction(false_positive_rate, "false_positive_rate", high=0.99)
    kinds = tuple(false_kinds)
    bad = set(kinds) - set(FALSE_POSITIVE_KINDS)
    if not kinds or bad:
        raise ValueError(f"false_kinds: expected a non-empty subset of {FALSE_POSITIVE_KINDS}, "
                         f"got {false_kinds!r}")
    rng = as_generator(rng)
    type_id = np.array([LANDMARK_TYPES.index(t) for t in field.types])

    seen = visible_landmarks(field, pose, camera)
    seen = seen[rng.random(len(seen)) >= miss_rate]
    clean_true = _to_robot(field.positions[seen], pose).reshape(-1, 2)
    local = _noisy(clean_true, camera, rng)
    rows = [np.c_[type_id[seen], local]]
    landmark = [seen]
    kind = [np.full(len(seen), "true", dtype=object)]
    clean = [clean_true]

    n_false = int(round(len(seen) * fp / (1 - fp))) if fp > 0 else 0
    if fp > 0 and len(seen) == 0:
        n_false = 1
    if n_false:
        chosen = rng.choice(len(kinds), size=n_false)
        for k, name in enumerate(kinds):
            m = int(np.count_nonzero(chosen == k))
            if m == 0:
                continue
            f_rows, f_kind, f_clean = _false(name, m, field, pose, camera, type_id, rng)
            rows.append(f_rows)
            landmark.append(np.full(len(f_rows), -1))
            kind.append(f_kind)
            clean.append(f_clean)
    data = np.concatenate(rows).reshape(-1, 3)
    order = rng.permutation(len(data))
    truth = ObservationTruth(pose.copy(), np.concatenate(landmark)[order].astype(int),
                             np.concatenate(kind)[order].astype(str),
                             np.concatenate(clean).reshape(-1, 2)[order])
    return Observations(ObservationInput(data[order]), truth)


def _false(name, m, field, pose, camera, type_id, rng):
    """``m`` false detections of one kind (falls back to ``random`` when impossible).

    Returns the rows, their kind and the noise-free point behind each (NaN for random ones).
    """
    n_types = len(LANDMARK_TYPES)
    if name == "wrong_type":
        seen = visible_landmarks(field, pose, camera)
        if len(seen):
            pick = seen[rng.integers(0, len(seen), m)]
            shift = rng.integers(1, n_types, m)  # any other type
            wrong = (type_id[pick] + shift) % n_types
            clean = _to_robot(field.positions[pick], pose).reshape(-1, 2)
            local = _noisy(clean, camera, rng)
            return np.c_[wrong, local], np.full(m, name, dtype=object), clean
    elif name == "neighbour":
        dims = field.dimensions
        width = dims.get("width", np.ptp(field.positions[:, 1]))
        border = dims.get("border", 1.0)
        offset = width + 2 * border  # the next field, touchline to touchline
        cands = np.concatenate([field.positions + [0.0, s * offset] for s in (-1, 1)])
        ctype = np.concatenate([type_id, type_id])
        local_all = _to_robot(cands, pose)
        vis = np.flatnonzero(camera.sees(local_all))
        if len(vis):
            pick = vis[rng.integers(0, len(vis), m)]
            local = _noisy(local_all[pick], camera, rng)
            return np.c_[ctype[pick], local], np.full(m, name, dtype=object), local_all[pick]
    local = _random_in_view(m, camera, rng)
    return (np.c_[rng.integers(0, n_types, m), local], np.full(m, "random", dtype=object),
            np.full((m, 2), np.nan))


def _carpet_poses(field: Field, rng, max_draws: int, min_true: int, kept):
    """Uniform poses over the field of play, 0.5 m inside its lines (x, then y, then any
    heading; one draw each), at most ``max_draws`` of them; then a ValueError saying how many
    frames were kept (``kept()``): the pose source of :func:`random_frames` and
    :func:`frames_at_rates`."""
    half_x = field.dimensions["length"] / 2 - 0.5
    half_y = field.dimensions["width"] / 2 - 0.5
    for _ in range(max_draws):
        yield SE2.from_xytheta(rng.uniform(-half_x, half_x), rng.uniform(-half_y, half_y),
                               rng.uniform(-np.pi, np.pi))
    raise ValueError(f"max_draws: {max_draws} poses gave only {kept()} frames with "
                     f"{min_true} real detections; lower min_true")


def random_frames(field: Field, n: int, *, false_positive_rate: float = 0.0,
                  min_true: int = 3, max_draws: int = 100_000, rng=None,
                  **options) -> list[Observations]:
    """``n`` frames from uniformly random poses on the carpet, each seeing ``min_true`` landmarks.

    Poses are drawn uniformly over the field of play, 0.5 m inside its lines
    (x, then y, then any heading; one draw each); a frame in
    which the robot sees fewer than ``min_true`` real landmarks is drawn again.
    That choice is the experiment's (it reads the simulator's truth to pick
    scenes), never an estimator's: each frame's ``input`` is all an estimator
    gets, its ``truth.pose`` scores it.

    Parameters
    ----------
    field : Field
    n : int
        Frames wanted.
    false_positive_rate : float in [0, 1)
    min_true : int
        Real detections a kept frame must have.
    max_draws : int
        Cap on the poses drawn.
    rng : None, int or numpy.random.Generator
    **options
        Passed to :func:`simulate_observations` (``camera``, ``miss_rate``, ...).

    Raises
    ------
    ValueError
        ``max_draws`` poses gave fewer than ``n`` frames.

    Examples
    --------
    >>> from clap_unified.localization import load_field
    >>> frames = random_frames(load_field("adult"), 3, false_positive_rate=0.2, rng=0)
    >>> [int((~f.truth.is_false).sum()) >= 3 for f in frames]
    [True, True, True]
    """
    n = check_int(n, "n", minimum=0)
    rng = as_generator(rng)
    out = []
    poses = _carpet_poses(field, rng, max_draws, min_true, lambda: len(out))
    while len(out) < n:
        pose = next(poses)
        obs = simulate_observations(field, pose, false_positive_rate=false_positive_rate,
                                    rng=rng, **options)
        if np.count_nonzero(~obs.truth.is_false) >= min_true:
            out.append(obs)
    return out


def frames_at_rates(field: Field, n: int, false_positive_rates, *, min_true: int = 3,
                    max_draws: int = 100_000, rng=None,
                    **options) -> list[list[Observations]]:
    """``n`` random frames, each seen at every rate of ``false_positive_rates``.

    The frames are those of :func:`random_frames` (uniform poses, kept when the
    robot sees at least ``min_true`` real landmarks), but every frame is
    simulated once per rate from one seed of its own, so the pose, the misses
    and the noisy true detections are the same at every rate and only the
    false detections differ. Comparing rates on these frames is a paired
    comparison: a change in a share is the false detections', not the luck
    of which poses each rate drew.

    Parameters
    ----------
    field, n, min_true, max_draws, rng, **options
        As in :func:`random_frames`.
    false_positive_rates : sequence of float in [0, 0.99]

    Returns
    -------
    list of list of Observations
        One list of ``n`` frames per rate, in the order of ``false_positive_rates``;
        frame ``k`` has the same pose and true detections in every list (the same set: each
        frame's detections are shuffled on their own).

    Raises
    ------
    ValueError
        ``max_draws`` poses gave fewer than ``n`` frames, or no rate was given.

    Examples
    --------
    >>> from clap_unified.localization import load_field
    >>> at0, at5 = frames_at_rates(load_field("adult"), 2, [0.0, 0.5], rng=0)
    >>> [int(a.truth.is_false.sum()) == 0 for a in at0]
    [True, True]
    >>> def true_rows(o):
    ...     return sorted(map(tuple, o.input.data[~o.truth.is_false].tolist()))
    >>> [true_rows(a) == true_rows(b) for a, b in zip(at0, at5, strict=True)]
    [True, True]
    """
    n = check_int(n, "n", minimum=0)
    try:
        given = np.asarray(false_positive_rates, dtype=float)
    except (TypeError, ValueError):
        given = None
    if given is None or given.ndim != 1 or not given.size:
        raise ValueError(f"false_positive_rates: expected a non-empty sequence of rates in "
                         f"[0, 0.99], got {false_positive_rates!r}")
    rates = [check_fraction(r, "false_positive_rates", high=0.99) for r in given]
    rng = as_generator(rng)
    out = [[] for _ in rates]
    poses = _carpet_poses(field, rng, max_draws, min_true, lambda: len(out[0]))
    while len(out[0]) < n:
        pose = next(poses)
        frame_seed = int(rng.integers(2**63))
        # one seed per frame: simulate_observations draws the misses and the noise of the
        # true detections before the false ones, so they are the same at every rate
        def seen_at(rate, pose=pose, frame_seed=frame_seed):
            return simulate_observations(field, pose, false_positive_rate=rate,
                                         rng=np.random.default_rng(frame_seed), **options)

        first = seen_at(rates[0])
        if np.count_nonzero(~first.truth.is_false) < min_true:
            continue  # a rejected pose is not simulated at the other rates
        for target, obs in zip(out, [first, *map(seen_at, rates[1:])], strict=True):
            target.append(obs)
    return out
