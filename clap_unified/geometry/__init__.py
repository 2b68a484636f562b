"""Geometry: the manifolds and Lie groups hypotheses live in.

* :class:`Euclidean`: R^d, flat (input space, plain parameter vectors);
* :class:`Line2D`: lines in the plane (a chart, not a group);
* :class:`LineND`: lines in ``R^d`` as ``(origin, direction)`` (scikit-image's
  ``LineModelND``), with :func:`line_residuals`, :func:`points_at` and
  :func:`predict_coordinate`;
* :class:`SE2`, :class:`SE3`: rigid motions, and :func:`kabsch`, the weighted
  least-squares motion between corresponding points in the plane or space;
* :class:`ProjectiveMatrices`: 3 x 3 matrices up to scale and sign (fundamental
  matrices), with the epipolar arithmetic :func:`seven_point`,
  :func:`eight_point` and :func:`sampson_error`;
* :class:`Homography`: planar homographies (PGL(3) with the ``H33 = 1`` or
  ``det = 1`` normalisation), with the paper's :func:`lie_distance`;
* plain batched array functions: SO(3) maps (``so3_*``) and the matrix
  :func:`expm` / principal :func:`logm`.
"""

from ._matrix import expm, logm
from .base import Manifold, MatrixLieGroup
from .euclidean import Euclidean
from .fundamental import eight_point, sampson_error, seven_point
from .homography import Homography, frobenius_distance, lie_distance, normalise_h33
from .lines import Line2D, canonical_lines, wrap_angle
from .lines_nd import (
    LineND,
    canonical_lines_nd,
    line_residuals,
    points_at,
    predict_coordinate,
)
from .projective import ProjectiveMatrices, normalise_projective
from .rigid import kabsch
from .se2 import SE2
from .se3 import SE3
from .so3 import (
    so3_exp,
    so3_hat,
    so3_left_jacobian,
    so3_left_jacobian_inverse,
    so3_log,
    so3_vee,
)

__all__ = ["SE2", "SE3", "Euclidean", "Homography", "Line2D", "LineND", "Manifold",
           "MatrixLieGroup", "ProjectiveMatrices", "canonical_lines", "canonical_lines_nd",
           "eight_point", "expm", "frobenius_distance", "kabsch", "lie_distance",
           "line_residuals", "logm", "normalise_h33", "normalise_projective", "points_at",
           "predict_coordinate",
           "sampson_error", "seven_point", "so3_exp", "so3_hat", "so3_left_jacobian",
           "so3_left_jacobian_inverse", "so3_log", "so3_vee", "wrap_angle"]
