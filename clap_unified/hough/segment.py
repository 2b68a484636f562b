"""The peaks of the randomized Hough accumulator as several models (a segmenter)."""

from __future__ import annotations

import numpy as np

from .._validation import check_int
from ..partition import select_models
from ..registry import Segmenter, register_segmenter
from ..result import Segmentation
from .randomized import run_randomized_hough

__all__ = ["run_hough_segment"]


def run_hough_segment(space, data, hypotheses, *, threshold: float, rng=None,
                      n_hypotheses: int = 0, min_support: int, cell_size=None,
                      num_peaks: int = 60, max_models: int = 20) -> Segmentation:
    """The accumulator's peaks, by votes, while each explains ``min_support`` new data.

    The classical Hough answer to several structures: every well-separated
    peak is one (:func:`~clap_unified.hough.run_randomized_hough` with
    ``num_peaks``); a peak whose data the fuller peaks already explain is
    dropped (:func:`~clap_unified.partition.select_models`).

    Returns
    -------
    Segmentation
        ``scores``: the votes of each peak kept.
    """
    num_peaks = check_int(num_peaks, "num_peaks", minimum=1)
    if hypotheses is None or len(hypotheses) == 0:
        return Segmentation(np.empty((0, *space.model_shape)), np.zeros(0),
                            reason="no hypotheses: every minimal sample was degenerate")
    found = run_randomized_hough(space, data, hypotheses, threshold=threshold,
                                 cell_size=cell_size, num_peaks=num_peaks)
    peaks = np.array([c.model for c in found.clusters]).reshape(-1, *space.model_shape)
    votes = np.array([c.support for c in found.clusters], dtype=float)
    kept = select_models(space, peaks, data, threshold, min_support, max_models)
    return Segmentation(peaks[kept], votes[kept],
                        selection=f"peaks by votes while each explains {min_support} new data "
                                  f"({len(peaks)} peaks)",
                        diagnostics={"peaks": int(len(peaks))})


register_segmenter(Segmenter(
    "randomized_hough", run_hough_segment,
    summary="the accumulator's peaks while each explains new data"))
