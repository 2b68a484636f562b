"""Shared by the wrappers of other libraries' estimators (OpenCV, PoseLib, COLMAP).

They estimate homographies and fundamental matrices; :data:`MODELS` names
the model of each space and says how it is normalised (``H33 = 1``, or unit
Frobenius norm with the largest entry positive).
"""

from __future__ import annotations

import numpy as np

from .._validation import as_generator, check_fraction, check_int
from ..geometry.projective import normalise_projective
from ..result import Consensus

__all__ = ["MODELS", "degenerate_reason", "normalise_model", "run_peer", "seed_of"]

#: Space name -> the model's name in reasons.
MODELS = {"homography": "homography", "fundamental": "fundamental matrix"}


def normalise_model(M, space_name: str = "homography"):
    """A peer's model in the space's normalisation, or None when it has none.

    Homographies: ``H / H33`` (None when ``H33`` is zero); fundamental
    matrices: unit Frobenius norm, largest-magnitude entry positive. None for
    a non-finite model.

    Examples
    --------
    >>> normalise_model(np.diag([2.0, 2.0, 2.0])).tolist()
    [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    >>> normalise_model(np.diag([0.0, 0.0, -2.0]), "fundamental").tolist()[2]
    [0.0, 0.0, 1.0]
    """
    M = np.asarray(M, dtype=float)
    if M.shape != (3, 3) or not np.all(np.isfinite(M)):
        return None
    if space_name == "fundamental":
        M = normalise_projective(M)
        return M if np.all(np.isfinite(M)) else None
    return None if abs(M[2, 2]) < 1e-12 else M / M[2, 2]


def seed_of(rng) -> int:
    """The integer seed a peer library receives: the first draw of ``as_generator(rng)``.

    Parameters
    ----------
    rng : None, int or numpy.random.Generator

    Returns
    -------
    int
        In ``[0, 2**31 - 1)``; the same for the same int ``rng``.

    Examples
    --------
    >>> seed_of(0) == seed_of(0)
    True
    """
    return int(as_generator(rng).integers(0, 2**31 - 1))


def degenerate_reason(data) -> str | None:
    """Why the matches determine no homography or fundamental matrix, or None.

    The points of either image all identical or all on one line leave a
    homography (and a fundamental matrix) undetermined: a peer may still
    return one that fits them (PoseLib does, for collinear points), which is
    no answer.

    Parameters
    ----------
    data : ndarray of shape (N, 4)
        Rows ``(x1, y1, x2, y2)``.

    Returns
    -------
    str or None

    Examples
    --------
    >>> t = np.arange(10.0)
    >>> degenerate_reason(np.c_[t, 2 * t, t, t ** 2])
    'the points of image 1 are collinear or identical'
    >>> degenerate_reason(np.c_[t, t ** 2, t, t ** 2]) is None
    True
    """
    for k, cols in ((1, slice(0, 2)), (2, slice(2, 4))):
        p = np.asarray(data[:, cols], dtype=float)
        s = np.linalg.svd(p - p.mean(0), compute_uv=False)
        if s[-1] <= 1e-9 * max(s[0], 1.0):
            return f"the points of image {k} are collinear or identical"
    return None


def run_peer(label: str, key: str, call, data, *, threshold: float, rng, n_hypotheses: int,
             confidence: float, min_iterations: int,
             space_name: str = "homography") -> Consensus:
    """The body every peer strategy shares: checks, seed, degeneracy, the call, the result.

    Parameters
    ----------
    label : str
        The peer's name in reasons (``"PoseLib"``).
    key : str
        Prefix of its diagnostics (``"poselib"``: ``poselib_mask``,
        ``poselib_inliers``).
    call : callable
        ``call(src, dst, threshold, max_iterations, min_iterations,
        confidence, seed) -> (model or None, mask, extra_diagnostics)``.
    data : ndarray of shape (N, 4)
        Checked matches.
    threshold, rng, n_hypotheses, confidence, min_iterations
        As documented by the strategies (:func:`~clap_unified.external.poselib.run_poselib`).
    space_name : {"homography", "fundamental"}
        The model estimated (:data:`MODELS`).

    Returns
    -------
    Consensus
        The model normalised as its space's (:func:`normalise_model`), score:
        the size of the peer's inlier mask; a failure with a reason for
        degenerate matches, no answer, a non-finite answer or an empty mask.

    Examples
    --------
    >>> t = np.arange(10.0)
    >>> data = np.c_[t, t ** 2, t, t ** 2]
    >>> c = run_peer("Identity", "id", lambda *a: (np.eye(3), np.ones(10, bool), {}), data,
    ...              threshold=1.0, rng=0, n_hypotheses=10, confidence=0.99, min_iterations=0)
    >>> c.model.tolist() == np.eye(3).tolist(), c.diagnostics["id_inliers"]
    (True, 10)
    """
    confidence = check_fraction(confidence, "confidence", inclusive=(False, False))
    min_iterations = check_int(min_iterations, "min_iterations", minimum=0)
    seed = seed_of(rng)
    what = MODELS[space_name]
    why = degenerate_reason(data)
    if why is not None:
        return Consensus.failed(f"no {what}: {why}", seed=seed)
    src = np.ascontiguousarray(data[:, :2], dtype=np.float64)
    dst = np.ascontiguousarray(data[:, 2:], dtype=np.float64)
    M, mask, extra = call(src, dst, float(threshold), int(n_hypotheses),
                          min(min_iterations, int(n_hypotheses)), confidence, seed)
    if M is None:
        return Consensus.failed(f"{label} found no {what}", seed=seed)
    mask = np.asarray(mask, dtype=bool).reshape(-1)
    if len(mask) != len(data):
        mask = np.zeros(len(data), bool)
    diagnostics = {f"{key}_mask": mask, f"{key}_inliers": int(mask.sum()), **extra,
                   "seed": seed}
    model = normalise_model(M, space_name)
    if model is None:
        return Consensus.failed(f"{label} found no {what} (non-finite model)", **diagnostics)
    if not mask.any():
        return Consensus.failed(f"{label} found no {what} (no inliers)", **diagnostics)
    return Consensus(model, score=float(mask.sum()), diagnostics=diagnostics)
