"""PoseLib's robust estimators as the strategy ``"poselib"`` of :func:`~clap_unified.fit`.

In the homography space ``poselib.estimate_homography`` on the matches:
LO-RANSAC on 4-point samples with PoseLib's non-linear refinement of the best
model. In the fundamental space ``poselib.estimate_fundamental``: LO-RANSAC
on 7-point samples, Sampson-error scoring, non-linear refinement; the
threshold is its ``max_epipolar_error`` (Sampson error in pixels, the
fundamental space's residual) and the model is scaled to unit Frobenius norm
(convention ``x2^T F x1 = 0``, checked on a known ``F``). A baseline
(``Strategy.baseline``), not one of the library's own strategies; it reads
the data only (``uses_hypotheses=False``). The arguments mean what they mean
for every strategy:

* ``threshold``: the inlier threshold in pixels, PoseLib's
  ``ransac_opt["max_reproj_error"]`` (forward transfer error in image 2);
* ``n_hypotheses``: the iteration cap, ``ransac_opt["max_iterations"]``;
* ``confidence``: the stopping confidence, ``ransac_opt["success_prob"]``
  (default 0.995 as for OpenCV's estimators; PoseLib's own is 0.9999);
* ``min_iterations``: ``ransac_opt["min_iterations"]``, default 0 so that,
  like OpenCV, it stops as soon as ``confidence`` is reached (PoseLib's own
  default is 1000); capped at ``n_hypotheses``;
* ``rng``: PoseLib's ``ransac_opt["seed"]`` is the first integer in
  ``[0, 2**31 - 1)`` drawn from ``as_generator(rng)``, so an int ``rng``
  gives the same result every time (``None``: a fresh random seed).

PoseLib refines its own estimate: compare it as PoseLib returns it with
``fit(..., refine=False)`` (the protocol of
:func:`~clap_unified.imaging.estimate_homography`). The result's inliers are,
as for every strategy, the matches within ``threshold`` of the returned model
(forward transfer error); PoseLib's own mask is in
``diagnostics["poselib_mask"]``. Convention as everywhere here (and as
PoseLib's, checked on a known ``H``): rows ``(x1, y1, x2, y2)``,
``x2 ~ H x1``. Matches whose points in either image are all collinear or
identical are a failure before the peer runs (PoseLib would return a
homography that fits a line of points). PoseLib is imported only when the strategy runs.

Examples
--------
>>> import numpy as np
>>> from clap_unified import fit
>>> from clap_unified.spaces import HomographySpace
>>> rng = np.random.default_rng(0)
>>> src = rng.uniform(0, 640, (100, 2))
>>> res = fit(HomographySpace(), np.c_[src, src + [5.0, -3.0]], "poselib", rng=0,
...           refine=False)
>>> res.success, res.n_inliers, np.round(res.model[:2, 2], 3).tolist()
(True, 100, [5.0, -3.0])
"""

from __future__ import annotations

import numpy as np  # noqa: F401  (the doctests)

from ..registry import Strategy, register_strategy
from ..result import Consensus
from ._peers import run_peer

__all__ = ["run_poselib"]


def _import_poselib():
    try:
        import poselib
    except ImportError as exc:
        raise ImportError("method 'poselib' needs the package poselib "
                          "(pip install poselib)") from exc
    return poselib


def run_poselib(space, data, hypotheses, *, threshold: float, prior=None, radius=None,
                rng=None, n_hypotheses: int = 1000, confidence: float = 0.995,
                min_iterations: int = 0) -> Consensus:
    """``poselib.estimate_homography`` (or ``estimate_fundamental``) on checked matches.

    Parameters
    ----------
    space : HomographySpace or FundamentalSpace
    data : ndarray of shape (N, 4)
        Rows ``(x1, y1, x2, y2)``.
    hypotheses
        Unused (PoseLib draws its own samples).
    threshold : float
        ``max_reproj_error`` (fundamental matrices: ``max_epipolar_error``)
        in pixels.
    prior, radius
        Unused.
    rng : None, int or numpy.random.Generator
        Source of PoseLib's ``seed`` (``seed_of``).
    n_hypotheses : int
        ``max_iterations``, the iteration cap.
    confidence : float
        ``success_prob``, strictly between 0 and 1.
    min_iterations : int
        ``min_iterations`` (at most ``n_hypotheses``).

    Returns
    -------
    Consensus
        The model with ``H33 = 1`` (fundamental matrices: unit Frobenius
        norm) and no clusters; score: the size of PoseLib's inlier mask. A
        non-finite answer (PoseLib's failure) or an empty mask, or degenerate
        matches, is a failure with a reason.

    Raises
    ------
    ImportError
        PoseLib is not installed.

    Examples
    --------
    >>> from clap_unified.spaces import HomographySpace
    >>> src = np.random.default_rng(1).uniform(0, 640, (50, 2))
    >>> c = run_poselib(HomographySpace(), np.c_[src, 2 * src], None, threshold=1.0, rng=0)
    >>> np.round(c.model, 6).tolist(), c.diagnostics["poselib_inliers"]
    ([[2.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 1.0]], 50)
    """
    poselib = _import_poselib()
    fundamental = space.name == "fundamental"

    def call(src, dst, t, max_iterations, min_iter, conf, seed):
        opt = {"max_iterations": max_iterations, "min_iterations": min_iter,
               "success_prob": conf, "seed": seed}
        if fundamental:
            M, info = poselib.estimate_fundamental(src, dst, {**opt, "max_epipolar_error": t})
        else:
            M, info = poselib.estimate_homography(src, dst, {**opt, "max_reproj_error": t})
        return M, info.get("inliers", []), {
            "poselib_iterations": int(info.get("iterations", 0)),
            "poselib_refinements": int(info.get("refinements", 0))}

    return run_peer("PoseLib", "poselib", call, data, threshold=threshold, rng=rng,
                    n_hypotheses=n_hypotheses, confidence=confidence,
                    min_iterations=min_iterations, space_name=space.name)


register_strategy(Strategy(
    "poselib", run_poselib, uses_hypotheses=False, applies_to=("homography", "fundamental"),
    baseline=True,
    summary="PoseLib's poselib.estimate_homography / estimate_fundamental (LO-RANSAC, "
            "non-linear refinement)"))
