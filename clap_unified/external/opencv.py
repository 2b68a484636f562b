"""OpenCV's robust homography estimators as strategies of :func:`~clap_unified.fit`.

``cv2.findHomography`` on the matches, registered under four names:

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

__all__ = ["OPENCV", "run_opencv"]


def _classical(flag_name):
    """``findHomography(src, dst, flag, threshold, maxIters=, confidence=)``."""
    def call(cv2, src, dst, threshold, max_iters, confidence):
        return cv2.findHomography(src, dst, getattr(cv2, flag_name), threshold,
                                  maxIters=max_iters, confidence=confidence)
    return call


def _usac_fixed(cv2, src, dst, threshold, max_iters, confidence):
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
    return cv2.findHomography(src, dst, params)


#: Strategy name -> (the ``cv2.findHomography`` call, one-line summary).
OPENCV = {
    "cv2_ransac": (_classical("RANSAC"),
                   "OpenCV's cv2.findHomography with cv2.RANSAC (adaptive stopping)"),
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
    space : HomographySpace
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
        The model with ``H33 = 1`` and no clusters; score: the size of
        OpenCV's inlier mask. A ``None`` or non-finite answer is a failure.
    """
    import cv2

    confidence = check_fraction(confidence, "confidence", inclusive=(False, False))
    src = np.ascontiguousarray(data[:, :2], dtype=np.float64)
    dst = np.ascontiguousarray(data[:, 2:], dtype=np.float64)
    H, mask = OPENCV[name][0](cv2, src, dst, threshold, int(n_hypotheses), confidence)
    if H is None or not np.all(np.isfinite(H)) or abs(H[2, 2]) < 1e-12:
        return Consensus.failed("OpenCV found no homography")
    mask = mask.ravel().astype(bool) if mask is not None else np.zeros(len(data), bool)
    return Consensus(H / H[2, 2], score=float(mask.sum()),
                     diagnostics={"opencv_mask": mask, "opencv_inliers": int(mask.sum())})


def _strategy(name):
    def run(space, data, hypotheses, *, threshold: float, prior=None, radius=None, rng=None,
            n_hypotheses: int = 1000, confidence: float = 0.995) -> Consensus:
        return run_opencv(name, space, data, hypotheses, threshold=threshold, prior=prior,
                          radius=radius, rng=rng, n_hypotheses=n_hypotheses,
                          confidence=confidence)

    run.__name__ = run.__qualname__ = f"run_{name}"
    run.__doc__ = f":func:`run_opencv` with ``name={name!r}``."
    return Strategy(name, run, uses_hypotheses=False, applies_to=("homography",),
                    summary=OPENCV[name][1], baseline=True)


for _name in OPENCV:
    register_strategy(_strategy(_name))
