"""The one localization pipeline of 2D and 3D: candidates from the map, then :func:`fit`.

What differs between the RoboCup field and a 3D map is the hypothesis space
(and the map inside it), not the pipeline:
:func:`~clap_unified.localization.localize2d`,
:func:`~clap_unified.localization.localize3d` and
:func:`~clap_unified.localization.align_correspondences` parse their inputs
into the space's data and call :func:`localize`.

:func:`localize` generates the candidate poses once (``space.hypotheses``,
from the prior's association where the space builds them so) and hands them
to :func:`~clap_unified.fit`, which gates them around the prior
(``space.near_prior``), runs the strategy and refines its pose on the
inliers. Every candidate counts: RANSAC's trial budget is the candidate
count, so it scores all of them, as CLAP clusters all of them.
"""

from __future__ import annotations

from .._validation import Checked, check_int
from ..fitting import fit
from ..registry import get_strategy
from ..result import ConsensusResult

__all__ = ["localize"]


def localize(space, data, method: str = "clap", *, prior=None, radius=None,
             n_hypotheses: int = 1000, threshold: float | None = None, rng=None,
             hypotheses=None, sampling: dict | None = None, **options) -> ConsensusResult:
    """A pose from one frame of data by the strategy ``method``, on all the candidates.

    Parameters
    ----------
    space : HypothesisSpace
        A pose space holding its map (``Landmark2DSpace``, ``Landmark3DSpace``,
        ``Correspondence3DSpace``).
    data : array_like
        One frame in the space's format (the caller has refused simulated
        frames that carry the truth).
    method : str
        A strategy registered for the space.
    prior, radius
        A previous estimate and the gate around it (what ``space.near_prior``
        accepts); a space with ``prior_hypotheses`` also builds its candidates
        from the prior's association.
    n_hypotheses : int
        Candidate budget of the generation; for a strategy that reads the
        data only (Open3D), its own budget (iterations).
    threshold : float, optional
        Inlier threshold, metres (default: the space's).
    rng : None, int or numpy.random.Generator
    hypotheses : HypothesisSet, optional
        Reuse candidates (e.g. to compare strategies on identical ones).
    sampling : dict, optional
        Space-specific options of the candidate generation.
    **options
        The strategy's own options.

    Returns
    -------
    ConsensusResult
        From :func:`~clap_unified.fit`: ``diagnostics["hypotheses"]`` counts
        the candidate poses (``diagnostics["candidates"]`` the pairs handed
        to an external estimator). Fewer observations than a minimal sample,
        or no candidate, give ``success=False`` with the reason.

    Examples
    --------
    >>> import numpy as np
    >>> from clap_unified.geometry import SE2
    >>> from clap_unified.maps import LANDMARK_TYPES, load_field
    >>> from clap_unified.spaces.landmarks2d import Landmark2DSpace
    >>> space = Landmark2DSpace(load_field("adult"))
    >>> truth = SE2.from_xytheta(2.0, -1.0, 0.3)
    >>> marks = space.field.positions[:6]
    >>> local = (np.linalg.inv(truth) @ np.c_[marks, np.ones(6)].T).T[:, :2]
    >>> ids = [LANDMARK_TYPES.index(t) for t in space.field.types[:6]]
    >>> res = localize(space, np.c_[ids, local], "ransac")
    >>> res.diagnostics["hypotheses"] > 1, np.round(SE2.to_xytheta(res.model), 6).tolist()
    (True, [2.0, -1.0, 0.3])
    """
    strategy = get_strategy(method, space)
    if isinstance(data, Checked):  # checked by the caller (localize3d)
        data = data.data
    else:
        if len(data) < space.min_samples:
            return ConsensusResult.failure(
                method, f"observations: {len(data)} given, a pose needs at least "
                f"{space.min_samples}", len(data), 0, space, hypotheses=0)
        data = space.check_data(data)
    n = len(data)
    if strategy.uses_hypotheses:
        if hypotheses is None:
            hypotheses = space.hypotheses(data, check_int(n_hypotheses, "n_hypotheses", minimum=1),
                                          rng=rng, prior=prior, radius=radius, **(sampling or {}))
        if len(hypotheses) == 0:
            where = "" if prior is None else " in the prior's association"
            return ConsensusResult.failure(method, f"no candidate pose{where}: no minimal sample "
                                           "matches the map", n, 0, space, hypotheses=0)
        n_hypotheses = len(hypotheses)  # every candidate is scored
    return fit(space, Checked(data), method, n_hypotheses=n_hypotheses, threshold=threshold,
               rng=rng, hypotheses=hypotheses if strategy.uses_hypotheses else None, prior=prior,
               radius=radius, **options)
