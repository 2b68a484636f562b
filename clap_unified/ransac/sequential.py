"""Sequential fitting: the best model, its inliers removed, again (a segmenter).

The classical multi-model baseline (Vincent and Laganiere, 2001; Kanazawa and
Kawakami, 2004): run a single-model strategy, take its model and remove its
inliers, repeat on what is left until a model explains fewer than
``min_support`` data. Registered as the ``"ransac"`` segmenter, and, by
:mod:`clap_unified.external`, for other libraries' estimators (OpenCV's
MAGSAC++ in a remove-inliers loop).
"""

from __future__ import annotations

import numpy as np

from .._validation import Checked, as_generator, check_int
from ..fitting import fit
from ..registry import Segmenter, register_segmenter
from ..result import Segmentation

__all__ = ["run_sequential"]


def run_sequential(space, data, hypotheses=None, *, threshold: float, rng=None,
                   n_hypotheses: int = 1000, min_support: int, strategy: str = "ransac",
                   neighbours: int | None = None, max_models: int = 20) -> Segmentation:
    """Fit, remove the inliers, fit again: ``strategy`` run on what is left each round.

    Parameters
    ----------
    space, data, threshold, rng, n_hypotheses
        As :func:`~clap_unified.segment` gives them; each round is
        ``fit(space, rest, strategy, n_hypotheses=n_hypotheses, rng=...)``
        on the data not yet explained, with one generator continued.
    hypotheses
        Unused: each round draws its own from the data left.
    min_support : int
        A round whose model explains fewer data ends the loop.
    strategy : str
        The single-model strategy of each round.
    neighbours : int, optional
        Local sampling in each round (``space.hypotheses(...,
        neighbours=...)``), for a strategy that uses hypotheses.
    max_models : int

    Returns
    -------
    Segmentation
        Models in the order found; ``scores``: their inliers when found.
    """
    max_models = check_int(max_models, "max_models", minimum=1)
    g = as_generator(rng)
    rest = np.arange(len(data))
    models, scores = [], []
    reason = "ok"
    while len(models) < max_models and len(rest) >= max(min_support, space.min_samples):
        hyps = (space.hypotheses(data[rest], n_hypotheses, rng=g, neighbours=neighbours)
                if neighbours is not None else None)
        res = fit(space, Checked(data[rest]), strategy, n_hypotheses=n_hypotheses,
                  threshold=threshold, rng=g, hypotheses=hyps)
        if not res.success or res.n_inliers < min_support:
            if not models:
                reason = (res.reason if not res.success else
                          f"the best model explains {res.n_inliers} data, fewer than "
                          f"min_support={min_support}")
            break
        models.append(res.model)
        scores.append(res.n_inliers)
        rest = rest[~res.inliers]
    models = np.array(models).reshape(-1, *space.model_shape)
    return Segmentation(models, np.array(scores, dtype=float), reason=reason,
                        selection=f"{strategy} on the data left until a model explains fewer "
                                  f"than {min_support}")


register_segmenter(Segmenter(
    "ransac", run_sequential, uses_hypotheses=False,
    summary="sequential RANSAC: fit, remove the inliers, repeat"))
