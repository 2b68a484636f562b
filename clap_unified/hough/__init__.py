"""Hough transforms: clustering on a grid."""

from .accumulator import LineAccumulator, line_accumulator
from .classical import hough_lines, run_hough
from .peaks import accumulator_peaks, sparse_peaks
from .randomized import bin_hypotheses, randomized_hough, run_randomized_hough
from .segment import run_hough_segment

__all__ = ["LineAccumulator", "accumulator_peaks", "bin_hypotheses", "hough_lines",
           "line_accumulator", "randomized_hough", "run_hough", "run_hough_segment",
           "run_randomized_hough", "sparse_peaks"]
