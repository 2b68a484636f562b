"""OpenCV's robust homography and fundamental-matrix estimators as strategies.

``cv2.findHomography`` on the matches in the homography space,
``cv2.findFundamentalMat`` in the fundamental space, registered under four
names that apply to both:

* ``"cv2_ransac"``: ``cv2.RANSAC``, the classical baseline; OpenCV stops
  adaptively once ``confidence`` is reached, at most ``n_hypotheses``
  iterations;
* ``"magsac"``: ``cv2.USAC_MAGSAC`` (MAGSAC++ in OpenCV's USAC framework);
* ``"usac_accurate"``: ``cv2.USAC_ACCURATE`` (USAC with graph-cut RANSAC's
  local optimisation and SPRT);
* ``"usac_ransac_fixed"``: plain RANSAC in the USAC framework (uniform
  sampling, inlier-count score, no local optimisation, OpenCV's
  least-squares final polisher requested) with confidence 1, so it does not
  stop early on confidence: the closest OpenCV setting to the paper's fixed
  budget. On the test pairs its estimate is visibly less refined than
  ``cv2.RANSAC``'s.

In the fundamental space ``threshold`` is ``findFundamentalMat``'s
``ransacReprojThreshold`` (OpenCV's USAC scores the Sampson error, the
space's residual; ``cv2.FM_RANSAC`` the larger of the two point-to-epipolar-line
distances), the model is scaled to unit Frobenius norm (convention
``x2^T F x1 = 0``), and OpenCV needs at least 8 matches (fewer, or matches
whose points in one image are all collinear or identical, are a failure with
a reason before OpenCV runs).

They read the data only (``uses_hypotheses=False``) and are baselines
(``Strategy.baseline``), not the library's own strategies. ``threshold`` is
OpenCV's ``ransacReprojThreshold`` and ``n_hypotheses`` its iteration cap
(``maxIters``). OpenCV refines its own estimate: compare it as OpenCV returns
it with ``fit(..., refine=False)`` (the protocol of
:func:`~clap_unified.imaging.estimate_homography`). The result's inliers are,
as for every strategy, the matches within ``threshold`` of the returned
model (forward transfer error); OpenCV's own mask is in
``diagnostics["opencv_mask"]``. Convention as everywhere here: rows
``(x1, y1, x2, y2)``, ``x2 ~ H x1``.

Examples
--------
>>> import numpy as np
>>> from clap_unified import fit
>>> from clap_unified.spaces import HomographySpace
>>> rng = np.random.default_rng(0)
>>> src = rng.uniform(0, 640, (100, 2))
>>> res = fit(HomographySpace(), np.c_[src, src + [5.0, -3.0]], "magsac", refine=False)
>>> res.success, res.n_inliers, np.round(res.model[:2, 2], 3).tolist()
(True, 100, [5.0, -3.0])
"""

from __future__ import annotations

import numpy as np

from .._validation import check_fraction
from ..registry import Strategy, register_strategy
from ..result import Consensus
from ._peers import MODELS, degenerate_reason, normalise_model

__all__ = ["OPENCV", "run_opencv"]


def _classical(flag_name, fm_flag_name=None):
    """``findHomography(src, dst, flag, threshold, maxIters=, confidence=)``.

    With ``fundamental=True``: ``findFundamentalMat(src, dst, flag, threshold,
    confidence, maxIters)`` (``fm_flag_name`` when the flag has another name
    there: ``cv2.FM_RANSAC``).
    """
    def call(cv2, src, dst, threshold, max_iters, confidence, fundamental=False):
        if fundamental:
            return cv2.findFundamentalMat(src, dst, getattr(cv2, fm_flag_name or flag_name),
                                          threshold, confidence, max_iters)
        return cv2.findHomography(src, dst, getattr(cv2, flag_name), threshold,
                                  maxIters=max_iters, confidence=confidence)
    return call


def _usac_fixed(cv2, src, dst, threshold, max_iters, confidence, fundamental=False):
    """Plain RANSAC in USAC with exactly ``max_iters`` iterations (``confidence`` ignored)."""
    params = cv2.UsacParams()
    params.confidence = 1.0  # never stops early: exactly maxIterations
    params.maxIterations = max_iters
    params.threshold = threshold
    params.sampler = cv2.SAMPLING_UNIFORM
    params.score = cv2.SCORE_METHOD_RANSAC
    params.loMethod = cv2.LOCAL_OPTIM_NULL
    params.isParallel = False
    params.final_polisher = cv2.LSQ_POLISHER
    if fundamental:
        return cv2.findFundamentalMat(src, dst, params)
    return cv2.findHomography(src, dst, params)


#: Strategy name -> (the ``cv2.findHomography`` call, one-line summary).
OPENCV = {
    "cv2_ransac": (_classical("RANSAC", "FM_RANSAC"),
                   "OpenCV's cv2.findHomography with cv2.RANSAC (adaptive stopping; "
                   "cv2.findFundamentalMat with cv2.FM_RANSAC)"),
    "magsac": (_classical("USAC_MAGSAC"),
               "OpenCV's MAGSAC++ (cv2.USAC_MAGSAC)"),
    "usac_accurate": (_classical("USAC_ACCURATE"),
                      "OpenCV's USAC_ACCURATE (graph-cut local optimisation, SPRT)"),
    "usac_ransac_fixed": (_usac_fixed,
                          "plain RANSAC in OpenCV's USAC with a fixed iteration budget"),
}


def run_opencv(name, space, data, hypotheses, *, threshold: float, prior=None, radius=None,
               rng=None, n_hypotheses: int = 1000, confidence: float = 0.995) -> Consensus:
    """The OpenCV strategy ``name`` (a key of :data:`OPENCV`) on checked matches.

    Parameters
    ----------
    name : str
    space : HomographySpace or FundamentalSpace
    data : ndarray of shape (N, 4)
    hypotheses
        Unused (OpenCV draws its own samples).
    threshold : float
        ``ransacReprojThreshold`` in pixels.
    prior, radius, rng
        Unused: OpenCV is deterministic for a given list of matches.
    n_hypotheses : int
        ``maxIters``, the iteration cap (the paper's budget: 1000).
    confidence : float
        OpenCV's stopping confidence, strictly between 0 and 1 (ignored by
        ``"usac_ransac_fixed"``).

    Returns
    -------
    Consensus
        The model with ``H33 = 1`` (fundamental matrices: unit Frobenius
        norm, largest entry positive) and no clusters; score: the size of
        OpenCV's inlier mask. A ``None`` or non-finite answer, or an error
        OpenCV raises, is a failure with a reason.
    """
    import cv2

    confidence = check_fraction(confidence, "confidence", inclusive=(False, False))
    fundamental = space.name == "fundamental"
    what = MODELS[space.name]
    if fundamental:
        if len(data) < 8:
            return Consensus.failed(f"OpenCV needs at least 8 matches for a {what}, "
                                    f"got {len(data)}")
        why = degenerate_reason(data)
        if why is not None:
            return Consensus.failed(f"no {what}: {why}")
    src = np.ascontiguousarray(data[:, :2], dtype=np.float64)
    dst = np.ascontiguousarray(data[:, 2:], dtype=np.float64)
    try:
        M, mask = OPENCV[name][0](cv2, src, dst, threshold, int(n_hypotheses), confidence,
                                  fundamental=fundamental)
    except cv2.error as exc:
        lines = [line for line in str(exc).splitlines() if line.strip()]
        return Consensus.failed(f"OpenCV found no {what}: {lines[-1] if lines else exc}")
    model = None if M is None else normalise_model(M, space.name)
    if model is None:
        return Consensus.failed(f"OpenCV found no {what}")
    mask = mask.ravel().astype(bool) if mask is not None else np.zeros(len(data), bool)
    if len(mask) != len(data):
        mask = np.zeros(len(data), bool)
    return Consensus(model, score=float(mask.sum()),
                     diagnostics={"opencv_mask": mask, "opencv_inliers": int(mask.sum())})


def _strategy(name):
    def run(space, data, hypotheses, *, threshold: float, prior=None, radius=None, rng=None,
            n_hypotheses: int = 1000, confidence: float = 0.995) -> Consensus:
        return run_opencv(name, space, data, hypotheses, threshold=threshold, prior=prior,
                          radius=radius, rng=rng, n_hypotheses=n_hypotheses,
                          confidence=confidence)

    run.__name__ = run.__qualname__ = f"run_{name}"
    run.__doc__ = f":func:`run_opencv` with ``name={name!r}``."
    return Strategy(name, run, uses_hypotheses=False, applies_to=("homography", "fundamental"),
                    summary=OPENCV[name][1], baseline=True)


for _name in OPENCV:
    register_strategy(_strategy(_name))
