"""One-frame 2D localization: CLAP, RANSAC and Hough on the same SE(2) candidates.

The original CLAP (RoboCup 2024 AdultSize): every pair of observed field
features, matched to every type-compatible ordered pair of map landmarks whose
separation agrees, gives one candidate pose
(:class:`~clap_unified.spaces.Landmark2DSpace`). Then

* ``"clap"`` finds density centres among the candidates: global mode without a
  prior (every cluster is reported, e.g. the pose and its mirror on the
  point-symmetric field), local mode around a prior (the previous estimate);
* ``"ransac"`` scores every candidate by how many observations land within
  ``residual_threshold`` of a map landmark of their type;
* ``"hough"`` votes the candidates into an ``(x, y, theta)`` grid.

With a prior, RANSAC and Hough see the same gated candidates as CLAP's local
mode (those within ``radius`` of the prior), so the three differ only in how
they reach consensus.
"""

from __future__ import annotations

import numpy as np

from .._validation import check_choice, check_positive
from ..clap import clap
from ..geometry.se2 import SE2
from ..hough import randomized_hough
from ..maps.field import Field, load_field
from ..ransac import ransac
from ..result import ConsensusResult
from ..spaces.landmarks2d import Landmark2DSpace, observations_array
from ..spaces.sampling import generate_hypotheses
from .observations import ObservationInput, Observations

__all__ = ["LOCALIZE_METHODS", "MIRROR", "as_pose", "localize2d", "observation_data", "pose_error"]

LOCALIZE_METHODS = ("clap", "ransac", "hough")

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

#: Hough grid: 0.25 m x 0.25 m x 5 degrees.
HOUGH_CELL = (0.25, 0.25, np.radians(5.0))

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
               radius: float = 1.0, bandwidth: float = 0.25, residual_threshold: float = 0.3,
               distance_tolerance: float = 0.3, angle_weight: float = 1.0,
               max_clusters: int = 5, min_support: int = 1, max_hypotheses: int = 20000,
               hough_cell=HOUGH_CELL, space: Landmark2DSpace | None = None, hypotheses=None,
               rng=None) -> ConsensusResult:
    """Robot pose on the field from one frame of landmark detections.

    Parameters
    ----------
    observations : list of dict, ObservationInput or ndarray of shape (N, 3)
        Detections in the robot frame (x forward, y left, metres):
        ``{"type", "x", "y"}`` dicts or rows ``(type_id, x, y)``.
    field : {"adult", "kid"} or Field
    method : {"clap", "ransac", "hough"}
    prior : (x, y, theta) or ndarray of shape (3, 3), optional
        Previous estimate. The candidates are then those of the association it
        implies (:meth:`~clap_unified.spaces.Landmark2DSpace.local_hypotheses`,
        observations within ``radius`` metres of a landmark of their type)
        that lie within ``radius`` of it; CLAP runs in local mode, RANSAC and
        Hough see the same candidates.
    radius : float
        Gate around the prior in the SE(2) distance (metres, radians times
        ``angle_weight``).
    bandwidth : float
        CLAP global mode: neighbourhood radius among candidates.
    residual_threshold : float
        An observation is an inlier when it lands this close (metres) to a map
        landmark of its type.
    distance_tolerance : float
        Candidate check: observed and map separations of a pair must agree
        this well (metres).
    angle_weight : float
        lambda of the SE(2) distance, metres per radian.
    max_clusters, min_support : int
        CLAP global mode: clusters reported and the smallest reported.
    max_hypotheses : int
        All observation pairs are enumerated while they give no more than
        this many pairs; beyond, pairs are sampled.
    hough_cell : (dx, dy, dtheta)
        Hough grid cell (metres, metres, radians; ``2 pi / dtheta`` whole).
    space : Landmark2DSpace, optional
        Reuse a space (and its field) across frames.
    hypotheses : HypothesisSet, optional
        Reuse candidates (e.g. to compare methods on identical candidates).
    rng : None, int or numpy.random.Generator
        Used only when pairs are sampled.

    Returns
    -------
    ConsensusResult
        ``model`` is ``T_field_robot``; ``clusters`` best first. Fewer than
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
    check_choice(method, "method", set(LOCALIZE_METHODS))
    if space is None:
        fld = field if isinstance(field, Field) else load_field(field)
        space = Landmark2DSpace(fld, distance_tolerance=distance_tolerance,
                                angle_weight=angle_weight)
    data = observation_data(observations)
    radius = check_positive(radius, "radius")
    prior = None if prior is None else as_pose(prior)
    n = len(data)
    if n < space.min_samples:
        return ConsensusResult.failure(method, f"observations: {n} given, a pose needs at least "
                                       f"{space.min_samples}", n, 0, space)
    data = space.check_data(data)
    if prior is not None and hypotheses is None:
        # only the candidates the prior's association allows (see local_hypotheses)
        hypotheses = space.local_hypotheses(data, prior, gate=radius)
    elif hypotheses is None:
        hypotheses = generate_hypotheses(space, data, max_hypotheses, rng=rng)
    candidates = hypotheses
    if prior is not None and method != "clap":  # CLAP's local mode gates them itself
        near = space.manifold.distance(prior, hypotheses.models) <= radius
        candidates = hypotheses.subset(np.flatnonzero(near))
    if len(candidates) == 0:
        where = "" if prior is None else f" within radius {radius:g} of the prior"
        return ConsensusResult.failure(method, f"no candidate pose{where}", n, len(hypotheses),
                                       space)
    common = dict(hypotheses=candidates, residual_threshold=residual_threshold)
    if method == "clap":
        if prior is not None:
            res = clap(space, data, mode="local", initial_guess=prior, radius=radius,
                       min_support=min_support, **common)
        else:
            res = clap(space, data, bandwidth=bandwidth, max_clusters=max_clusters,
                       min_support=min_support, **common)
    elif method == "ransac":
        res = ransac(space, data, max_trials=len(candidates), **common)
    else:
        res = randomized_hough(space, data, cell_size=hough_cell, coordinates=SE2.to_xytheta,
                               periods=(None, None, 2 * np.pi), num_peaks=max_clusters, **common)
    res.diagnostics["candidates"] = len(candidates)
    return res
