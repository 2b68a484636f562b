"""One-frame 6-DoF localization from typed 3D landmark detections.

Three methods on the same detections:

* ``"clap"``: candidate poses from observed triplets matched to every
  type- and distance-compatible map triplet
  (:class:`~clap_unified.spaces.Landmark3DSpace`), clustered in SE(3); the
  densest cluster's robust centre, refitted on its inliers;
* ``"ransac"``: the very same candidates scored by inlier counting (same
  candidate budget), the best refitted on its inliers;
* ``"open3d"``: Open3D's ``registration_ransac_based_on_correspondence`` on
  every type-compatible (detection, landmark) pair, with its edge-length
  checker (the counterpart of the triplet distance check), then the same
  inlier refit.

Poses are ``T_world_body``: a body point ``p`` is at ``R p + t`` in the world.
"""

from __future__ import annotations

import time

import numpy as np

from .._validation import check_choice, check_int, check_positive
from ..clap import clap
from ..ransac import ransac
from ..refine import refit_on_inliers
from ..result import Cluster, ConsensusResult
from ..spaces.landmarks3d import Landmark3DSpace
from ..spaces.sampling import generate_hypotheses
from .map3d import LandmarkMap3D

__all__ = ["LOCALIZE3D_METHODS", "localize3d", "type_correspondences", "pose_errors",
           "dense_candidates", "align_correspondences"]

LOCALIZE3D_METHODS = ("clap", "ransac", "open3d")


def type_correspondences(space: Landmark3DSpace, data) -> np.ndarray:
    """Every (detection, map landmark) pair of the same type, ``(K, 2)``.

    Examples
    --------
    >>> space = Landmark3DSpace(np.eye(3), ["a", "b", "b"])
    >>> type_correspondences(space, np.array([[1.0, 0, 0, 0], [0.0, 1, 1, 1]])).tolist()
    [[0, 1], [0, 2], [1, 0]]
    """
    ids = np.asarray(data, dtype=float)[:, 0].astype(int)
    i, m = np.nonzero(ids[:, None] == space.type_ids[None, :])
    return np.c_[i, m].astype(np.intp)


def dense_candidates(manifold, models, radius: float, min_count: int) -> np.ndarray:
    """Indices of candidate poses with at least ``min_count`` candidates within ``radius``.

    Counted with a k-d tree on :meth:`~clap_unified.geometry.SE3.chordal_embedding`
    (``O(H log H)``). For the ``relative`` metric nothing CLAP could use is
    lost with ``radius = 2 * bandwidth``: a member of a cluster lies within
    the bandwidth of a seed that has ``min_support`` candidates within the
    bandwidth, hence (triangle inequality) within twice the bandwidth of the
    member, and chordal distances never exceed ``relative`` ones. For the
    other metrics it is a close approximation.

    Examples
    --------
    >>> from clap_unified.geometry import SE3
    >>> g = SE3(2.0, metric="relative")
    >>> T = g.expmap(np.r_[np.zeros((5, 6)), 10 * np.eye(6)[:2]])
    >>> dense_candidates(g, T, 0.1, 3).tolist()
    [0, 1, 2, 3, 4]
    """
    from scipy.spatial import cKDTree

    emb = manifold.chordal_embedding(models)
    counts = cKDTree(emb).query_ball_point(emb, radius, return_length=True)
    return np.flatnonzero(counts >= min_count)


def pose_errors(estimate, truth):
    """Translation error (metres) and rotation error (degrees) of ``truth^-1 estimate``.

    Examples
    --------
    >>> from clap_unified.geometry import SE3, so3_exp
    >>> e_t, e_r = pose_errors(SE3.from_rt(so3_exp([0, 0, np.radians(2)]), [0.03, 0, 0]),
    ...                        np.eye(4))
    >>> print(f"{e_t:.3f} m {e_r:.3f} deg")
    0.030 m 2.000 deg
    """
    from ..geometry.se3 import SE3

    e_t, e_r = SE3().relative_error(truth, estimate)
    return float(e_t), float(np.degrees(e_r))


def localize3d(observations, landmarks, *, method: str = "clap", n_hypotheses: int = 1000,
               bandwidth: float = 0.15, centre: str = "medoid", residual_threshold: float = 0.15,
               max_clusters: int = 5, min_support: int = 3, space: Landmark3DSpace | None = None,
               hypotheses=None, prune: bool = True, prior=None, max_translation: float = 0.5,
               max_rotation: float = np.radians(10.0), open3d_iterations: int = 100000, rng=None,
               **space_options) -> ConsensusResult:
    """Pose ``T_world_body`` from one frame of typed 3D landmark detections.

    Parameters
    ----------
    observations : ndarray of shape (N, 4), DetectionInput3D or list of dict
        Rows ``(type_id, x, y, z)`` in the body frame (``type_id`` indexes
        ``space.type_names``), a simulated frame's ``.input``, or
        ``{"type", "x", "y", "z"}`` dicts. A whole simulated
        :class:`~clap_unified.localization.scene3d.Detections3D` is refused
        (it holds the truth).
    landmarks : LandmarkMap3D
        The map (ignored when ``space`` is given).
    method : {"clap", "ransac", "open3d"}
    n_hypotheses : int
        Candidate poses wanted; all observation triplets are enumerated when
        there are no more than this many, otherwise triplets are sampled.
    bandwidth : float
        CLAP: neighbourhood radius among candidates, in the SE(3) distance.
    centre : {"medoid", "karcher", "log_euclidean", "split", "median"}
        CLAP's cluster centre.
    residual_threshold : float
        A detection is an inlier when it lands this close (metres) to a map
        landmark of its type.
    max_clusters, min_support : int
        CLAP: clusters reported, smallest reported.
    space : Landmark3DSpace, optional
        Reuse a space across frames (its distance, lambda and tolerances).
    hypotheses : HypothesisSet, optional
        Reuse candidates, e.g. to run CLAP and RANSAC on identical ones.
    prune : bool
        CLAP: before clustering, drop candidates with fewer than
        ``min_support`` others within ``2 * bandwidth``
        (:func:`dense_candidates`); they cannot join a cluster, and the
        pairwise distance matrix shrinks from all candidates to the few dense ones.
    prior : ndarray of shape (4, 4), optional
        An initial guess (the previous estimate). Only candidates within
        ``max_translation`` and ``max_rotation`` of it (relative transform
        error, Sec. III-C of the paper) are kept; CLAP then finds their robust
        centre in local mode, RANSAC scores only them. Open3D ignores it.
    max_translation : float
        Local filter: translation threshold, metres.
    max_rotation : float
        Local filter: rotation threshold, radians.
    open3d_iterations : int
        Open3D RANSAC iteration cap.
    rng : None, int or numpy.random.Generator
        Seeds triplet sampling (and Open3D's generator).
    **space_options
        Passed to :class:`~clap_unified.spaces.Landmark3DSpace` when no
        ``space`` is given (``distance_tolerance``, ``angle_weight``,
        ``metric``, ...).

    Returns
    -------
    ConsensusResult
        ``model`` is ``T_world_body``, ``clusters`` best first;
        ``diagnostics["candidates"]`` counts the candidate poses. Fewer than
        three detections or no candidate give ``success=False`` with a reason.

    Examples
    --------
    >>> from clap_unified.localization.map3d import lab_map
    >>> from clap_unified.localization.scene3d import mocap_trajectory, simulate_detections
    >>> lab = lab_map()
    >>> truth = mocap_trajectory(20, rng=0)[4]
    >>> det = simulate_detections(lab, truth, outlier_ratio=0.6, rng=2)
    >>> res = localize3d(det.input, lab, rng=0)
    >>> e_t, e_r = pose_errors(res.model, truth)
    >>> res.success, e_t < 0.05, e_r < 1.0
    (True, True, True)
    """
    t0 = time.perf_counter()
    check_choice(method, "method", set(LOCALIZE3D_METHODS))
    if space is None:
        if not isinstance(landmarks, LandmarkMap3D):
            raise ValueError("landmarks: expected a LandmarkMap3D (or pass space=)")
        space = landmarks.space(inlier_threshold=residual_threshold, **space_options)
    from .scene3d import DetectionInput3D, Detections3D

    if isinstance(observations, Detections3D):
        raise ValueError("observations: pass the simulated frame's .input, not the whole "
                         "Detections3D (it holds the truth)")
    if isinstance(observations, DetectionInput3D):
        observations = observations.data
    if isinstance(observations, (list, tuple)):
        observations = space.observations_array(observations)
    data = np.asarray(observations, dtype=float)
    if data.ndim != 2 or data.shape[1] != 4:
        raise ValueError(f"observations: expected shape (N, 4) rows (type_id, x, y, z), got "
                         f"{data.shape}")
    n = len(data)
    if n < space.min_samples:
        return ConsensusResult.failure(method, f"observations: {n} given, a pose needs at "
                                       f"least {space.min_samples}", n, 0, space)
    data = space.check_data(data)
    residual_threshold = check_positive(residual_threshold, "residual_threshold")
    n_hypotheses = check_int(n_hypotheses, "n_hypotheses", minimum=1)
    if prior is not None:
        prior = space.manifold.validate(prior, "prior")
        if prior.shape != (4, 4):
            raise ValueError(f"prior: expected one 4 x 4 pose, got shape {prior.shape}")
        max_translation = check_positive(max_translation, "max_translation")
        max_rotation = check_positive(max_rotation, "max_rotation")
    if method == "open3d":
        res = _open3d(space, data, residual_threshold, open3d_iterations, rng)
    else:
        if hypotheses is None:
            hypotheses = generate_hypotheses(space, data, n_hypotheses, rng=rng)
        gate = None
        if prior is not None:
            e_t, e_r = space.manifold.relative_error(prior, hypotheses.models)
            gate = np.flatnonzero((e_t <= max_translation) & (e_r <= max_rotation))
        if len(hypotheses) == 0:
            res = ConsensusResult.failure(method, "no candidate pose: no observed triplet "
                                          "matches a map triplet", n, 0, space)
        elif gate is not None and len(gate) < (min_support if method == "clap" else 1):
            res = ConsensusResult.failure(
                method, f"{len(gate)} candidates within {max_translation:g} m and "
                f"{np.degrees(max_rotation):.3g} deg of the prior", n, len(hypotheses), space)
        elif gate is not None:
            near = hypotheses.subset(gate)
            if method == "clap":
                radius = float(space.manifold.distance(prior, near.models).max())
                res = clap(space, data, hypotheses=near, mode="local", initial_guess=prior,
                           radius=max(radius * (1 + 1e-9), 1e-12), centre=centre,
                           min_support=min_support, residual_threshold=residual_threshold)
            else:
                res = ransac(space, data, hypotheses=near, max_trials=len(near),
                             residual_threshold=residual_threshold)
            _index_into(res, gate, len(hypotheses))
            res.diagnostics["near_prior"] = len(gate)
        elif method == "clap":
            candidates = hypotheses
            if prune:
                keep = dense_candidates(space.manifold, hypotheses.models, 2 * bandwidth,
                                        min_support)
                candidates = hypotheses.subset(keep)
            if len(candidates) == 0:
                res = ConsensusResult.failure(method, f"no candidate has {min_support} others "
                                              f"within {2 * bandwidth:g}", n, 0, space)
            else:
                res = clap(space, data, hypotheses=candidates, bandwidth=bandwidth,
                           centre=centre, max_clusters=max_clusters, min_support=min_support,
                           residual_threshold=residual_threshold)
                if prune:
                    _index_into(res, keep, len(hypotheses))
            res.diagnostics["dense_candidates"] = len(candidates)
        else:
            res = ransac(space, data, hypotheses=hypotheses, max_trials=len(hypotheses),
                         residual_threshold=residual_threshold)
        res.diagnostics["candidates"] = 0 if hypotheses is None else len(hypotheses)
    res.diagnostics["seconds"] = time.perf_counter() - t0
    return res


def _index_into(res, keep, n_hypotheses):
    """Make a result on ``hypotheses.subset(keep)`` refer to the full candidate set."""
    for c in res.clusters:
        c.members = keep[c.members]
    if res.success:
        support = np.zeros(n_hypotheses, bool)
        support[keep[res.support]] = True
        res.support = support


def _open3d(space, data, threshold, iterations, rng):
    from .open3d_baselines import open3d_correspondence_ransac

    seed = rng if isinstance(rng, (int, np.integer)) else 0
    corr = type_correspondences(space, data)
    n = len(data)
    T, info = open3d_correspondence_ransac(data[:, 1:], space.positions, corr,
                                           threshold=threshold, max_iteration=iterations,
                                           seed=int(seed))
    if len(info["inliers"]) < 3:
        return ConsensusResult.failure("open3d", "Open3D RANSAC found no pose with three "
                                       "inliers", n, 0, space, candidates=len(corr))
    model, inliers = refit_on_inliers(space, T, data, threshold)
    cluster = Cluster(model, int(np.count_nonzero(inliers)), 0.0)
    return ConsensusResult("open3d", True, "ok", model, inliers, np.zeros(0, bool),
                           float(np.count_nonzero(inliers)), [cluster],
                           {"candidates": len(corr), "fitness": info["fitness"],
                            "open3d_seconds": info["seconds"]}, space)


def align_correspondences(correspondences, *, method: str = "clap", n_samples: int = 1000,
                          bandwidth: float = 0.15, centre: str = "medoid",
                          residual_threshold: float = 0.15, min_support: int = 3,
                          space=None, prune: bool = True, rng=None) -> ConsensusResult:
    """Pose ``T_world_body`` from putative 3D correspondences ``(N, 6)`` rows ``(p, q)``.

    ``"clap"`` and ``"ransac"`` see the same ``n_samples`` random triplets
    (the candidate budget) of a
    :class:`~clap_unified.spaces.rigid3d.Correspondence3DSpace`; ``"open3d"``
    runs Open3D's correspondence RANSAC with ``n_samples`` iterations at most.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> p = rng.uniform(-4, 4, (50, 3))
    >>> q = p + [0.5, -1.0, 2.0] + rng.normal(0, 0.01, (50, 3))
    >>> q[:30] = rng.uniform(-4, 4, (30, 3))          # 60 % wrong correspondences
    >>> res = align_correspondences(np.c_[p, q], rng=0)
    >>> res.model[:3, 3].round(2).tolist(), res.n_inliers
    ([0.5, -1.0, 2.0], 20)
    """
    from ..spaces.rigid3d import Correspondence3DSpace

    t0 = time.perf_counter()
    check_choice(method, "method", set(LOCALIZE3D_METHODS))
    if space is None:
        space = Correspondence3DSpace(inlier_threshold=residual_threshold)
    data = space.check_data(correspondences)
    n_samples = check_int(n_samples, "n_samples", minimum=1)
    n = len(data)
    if method == "open3d":
        from .open3d_baselines import open3d_correspondence_ransac

        seed = rng if isinstance(rng, (int, np.integer)) else 0
        T, info = open3d_correspondence_ransac(data[:, :3], data[:, 3:], np.c_[np.arange(n),
                                               np.arange(n)], threshold=residual_threshold,
                                               max_iteration=n_samples, seed=int(seed))
        if len(info["inliers"]) < 3:
            res = ConsensusResult.failure("open3d", "Open3D RANSAC found no pose with three "
                                          "inliers", n, 0, space)
        else:
            model, inliers = refit_on_inliers(space, T, data, residual_threshold)
            res = ConsensusResult("open3d", True, "ok", model, inliers, np.zeros(0, bool),
                                  float(np.count_nonzero(inliers)),
                                  [Cluster(model, int(np.count_nonzero(inliers)), 0.0)],
                                  {"fitness": info["fitness"]}, space)
    else:
        hyps = generate_hypotheses(space, data, n_samples, rng=rng, exhaustive=False,
                                   max_draws=n_samples)
        if len(hyps) == 0:
            res = ConsensusResult.failure(method, "no triplet passed the distance and "
                                          "collinearity checks", n, 0, space)
        elif method == "ransac":
            res = ransac(space, data, hypotheses=hyps, max_trials=len(hyps),
                         residual_threshold=residual_threshold)
        else:
            keep = (dense_candidates(space.manifold, hyps.models, 2 * bandwidth, min_support)
                    if prune else np.arange(len(hyps)))
            if len(keep) == 0:
                res = ConsensusResult.failure(method, f"no candidate has {min_support} others "
                                              f"within {2 * bandwidth:g}", n, len(hyps), space)
            else:
                res = clap(space, data, hypotheses=hyps.subset(keep), bandwidth=bandwidth,
                           centre=centre, min_support=min_support,
                           residual_threshold=residual_threshold)
                _index_into(res, keep, len(hyps))
        res.diagnostics["candidates"] = len(hyps)
    res.diagnostics["seconds"] = time.perf_counter() - t0
    return res
