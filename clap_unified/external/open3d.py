"""Open3D's correspondence RANSAC as the strategy ``"open3d"`` of :func:`~clap_unified.fit`.

``registration_ransac_based_on_correspondence`` on the putative pairs a pose
space hands out (``space.correspondences(data)``: every type-compatible
(detection, landmark) pair in :class:`~clap_unified.spaces.Landmark3DSpace`,
the rows themselves in :class:`~clap_unified.spaces.rigid3d.Correspondence3DSpace`),
with Open3D's edge-length checker (the counterpart of the triplet distance
check) and its distance checker. It reads the data only
(``uses_hypotheses=False``); ``n_hypotheses`` is its iteration cap.
:func:`~clap_unified.fit` then refines Open3D's pose on its inliers like
every other strategy's (``refine=False`` keeps it as Open3D returns it).

:func:`open3d_correspondence_ransac` is the one call into Open3D's
correspondence RANSAC (the chapter and the benchmark use it directly too).
Open3D is imported on first use. Its RANSAC does not promise reproducible
results: the seed goes to Open3D's global generator (the only way its API
offers) and its loops run in parallel.

Examples
--------
>>> import numpy as np
>>> from clap_unified import fit
>>> from clap_unified.spaces import Correspondence3DSpace
>>> rng = np.random.default_rng(0)
>>> p = rng.uniform(-3, 3, (20, 3))
>>> res = fit(Correspondence3DSpace(), np.c_[p, p + [1.0, 2.0, 0.5]], "open3d", seed=0)
>>> res.success, res.n_inliers, res.model[:3, 3].round(4).tolist()
(True, 20, [1.0, 2.0, 0.5])
"""

from __future__ import annotations

import os
import time

import numpy as np

from .._validation import as_generator, check_int, check_positive
from ..registry import Strategy, register_strategy
from ..result import Cluster, Consensus

__all__ = ["open3d_correspondence_ransac", "run_open3d"]


def _o3d():
    os.environ.setdefault("OPEN3D_DISABLE_WEB_VISUALIZER", "true")
    import open3d as o3d

    return o3d


def _cloud(points):
    o3d = _o3d()
    pc = o3d.geometry.PointCloud()
    # a writeable copy: Open3D refuses read-only buffers (the scenes hand out read-only arrays)
    pc.points = o3d.utility.Vector3dVector(np.array(points, dtype=float, order="C", copy=True))
    return pc


def open3d_correspondence_ransac(source, target, correspondences, *, threshold: float,
                                 max_iteration: int = 100000, confidence: float = 0.999,
                                 edge_length: float | None = 0.9, seed: int = 0):
    """Open3D's RANSAC over putative correspondences: ``target ~ T source``.

    Parameters
    ----------
    source : ndarray of shape (N, 3)
        Points in the body frame.
    target : ndarray of shape (M, 3)
        Points in the world frame.
    correspondences : ndarray of int, shape (K, 2)
        Rows ``(source index, target index)``.
    threshold : float
        Inlier distance, metres (``max_correspondence_distance``).
    max_iteration : int
        RANSAC iterations at most (Open3D's default 100,000).
    confidence : float
        Open3D's early-stop confidence.
    edge_length : float or None
        ``CorrespondenceCheckerBasedOnEdgeLength`` similarity (0.9 in
        Open3D's examples); None turns the checker off.
    seed : int
        Seeds Open3D's random generator.

    Returns
    -------
    T : ndarray of shape (4, 4)
        ``T_world_body``; the identity when no sample passed the checkers.
    info : dict
        ``seconds``, ``fitness`` (Open3D's inlier fraction), ``inlier_rmse``,
        ``inliers`` (indices into ``correspondences``).

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> p = rng.uniform(-3, 3, (20, 3))
    >>> q = p + [1.0, 2.0, 0.5]
    >>> corr = np.c_[np.arange(20), np.arange(20)]
    >>> corr[:8, 1] = rng.permutation(8)[::-1]       # some wrong pairs
    >>> T, info = open3d_correspondence_ransac(p, q, corr, threshold=0.05)
    >>> T[:3, 3].round(4).tolist()
    [1.0, 2.0, 0.5]
    """
    o3d = _o3d()
    reg = o3d.pipelines.registration
    corr = np.array(correspondences, dtype=np.int32, order="C", copy=True).reshape(-1, 2)
    threshold = check_positive(threshold, "threshold")
    max_iteration = check_int(max_iteration, "max_iteration", minimum=1)
    o3d.utility.random.seed(int(seed))
    checkers = [reg.CorrespondenceCheckerBasedOnDistance(threshold)]
    if edge_length is not None:
        checkers.insert(0, reg.CorrespondenceCheckerBasedOnEdgeLength(edge_length))
    src, tgt = _cloud(source), _cloud(target)
    t0 = time.perf_counter()
    res = reg.registration_ransac_based_on_correspondence(
        src, tgt, o3d.utility.Vector2iVector(corr), threshold,
        reg.TransformationEstimationPointToPoint(False), 3, checkers,
        reg.RANSACConvergenceCriteria(max_iteration, confidence))
    seconds = time.perf_counter() - t0
    T = np.asarray(res.transformation).copy()
    moved = np.asarray(source, dtype=float)[corr[:, 0]] @ T[:3, :3].T + T[:3, 3]
    err = np.linalg.norm(moved - np.asarray(target, dtype=float)[corr[:, 1]], axis=1)
    return T, {"seconds": seconds, "fitness": float(res.fitness),
               "inlier_rmse": float(res.inlier_rmse), "inliers": np.flatnonzero(err < threshold)}


def run_open3d(space, data, hypotheses=None, *, threshold: float, prior=None, radius=None,
               rng=None, n_hypotheses: int = 100000, seed: int | None = None,
               confidence: float = 0.999, edge_length: float | None = 0.9) -> Consensus:
    """The ``"open3d"`` strategy: Open3D's RANSAC on ``space.correspondences(data)``.

    Parameters
    ----------
    space : Landmark3DSpace or Correspondence3DSpace
    data : ndarray
        Checked data of the space.
    hypotheses, prior, radius
        Unused (Open3D draws its own samples; a prior plays no part).
    threshold : float
        Inlier distance, metres.
    rng : None, int or numpy.random.Generator
        Draws Open3D's seed when ``seed`` is not given.
    n_hypotheses : int
        Open3D's iteration cap.
    seed : int, optional
        Open3D's seed itself.
    confidence, edge_length
        See :func:`open3d_correspondence_ransac`.

    Returns
    -------
    Consensus
        Open3D's pose, as one cluster supported by its inlier pairs; a failure
        when fewer than three pairs agree with it.
    """
    if seed is None:
        seed = int(as_generator(rng).integers(2**31 - 1)) if rng is not None else 0
    source, target, pairs = space.correspondences(data)
    T, info = open3d_correspondence_ransac(source, target, pairs, threshold=threshold,
                                           max_iteration=n_hypotheses, confidence=confidence,
                                           edge_length=edge_length, seed=int(seed))
    diag = {"candidates": len(pairs), "fitness": info["fitness"],
            "open3d_seconds": info["seconds"]}
    k = len(info["inliers"])
    pts = np.asarray(source, dtype=float)[pairs[info["inliers"], 0]]
    spread = np.linalg.svd(pts - pts.mean(axis=0), compute_uv=False) if k else np.zeros(2)
    if k < 3 or spread[1] <= 1e-9 * max(1.0, spread[0]):  # a line does not fix a pose
        return Consensus.failed("Open3D RANSAC found no pose with three non-collinear "
                                "inliers", **diag)
    return Consensus(T, (Cluster(T, k, 0.0),), score=float(k), diagnostics=diag)


def _finish(space, data, model, inliers, threshold, consensus):
    """The score of the returned (refined) pose: its inliers."""
    return float(np.count_nonzero(inliers)), "ok"


register_strategy(Strategy(
    "open3d", run_open3d, uses_hypotheses=False, applies_to=("pose3d", "rigid3d"),
    finish=_finish, baseline=True,
    summary="Open3D's registration_ransac_based_on_correspondence on the putative pairs"))
