"""One-frame 6-DoF localization from typed 3D landmark detections.

Every strategy registered for 3D poses runs on the same detections through
the one localization pipeline (:func:`~clap_unified.localization.core.localize`,
hence :func:`~clap_unified.fit`):

* ``"clap"``: candidate poses from observed triplets matched to every
  type- and distance-compatible map triplet
  (:class:`~clap_unified.spaces.Landmark3DSpace`), clustered in SE(3); the
  densest cluster's robust centre, refitted on its inliers;
* ``"ransac"``: the very same candidates scored by inlier counting (all of
  them), the best refitted on its inliers;
* ``"open3d"``: Open3D's ``registration_ransac_based_on_correspondence`` on
  every type-compatible (detection, landmark) pair, with its edge-length
  checker (the counterpart of the triplet distance check), then the same
  inlier refit (:mod:`clap_unified.external.open3d`).

Poses are ``T_world_body``: a body point ``p`` is at ``R p + t`` in the world.
"""

from __future__ import annotations

import numpy as np

from .._validation import Checked, check_positive
from ..presets import get_preset
from ..result import ConsensusResult
from ..spaces.landmarks3d import Landmark3DSpace
from .core import localize
from .map3d import LandmarkMap3D

__all__ = ["localize3d", "pose_errors", "align_correspondences"]

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


def _given(**values) -> dict:
    """The arguments given (not ``None``): they override the preset's."""
    return {k: v for k, v in values.items() if v is not None}


def _open3d_seed(rng) -> int:
    """Open3D's seed: the given integer seed, else 0."""
    return int(rng) if isinstance(rng, (int, np.integer)) else 0


def localize3d(observations, landmarks, *, method: str = "clap",
               n_hypotheses: int | None = None, bandwidth: float | None = None,
               centre: str | None = None, threshold: float | None = None,
               max_clusters: int | None = None, min_support: int | None = None,
               space: Landmark3DSpace | None = None, hypotheses=None, prune: bool | None = None,
               prior=None, max_translation: float | None = None,
               max_rotation: float | None = None, open3d_iterations: int | None = None,
               rng=None, select: str | None = None, **space_options) -> ConsensusResult:
    """Pose ``T_world_body`` from one frame of typed 3D landmark detections.

    Every argument left ``None`` takes the default of the localization preset
    (``get_preset("pose3d", method, task="localize")``,
    :mod:`clap_unified.presets`, the one home of the defaults; the command
    ``clap-unified localize3d`` reads the same): ``n_hypotheses`` 1000,
    ``threshold`` 0.15 m, a gate of 0.5 m and 10 degrees around a prior; CLAP's
    ``bandwidth`` 0.15, ``centre`` ``"medoid"``, ``max_clusters`` 5,
    ``min_support`` 3, ``prune``, ``select`` ``"support"``; Open3D's
    ``open3d_iterations`` 100000.

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
    method : str
        A strategy registered for 3D poses (``strategy_names(space)``):
        ``"clap"``, ``"ransac"``, ``"open3d"``...
    n_hypotheses : int, optional
        Candidate poses wanted; all observation triplets are enumerated when
        there are no more than this many, otherwise triplets are sampled.
        Every candidate is used (RANSAC scores them all).
    bandwidth : float, optional
        CLAP: neighbourhood radius among candidates, in the SE(3) distance.
    centre : {"medoid", "karcher", "log_euclidean", "split", "median"}, optional
        CLAP's cluster centre.
    threshold : float, optional
        A detection is an inlier when it lands this close (metres) to a map
        landmark of its type.
    max_clusters, min_support : int, optional
        CLAP: clusters reported, smallest reported.
    space : Landmark3DSpace, optional
        Reuse a space across frames (its distance, lambda and tolerances).
    hypotheses : HypothesisSet, optional
        Reuse candidates, e.g. to run CLAP and RANSAC on identical ones.
    prune : bool, optional
        CLAP global mode: before clustering, drop candidates with fewer than
        ``min_support`` others within ``2 * bandwidth``
        (:func:`~clap_unified.clap.density.dense_candidates`); they cannot
        join a cluster, and the pairwise distance matrix shrinks from all
        candidates to the few dense ones.
    prior : ndarray of shape (4, 4), optional
        An initial guess (the previous estimate). Only candidates within
        ``max_translation`` and ``max_rotation`` of it (relative transform
        error, Sec. III-C of the paper: the gate ``radius=(max_translation,
        max_rotation)`` of :meth:`~clap_unified.spaces.Landmark3DSpace.near_prior`)
        are kept; CLAP then finds the robust centre of all of them in local
        mode, RANSAC scores only them. Open3D ignores it.
    max_translation : float, optional
        Local filter: translation threshold, metres.
    max_rotation : float, optional
        Local filter: rotation threshold, radians.
    open3d_iterations : int, optional
        Open3D RANSAC iteration cap (its ``n_hypotheses``).
    rng : None, int or numpy.random.Generator
        Seeds triplet sampling (an integer also seeds Open3D's generator).
    select : {"support", "consensus"}, optional
        CLAP: the answer is the cluster with the most candidates (the paper)
        or the one whose refined centre best explains the detections
        (:func:`~clap_unified.clap.run_clap`).
    **space_options
        Passed to :class:`~clap_unified.spaces.Landmark3DSpace` when no
        ``space`` is given (``distance_tolerance``, ``angle_weight``,
        ``metric``, ...).

    Returns
    -------
    ConsensusResult
        ``model`` is ``T_world_body``, ``clusters`` best first;
        ``diagnostics["hypotheses"]`` counts the candidate poses
        (``diagnostics["candidates"]`` the type-compatible pairs for Open3D).
        Fewer than three detections or no candidate give ``success=False``
        with a reason.

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
    preset = get_preset("pose3d", method, task="localize")  # this function's defaults
    args = {**preset.fit, **_given(n_hypotheses=n_hypotheses, threshold=threshold,
                                   max_translation=max_translation, max_rotation=max_rotation)}
    threshold = args["threshold"]
    if space is None:
        if not isinstance(landmarks, LandmarkMap3D):
            raise ValueError("landmarks: expected a LandmarkMap3D (or pass space=)")
        space = landmarks.space(inlier_threshold=threshold, **space_options)
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
    radius = None
    if prior is not None:
        radius = (check_positive(args["max_translation"], "max_translation"),
                  check_positive(args["max_rotation"], "max_rotation"))
    # the options of each strategy this function sets (the others keep their defaults)
    given = {"clap": _given(bandwidth=bandwidth, centre=centre, max_clusters=max_clusters,
                            min_support=min_support, prune=prune, select=select),
             "open3d": {"n_hypotheses": preset.fit["n_hypotheses"] if open3d_iterations is None
                        else open3d_iterations, "seed": _open3d_seed(rng)}}
    own = {**preset.options, **given.get(method, {})}
    budget = (get_preset("pose3d", None, task="localize").fit["n_hypotheses"]
              if n_hypotheses is None else n_hypotheses)  # the candidates' (open3d: unused)
    return localize(space, data, method, prior=prior, radius=radius, threshold=threshold,
                    rng=rng, hypotheses=hypotheses, **{"n_hypotheses": budget, **own})


def align_correspondences(correspondences, *, method: str = "clap",
                          n_hypotheses: int | None = None, bandwidth: float | None = None,
                          centre: str | None = None, threshold: float | None = None,
                          min_support: int | None = None, space=None,
                          prune: bool | None = None, rng=None) -> ConsensusResult:
    """Pose ``T_world_body`` from putative 3D correspondences ``(N, 6)`` rows ``(p, q)``.

    ``"clap"`` and ``"ransac"`` see the same ``n_hypotheses`` random triplets
    (the candidate budget: exactly that many are drawn) of a
    :class:`~clap_unified.spaces.rigid3d.Correspondence3DSpace`; ``"open3d"``
    runs Open3D's correspondence RANSAC with ``n_hypotheses`` iterations at most.
    Every argument left ``None`` takes the default of the localization preset
    (``get_preset("rigid3d", method, task="localize")``: 1000 triplets, 0.15 m;
    CLAP as :func:`localize3d`'s).

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

    preset = get_preset("rigid3d", method, task="localize")  # this function's defaults
    args = {**preset.fit, **_given(n_hypotheses=n_hypotheses, threshold=threshold)}
    n_hypotheses, threshold = args["n_hypotheses"], args["threshold"]
    if space is None:
        space = Correspondence3DSpace(inlier_threshold=threshold)
    data = Checked(space.check_data(correspondences))  # once: localize and fit unwrap it
    given = {"clap": _given(bandwidth=bandwidth, centre=centre, min_support=min_support,
                            prune=prune),
             "open3d": dict(seed=_open3d_seed(rng))}
    own = {**preset.options, **given.get(method, {})}
    return localize(space, data, method, n_hypotheses=n_hypotheses, threshold=threshold,
                    rng=rng, sampling={"exhaustive": False, "max_draws": n_hypotheses}, **own)
