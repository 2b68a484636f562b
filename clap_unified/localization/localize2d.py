"""One-frame 2D localization: CLAP, RANSAC and randomized Hough on the same SE(2) candidates.

The original CLAP (RoboCup 2024 AdultSize): every pair of observed field
features, matched to every type-compatible ordered pair of map landmarks whose
separation agrees, gives one candidate pose
(:class:`~clap_unified.spaces.landmarks2d.Landmark2DSpace`). Then any strategy
registered for planar poses reaches consensus over them
(:func:`~clap_unified.localization.core.localize`, hence :func:`~clap_unified.fit`):

* ``"clap"`` finds density centres among the candidates: global mode without a
  prior (every cluster is reported, e.g. the pose and its mirror on the
  point-symmetric field), local mode around a prior (the previous estimate);
* ``"ransac"`` scores every candidate by how many observations land within
  ``threshold`` of a map landmark of their type;
* ``"randomized_hough"`` votes the candidates into an ``(x, y, theta)`` grid.

With a prior, all of them see the same gated candidates (those within
``radius`` of the prior), so they differ only in how they reach consensus.
"""

from __future__ import annotations

import numpy as np

from .._validation import check_positive
from ..geometry.se2 import SE2
from ..maps.field import Field, load_field
from ..presets import get_preset
from ..result import ConsensusResult
from ..spaces.landmarks2d import HOUGH_CELL, Landmark2DSpace, observations_array
from .core import localize
from .observations import ObservationInput, Observations

__all__ = ["HOUGH_CELL", "MIRROR", "as_pose", "localize2d", "observation_data", "pose_error"]

#: The field's 180 degree symmetry about the centre spot: ``MIRROR @ pose`` looks the same.
MIRROR = SE2.from_xytheta(0.0, 0.0, np.pi)


def pose_error(estimate, truth, *, up_to_symmetry: bool = False) -> tuple[float, float]:
    """Position error (metres) and absolute heading error (degrees) of ``truth^-1 estimate``.

    Parameters
    ----------
    estimate, truth : ndarray of shape (3, 3)
        Poses ``T_field_robot``.
    up_to_symmetry : bool
        Score against the closer of ``truth`` and its mirror ``MIRROR @ truth``
        (global localization cannot tell them apart on a symmetric field).

    Examples
    --------
    >>> truth = SE2.from_xytheta(2.0, 1.0, 0.3)
    >>> e = pose_error(MIRROR @ truth, truth)
    >>> round(e[0], 3), round(e[1], 1), pose_error(MIRROR @ truth, truth, up_to_symmetry=True)
    (4.472, 180.0, (0.0, 0.0))
    """
    if up_to_symmetry:
        return min(pose_error(estimate, t) for t in (truth, MIRROR @ truth))
    x, y, th = SE2.to_xytheta(np.linalg.inv(truth) @ estimate)
    return float(np.hypot(x, y)), float(abs(np.degrees(th)))

_SE2 = SE2()  # validates poses (the angle weight plays no part)


def as_pose(pose, name: str = "prior") -> np.ndarray:
    """A pose from ``(x, y, theta)`` or a 3 x 3 SE(2) matrix.

    Examples
    --------
    >>> as_pose((1.0, 2.0, 0.0))[:2, 2].tolist()
    [1.0, 2.0]
    """
    arr = np.asarray(pose, dtype=float)
    if arr.shape == (3,):
        if not np.all(np.isfinite(arr)):
            raise ValueError(f"{name}: expected finite x, y, theta, got {arr.tolist()}")
        return SE2.from_xytheta(*arr)
    return _SE2.validate(arr, name)


def observation_data(observations) -> np.ndarray:
    """``(N, 3)`` rows ``(type_id, x, y)`` from dicts, an :class:`ObservationInput` or an array.

    A whole simulated :class:`Observations` is refused (it carries the truth):
    pass its ``.input``.
    """
    if isinstance(observations, ObservationInput):
        return observations.data
    if isinstance(observations, Observations):
        raise ValueError("observations: pass the simulated frame's .input, not the whole "
                         "Observations (it holds the truth)")
    if isinstance(observations, np.ndarray) and observations.dtype != object:
        arr = np.asarray(observations, dtype=float)
        if arr.ndim != 2 or arr.shape[1] != 3:
            raise ValueError(f"observations: expected shape (N, 3) rows (type_id, x, y), "
                             f"got {arr.shape}")
        return arr
    if not isinstance(observations, (list, tuple)):
        raise ValueError("observations: expected a list of {'type', 'x', 'y'} dicts, "
                         f"got {type(observations).__name__}")
    return observations_array(observations)


def localize2d(observations, field="adult", *, method: str = "clap", prior=None,
               radius: float | None = None, bandwidth: float | None = None,
               threshold: float | None = None, distance_tolerance: float | None = None,
               angle_weight: float | None = None, max_clusters: int | None = None,
               min_support: int | None = None, n_hypotheses: int | None = None,
               cell_size=None, space: Landmark2DSpace | None = None, hypotheses=None,
               rng=None) -> ConsensusResult:
    """Robot pose on the field from one frame of landmark detections.

    Every argument left ``None`` takes the default of the localization preset of
    ``method`` (``get_preset("pose2d", method, task="localize")``,
    :mod:`clap_unified.presets`, the one home of the defaults; the command
    ``clap-unified localize2d`` reads the same): ``radius`` 1 m, ``bandwidth``
    0.25, ``threshold`` 0.3 m, ``max_clusters`` 5, ``min_support`` 1,
    ``n_hypotheses`` 20000, ``cell_size``
    :data:`~clap_unified.spaces.landmarks2d.HOUGH_CELL`; the space's own
    ``distance_tolerance`` and ``angle_weight``
    (:class:`~clap_unified.spaces.landmarks2d.Landmark2DSpace`).

    Parameters
    ----------
    observations : list of dict, ObservationInput or ndarray of shape (N, 3)
        Detections in the robot frame (x forward, y left, metres):
        ``{"type", "x", "y"}`` dicts or rows ``(type_id, x, y)``.
    field : {"adult", "kid"} or Field
    method : str
        A strategy registered for planar poses
        (``strategy_names(space)``): ``"clap"``, ``"ransac"``,
        ``"randomized_hough"``.
    prior : (x, y, theta) or ndarray of shape (3, 3), optional
        Previous estimate. The candidates are then those of the association it
        implies (:meth:`~clap_unified.spaces.landmarks2d.Landmark2DSpace.local_hypotheses`,
        observations within ``radius`` metres of a landmark of their type)
        that lie within ``radius`` of it; CLAP runs in local mode, the other
        strategies see the same candidates.
    radius : float, optional
        Gate around the prior in the SE(2) distance (metres, radians times
        ``angle_weight``).
    bandwidth : float, optional
        CLAP global mode: neighbourhood radius among candidates.
    threshold : float, optional
        An observation is an inlier when it lands this close (metres) to a map
        landmark of its type.
    distance_tolerance : float, optional
        Candidate check: observed and map separations of a pair must agree
        this well (metres).
    angle_weight : float, optional
        lambda of the SE(2) distance, metres per radian.
    max_clusters, min_support : int, optional
        CLAP global mode: clusters reported and the smallest reported
        (``max_clusters`` is also the randomized Hough's peak count).
    n_hypotheses : int, optional
        All observation pairs are enumerated while they give no more than
        this many pairs; beyond, pairs are sampled. Every candidate is used
        (RANSAC scores them all).
    cell_size : (dx, dy, dtheta), optional
        Randomized Hough grid cell (metres, metres, radians; ``2 pi / dtheta`` whole).
    space : Landmark2DSpace, optional
        Reuse a space (and its field) across frames.
    hypotheses : HypothesisSet, optional
        Reuse candidates (e.g. to compare methods on identical candidates).
    rng : None, int or numpy.random.Generator
        Used only when pairs are sampled.

    Returns
    -------
    ConsensusResult
        ``model`` is ``T_field_robot``; ``clusters`` best first;
        ``diagnostics["hypotheses"]`` counts the candidate poses. Fewer than
        two observations, no candidate, or no candidate near the prior give
        ``success=False`` with the reason.

    Examples
    --------
    >>> from clap_unified.localization import simulate_observations, load_field
    >>> f = load_field("adult")
    >>> truth = SE2.from_xytheta(3.0, 1.0, 0.2)
    >>> obs = simulate_observations(f, truth, false_positive_rate=0.4, rng=1)
    >>> res = localize2d(obs.input, f)
    >>> [round(c.support) for c in res.clusters][:2]   # the pose and its mirror, tied
    [20, 20]
    >>> x, y, th = SE2.to_xytheta(localize2d(obs.input, f, prior=(2.9, 1.1, 0.25)).model)
    >>> print(f"{x:.2f} {y:.2f} {th:.2f}")
    2.99 0.99 0.20
    """
    if space is None:
        fld = field if isinstance(field, Field) else load_field(field)
        space = Landmark2DSpace(fld, **{k: v for k, v in (("distance_tolerance",
                                                            distance_tolerance),
                                                           ("angle_weight", angle_weight))
                                        if v is not None})
    data = observation_data(observations)
    preset = get_preset("pose2d", method, task="localize")  # this function's defaults
    args = {**preset.fit, **{k: v for k, v in (("radius", radius), ("threshold", threshold),
                                                ("n_hypotheses", n_hypotheses))
                             if v is not None}}
    radius = check_positive(args["radius"], "radius")
    prior = None if prior is None else as_pose(prior)
    # the options of each strategy this function sets (the others keep their defaults)
    given = {"clap": dict(bandwidth=bandwidth, max_clusters=max_clusters,
                          min_support=min_support),
             "randomized_hough": dict(cell_size=cell_size, num_peaks=max_clusters)}
    own = {**preset.options,
           **{k: v for k, v in given.get(method, {}).items() if v is not None}}
    return localize(space, data, method, prior=prior, radius=None if prior is None else radius,
                    n_hypotheses=args["n_hypotheses"],
                    threshold=args["threshold"], rng=rng, hypotheses=hypotheses, **own)
