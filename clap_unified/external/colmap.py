"""COLMAP's robust estimators as the strategy ``"colmap"`` of :func:`~clap_unified.fit`.

In the homography space ``pycolmap.estimate_homography_matrix`` on the
matches: COLMAP's LO-RANSAC (4-point DLT samples, local optimisation on the
inliers). In the fundamental space ``pycolmap.estimate_fundamental_matrix``:
LO-RANSAC on 7-point samples with squared-Sampson-error inliers (``max_error``
is the Sampson error in pixels, the fundamental space's residual) and
COLMAP's Sampson refinement; the model is scaled to unit Frobenius norm
(convention ``x2^T F x1 = 0``, checked on a known ``F``). A baseline
(``Strategy.baseline``), not one of the library's own strategies; it reads
the data only (``uses_hypotheses=False``). The arguments mean what they mean
for every strategy:

* ``threshold``: the inlier threshold in pixels,
  ``pycolmap.RANSACOptions.max_error`` (forward transfer error in image 2);
* ``n_hypotheses``: the iteration cap, ``RANSACOptions.max_num_trials``;
* ``confidence``: the stopping confidence, ``RANSACOptions.confidence``
  (default 0.995 as for OpenCV's estimators; COLMAP's own is 0.9999);
* ``min_iterations``: ``RANSACOptions.min_num_trials``, default 0 so that,
  like OpenCV, it stops as soon as ``confidence`` is reached (COLMAP's own
  default is 1000); capped at ``n_hypotheses``;
* ``rng``: ``RANSACOptions.random_seed`` is the first integer in
  ``[0, 2**31 - 1)`` drawn from ``as_generator(rng)``
  (``seed_of``), so an int ``rng`` gives the
  same result every time (``None``: a fresh random seed). COLMAP runs on one
  thread (``num_threads=1``).

COLMAP refines its own estimate: compare it as COLMAP returns it with
``fit(..., refine=False)`` (the protocol of
:func:`~clap_unified.imaging.estimate_homography`). The result's inliers are,
as for every strategy, the matches within ``threshold`` of the returned model
(forward transfer error); COLMAP's own mask is in
``diagnostics["colmap_mask"]``. Convention as everywhere here (and as
COLMAP's, checked on a known ``H``): rows ``(x1, y1, x2, y2)``,
``x2 ~ H x1``. Matches whose points in either image are all collinear or
identical are a failure before the peer runs (PoseLib would return a
homography that fits a line of points). pycolmap is imported only when the strategy runs.

Examples
--------
>>> import numpy as np
>>> from clap_unified import fit
>>> from clap_unified.spaces import HomographySpace
>>> rng = np.random.default_rng(0)
>>> src = rng.uniform(0, 640, (100, 2))
>>> res = fit(HomographySpace(), np.c_[src, src + [5.0, -3.0]], "colmap", rng=0,
...           refine=False)
>>> res.success, res.n_inliers, np.round(res.model[:2, 2], 3).tolist()
(True, 100, [5.0, -3.0])
"""

from __future__ import annotations

import numpy as np  # noqa: F401  (the doctests)

from ..registry import Strategy, register_strategy
from ..result import Consensus
from ._peers import run_peer

__all__ = ["run_colmap"]


def _import_pycolmap():
    try:
        import pycolmap
    except ImportError as exc:
        raise ImportError("method 'colmap' needs the package pycolmap "
                          "(pip install pycolmap)") from exc
    return pycolmap


def run_colmap(space, data, hypotheses, *, threshold: float, prior=None, radius=None,
               rng=None, n_hypotheses: int = 1000, confidence: float = 0.995,
               min_iterations: int = 0) -> Consensus:
    """``pycolmap.estimate_homography_matrix`` (or ``estimate_fundamental_matrix``).

    Parameters
    ----------
    space : HomographySpace or FundamentalSpace
    data : ndarray of shape (N, 4)
        Rows ``(x1, y1, x2, y2)``.
    hypotheses
        Unused (COLMAP draws its own samples).
    threshold : float
        ``max_error`` in pixels.
    prior, radius
        Unused.
    rng : None, int or numpy.random.Generator
        Source of COLMAP's ``random_seed``
        (``seed_of``).
    n_hypotheses : int
        ``max_num_trials``, the iteration cap.
    confidence : float
        ``confidence``, strictly between 0 and 1.
    min_iterations : int
        ``min_num_trials`` (at most ``n_hypotheses``).

    Returns
    -------
    Consensus
        The model with ``H33 = 1`` (fundamental matrices: unit Frobenius
        norm) and no clusters; score: the size of COLMAP's inlier mask.
        ``None`` (COLMAP's failure) or a non-finite answer, or degenerate
        matches, is a failure with a reason.

    Raises
    ------
    ImportError
        pycolmap is not installed.

    Examples
    --------
    >>> from clap_unified.spaces import HomographySpace
    >>> src = np.random.default_rng(1).uniform(0, 640, (50, 2))
    >>> c = run_colmap(HomographySpace(), np.c_[src, 2 * src], None, threshold=1.0, rng=0)
    >>> np.round(c.model, 6).tolist(), c.diagnostics["colmap_inliers"]
    ([[2.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 1.0]], 50)
    """
    pycolmap = _import_pycolmap()

    def call(src, dst, t, max_iterations, min_iter, conf, seed):
        opt = pycolmap.RANSACOptions(max_error=t, max_num_trials=max_iterations,
                                     min_num_trials=min_iter, confidence=conf,
                                     random_seed=seed, num_threads=1)
        if fundamental:
            answer = pycolmap.estimate_fundamental_matrix(src, dst, opt)
        else:
            answer = pycolmap.estimate_homography_matrix(src, dst, opt)
        if answer is None:
            return None, [], {}
        return answer["F" if fundamental else "H"], answer.get("inlier_mask", []), {}

    fundamental = space.name == "fundamental"
    return run_peer("COLMAP", "colmap", call, data, threshold=threshold, rng=rng,
                    n_hypotheses=n_hypotheses, confidence=confidence,
                    min_iterations=min_iterations, space_name=space.name)


register_strategy(Strategy(
    "colmap", run_colmap, uses_hypotheses=False, applies_to=("homography", "fundamental"),
    baseline=True,
    summary="COLMAP's pycolmap.estimate_homography_matrix / estimate_fundamental_matrix "
            "(LO-RANSAC)"))
