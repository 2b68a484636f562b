"""A walking robot on the field: ground-truth poses and noisy odometry.

The robot walks towards random waypoints on the field at a humanoid's pace,
turning with a bounded rate; its odometry (the motion it believes it made,
as an SE(2) increment in its own frame) is the true increment with noise
proportional to the motion, plus a small bias, as walking odometry drifts.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from .._validation import as_generator, check_int, check_positive
from ..datatypes import freeze_arrays
from ..geometry.lines import wrap_angle
from ..geometry.se2 import SE2
from ..maps.field import Field

__all__ = ["OdometryInput", "Trajectory", "TrajectoryTruth", "walk_trajectory",
           "relative_motion"]


@dataclasses.dataclass(frozen=True)
class OdometryInput:
    """What a tracker may see of a walk: the odometry, nothing else.

    Attributes
    ----------
    odometry : ndarray of shape (F - 1, 3)
        Measured increments ``(dx, dy, dtheta)`` in the robot frame from frame
        ``k`` to ``k + 1`` (noisy, biased, blind to pushes). Read-only.
    dt : float
        Seconds between frames.
    """

    odometry: np.ndarray
    dt: float

    def __post_init__(self):
        freeze_arrays(self)

    @property
    def n_frames(self) -> int:
        return len(self.odometry) + 1


@dataclasses.dataclass(frozen=True)
class TrajectoryTruth:
    """Evaluation data of a walk: for scoring only.

    Attributes
    ----------
    poses : ndarray of shape (F, 3, 3)
        True ``T_field_robot`` at every frame.
    pushes : ndarray of int
        Frames at which an unmodelled push moved the robot.
    """

    poses: np.ndarray
    pushes: np.ndarray

    def __post_init__(self):
        freeze_arrays(self)

    def __len__(self) -> int:
        return len(self.poses)

    @property
    def xytheta(self) -> np.ndarray:
        """True ``(x, y, theta)`` at every frame, ``(F, 3)``."""
        return SE2.to_xytheta(self.poses)


@dataclasses.dataclass(frozen=True)
class Trajectory:
    """A simulated walk: the tracker's ``input`` (odometry) and the ``truth`` (poses), apart.

    Trackers take ``walk.input``; :func:`~clap_unified.localization.tracking.simulate_frames`
    (a simulator) and the error summaries take ``walk.truth``. The start pose
    is not part of the input: a tracker is given it explicitly (robots enter
    a RoboCup match from known positions).

    Attributes
    ----------
    input : OdometryInput
    truth : TrajectoryTruth
    """

    input: OdometryInput
    truth: TrajectoryTruth

    def __len__(self) -> int:
        return len(self.truth)


def relative_motion(a, b) -> np.ndarray:
    """``(dx, dy, dtheta)`` of pose ``b`` in the frame of pose ``a``, batched."""
    return SE2.to_xytheta(SE2().compose(SE2().inverse(a), b))


def walk_trajectory(field: Field, n_frames: int = 300, *, dt: float = 0.2, speed: float = 0.4,
                    turn_rate: float = np.pi / 4, odometry_noise: float = 0.1,
                    odometry_bias: float = 0.02, margin: float = 0.5, start=None,
                    pushes: int = 0, push_size=(0.5, np.pi / 6),
                    rng=None) -> Trajectory:
    """Simulate a robot walking between random waypoints on the field.

    Parameters
    ----------
    field : Field
        Needs ``dimensions`` (length, width).
    n_frames : int
    dt : float
        Seconds per frame (default 5 frames per second).
    speed : float
        Walking speed, m/s.
    turn_rate : float
        Largest heading change, rad/s.
    odometry_noise : float
        Standard deviation of the odometry error as a fraction of the motion.
    odometry_bias : float
        Systematic heading drift, radians per metre walked.
    margin : float
        Waypoints stay this far inside the field lines.
    start : (x, y, theta), optional
        Initial pose; default a random one.
    pushes : int
        Unmodelled disturbances (a push, a fall, a slip on the carpet): at
        this many random frames the robot is displaced by up to
        ``push_size`` (metres, radians) and the odometry does not know.
        ``truth.pushes`` lists the frames.
    rng : None, int or numpy.random.Generator

    Returns
    -------
    Trajectory
        ``input``: the odometry and the frame period; ``truth``: the poses
        and the push frames.

    Examples
    --------
    >>> from clap_unified.localization import load_field
    >>> walk = walk_trajectory(load_field("adult"), 50, rng=0)
    >>> walk.truth.poses.shape, walk.input.odometry.shape
    ((50, 3, 3), (49, 3))
    >>> steps = np.linalg.norm(np.diff(walk.truth.xytheta[:, :2], axis=0), axis=1)
    >>> bool(steps.max() <= 0.4 * 0.2 + 1e-12)
    True
    >>> true_step = relative_motion(walk.truth.poses[0], walk.truth.poses[1])
    >>> np.round(walk.input.odometry[0] - true_step, 3).tolist()
    [0.002, 0.002, 0.017]
    """
    n_frames = check_int(n_frames, "n_frames", minimum=2)
    dt = check_positive(dt, "dt")
    speed = check_positive(speed, "speed")
    turn_rate = check_positive(turn_rate, "turn_rate")
    odometry_noise = check_positive(odometry_noise, "odometry_noise", allow_zero=True)
    rng = as_generator(rng)
    hl = field.dimensions["length"] / 2 - margin
    hw = field.dimensions["width"] / 2 - margin

    def waypoint():
        return rng.uniform([-hl, -hw], [hl, hw])

    if start is None:
        x, y = waypoint()
        theta = rng.uniform(-np.pi, np.pi)
    else:
        x, y, theta = (float(v) for v in start)
    goal = waypoint()
    pushed = (np.sort(rng.choice(np.arange(1, n_frames), size=min(pushes, n_frames - 1),
                                 replace=False)) if pushes else np.zeros(0, int))
    states = np.empty((n_frames, 3))
    walked = np.zeros((n_frames - 1, 3))  # the increments the legs made (no pushes)
    for k in range(n_frames):
        if k in pushed:
            size = rng.uniform(0.5, 1.0) * push_size[0]
            direction = rng.uniform(-np.pi, np.pi)
            x, y = x + size * np.cos(direction), y + size * np.sin(direction)
            theta = float(wrap_angle(theta + rng.choice([-1.0, 1.0]) * rng.uniform(0.5, 1.0)
                                     * push_size[1]))
        states[k] = x, y, theta
        if k == n_frames - 1:
            break
        to_goal = goal - (x, y)
        if np.hypot(*to_goal) < 0.3:
            goal = waypoint()
            to_goal = goal - (x, y)
        bearing = float(wrap_angle(np.arctan2(to_goal[1], to_goal[0]) - theta))
        dtheta = float(np.clip(bearing, -turn_rate * dt, turn_rate * dt))
        # slow down while turning sharply, as a humanoid does
        step = speed * dt * max(0.2, np.cos(bearing))
        walked[k] = step * np.cos(dtheta), step * np.sin(dtheta), dtheta
        theta = float(wrap_angle(theta + dtheta))
        x, y = x + step * np.cos(theta), y + step * np.sin(theta)
    poses = SE2.from_xytheta(states[:, 0], states[:, 1], states[:, 2])
    dist = np.hypot(walked[:, 0], walked[:, 1])
    scale = np.c_[np.abs(walked[:, 0]), np.abs(walked[:, 1]) + 0.1 * dist,
                  np.abs(walked[:, 2]) + 0.1 * dist]
    odo = walked + odometry_noise * scale * rng.standard_normal(walked.shape)
    odo[:, 2] += odometry_bias * dist
    return Trajectory(OdometryInput(odo, dt), TrajectoryTruth(poses, np.asarray(pushed, int)))
