"""Tracking a walking robot: CLAP per frame into an EKF, against Monte Carlo localization.

Both pipelines get the same odometry and the same detections every frame.

* **CLAP + EKF**: the EKF predicts with odometry; CLAP's local mode, around
  the prediction, turns the frame's detections into one pose; the EKF takes
  it if it passes the Mahalanobis gate. After ``lost_after`` frames without an
  accepted pose, CLAP's global mode is asked for every cluster and the filter
  restarts at the cluster nearest to its prediction.
* **MCL**: :class:`~clap_unified.localization.mcl.ParticleFilter` weighs its
  particles by the detections directly.

:func:`tracking_summary` reports position and heading error, divergence
(frames more than 1 m off) and velocity jumps (frames where the estimate
moves more than ``jump`` metres further than the robot did).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from .._validation import as_generator, check_positive
from ..geometry.lines import wrap_angle
from ..geometry.se2 import SE2
from ..maps.field import Field
from ..spaces.landmarks2d import Landmark2DSpace
from .ekf import PoseEKF
from .localize2d import localize2d
from .mcl import ParticleFilter
from .observations import Camera, ObservationInput, Observations, simulate_observations
from .trajectory import OdometryInput, Trajectory, TrajectoryTruth

__all__ = ["TrackingRun", "simulate_frames", "track_clap_ekf", "track_mcl", "tracking_errors",
           "tracking_summary"]


@dataclass
class TrackingRun:
    """Estimates of one tracker along a trajectory.

    Attributes
    ----------
    method : str
    estimates : ndarray of shape (F, 3)
        ``(x, y, theta)`` after each frame.
    seconds : ndarray of shape (F,)
        Wall-clock time of each frame's update (not deterministic).
    accepted : ndarray of bool, shape (F,)
        Frames whose measurement the filter took (CLAP + EKF) or that had
        detections (MCL).
    """

    method: str
    estimates: np.ndarray
    seconds: np.ndarray
    accepted: np.ndarray


def simulate_frames(field: Field, trajectory: Trajectory, *, camera: Camera | None = None,
                    miss_rate: float = 0.1, false_positive_rate: float = 0.0,
                    rng=None) -> list[Observations]:
    """Detections at every true pose of a trajectory (seeded).

    A simulator, so it reads ``trajectory.truth``; each returned
    :class:`~clap_unified.localization.observations.Observations` keeps the
    detections (``.input``, for the trackers) apart from their truth.
    """
    if not isinstance(trajectory, Trajectory):
        raise ValueError(f"trajectory: expected a Trajectory, got {type(trajectory).__name__}")
    rng = as_generator(rng)
    return [simulate_observations(field, T, camera=camera, miss_rate=miss_rate,
                                  false_positive_rate=false_positive_rate, rng=rng)
            for T in trajectory.truth.poses]


def _odometry(odometry) -> OdometryInput:
    if not isinstance(odometry, OdometryInput):
        raise ValueError("odometry: expected the OdometryInput of a walk (walk.input), got "
                         f"{type(odometry).__name__}")
    return odometry


def _initial(initial) -> np.ndarray:
    arr = np.asarray(initial, dtype=float)
    if arr.shape != (3,) or not np.all(np.isfinite(arr)):
        raise ValueError(f"initial: expected finite (x, y, theta), got {initial!r}")
    return arr


def _frame_data(frame) -> np.ndarray:
    """A frame's detections ``(N, 3)``; the truth of a simulated frame is refused."""
    if isinstance(frame, ObservationInput):
        return frame.data
    if isinstance(frame, Observations):
        raise ValueError("frames: pass each frame's .input (an Observations holds the truth)")
    return np.asarray(frame, dtype=float).reshape(-1, 3)


def track_clap_ekf(field: Field, odometry: OdometryInput, frames, *, initial,
                   initial_cov=(0.3, np.pi / 18), measurement_sigma=(0.1, np.pi / 60),
                   min_radius: float = 0.5, max_radius: float = 2.0, lost_after: int = 5,
                   recovery_support: int = 3, space: Landmark2DSpace | None = None) -> TrackingRun:
    """CLAP local mode per frame, fused by a :class:`~clap_unified.localization.ekf.PoseEKF`.

    Parameters
    ----------
    field : Field
    odometry : OdometryInput
        ``walk.input``: its odometry drives the prediction.
    frames : list of ObservationInput or arrays of shape (N, 3)
        Detections of every frame (``obs.input`` of simulated frames).
    initial : (x, y, theta)
        Start of the filter (robots enter a match from known positions).
    initial_cov : (float, float)
        Initial standard deviations, metres and radians.
    measurement_sigma : (float, float)
        Standard deviations of a CLAP pose, metres and radians.
    min_radius, max_radius : float
        The local-mode radius is three standard deviations of the predicted
        position, clipped to this range.
    lost_after : int
        Frames in a row where the global mode finds a convincing pose (a
        cluster of at least ``recovery_support`` candidates) that the filter
        rejects, before the filter restarts there (frames that see too little
        do not count).
    recovery_support : int
    space : Landmark2DSpace, optional
    """
    space = Landmark2DSpace(field) if space is None else space
    odometry = _odometry(odometry)
    check_positive(min_radius, "min_radius")
    sp, sth = initial_cov
    ekf = PoseEKF(_initial(initial), np.diag([sp**2, sp**2, sth**2]))
    R = np.diag([measurement_sigma[0] ** 2] * 2 + [measurement_sigma[1] ** 2])
    n = len(frames)
    est, secs, ok = np.empty((n, 3)), np.empty(n), np.zeros(n, bool)
    rejected = 0
    for k, frame in enumerate(frames):
        t0 = time.perf_counter()
        if k > 0:
            ekf.predict(odometry.odometry[k - 1])
        data = _frame_data(frame)
        radius = float(np.clip(3 * np.sqrt(np.linalg.eigvalsh(ekf.cov[:2, :2])[-1]),
                               min_radius, max_radius))
        if len(data) >= 2:
            res = localize2d(data, space=space, prior=ekf.mean, radius=radius)
            if res.success:
                ok[k] = ekf.update(SE2.to_xytheta(res.model), R)
            if not ok[k]:
                # nothing near the prediction: is there a convincing pose elsewhere?
                glob = localize2d(data, space=space)
                if glob.success and glob.clusters[0].support >= recovery_support:
                    rejected += 1
                    if rejected >= lost_after:
                        ok[k] = _recover(ekf, glob, R, recovery_support)
            if ok[k]:
                rejected = 0
        est[k] = ekf.mean
        secs[k] = time.perf_counter() - t0
    return TrackingRun("CLAP + EKF", est, secs, ok)


def _recover(ekf, res, R, min_support) -> bool:
    """Restart the filter at the convincing global-mode cluster nearest its prediction."""
    poses = [SE2.to_xytheta(c.model) for c in res.clusters if c.support >= min_support]
    best = min(poses, key=lambda p: ekf.mahalanobis2(p, R))
    ekf.reset(best, R * 4)
    return True


def track_mcl(field: Field, odometry: OdometryInput, frames, *, initial,
              n_particles: int = 500, rng=None, **options) -> TrackingRun:
    """Monte Carlo localization fed the same odometry, detections and start as CLAP + EKF."""
    odometry = _odometry(odometry)
    pf = ParticleFilter(field, n_particles, initial=_initial(initial), rng=rng, **options)
    n = len(frames)
    est, secs, ok = np.empty((n, 3)), np.empty(n), np.zeros(n, bool)
    for k, frame in enumerate(frames):
        t0 = time.perf_counter()
        if k > 0:
            pf.predict(odometry.odometry[k - 1])
        data = _frame_data(frame)
        if len(data):
            pf.update(data)
            ok[k] = True
        est[k] = pf.estimate()
        secs[k] = time.perf_counter() - t0
    return TrackingRun("MCL", est, secs, ok)


def _truth(truth) -> TrajectoryTruth:
    if not isinstance(truth, TrajectoryTruth):
        raise ValueError(f"truth: expected a TrajectoryTruth (walk.truth), got "
                         f"{type(truth).__name__}")
    return truth


def tracking_errors(estimates, truth: TrajectoryTruth):
    """Position error (metres) and absolute heading error (radians) per frame."""
    truth = _truth(truth).xytheta
    est = np.asarray(estimates, dtype=float)
    return (np.hypot(*(est[:, :2] - truth[:, :2]).T),
            np.abs(wrap_angle(est[:, 2] - truth[:, 2])))


def tracking_summary(run: TrackingRun, truth: TrajectoryTruth, *, divergence: float = 1.0,
                     jump: float = 0.3) -> dict:
    """Error statistics of one run.

    Returns
    -------
    dict
        ``position_median``, ``position_p95`` (metres), ``heading_median_deg``,
        ``diverged`` (fraction of frames more than ``divergence`` metres off),
        ``jumps`` (frames whose estimated step exceeds the true step by more
        than ``jump`` metres), ``ms_per_frame`` (median, wall clock).
    """
    pos, head = tracking_errors(run.estimates, truth)
    truth = truth.xytheta
    step_err = np.hypot(*(np.diff(run.estimates[:, :2], axis=0)
                          - np.diff(truth[:, :2], axis=0)).T)
    return {
        "position_median": float(np.median(pos)),
        "position_p95": float(np.quantile(pos, 0.95)),
        "heading_median_deg": float(np.degrees(np.median(head))),
        "diverged": float(np.mean(pos > divergence)),
        "jumps": int(np.count_nonzero(step_err > jump)),
        "ms_per_frame": float(np.median(run.seconds) * 1e3),
    }
