"""Planar homographies as a matrix group, and the paper's homography distances."""

from __future__ import annotations

import numpy as np

from .._validation import check_array, check_choice
from ._matrix import expm, logm
from .base import MatrixLieGroup

__all__ = ["Homography", "frobenius_distance", "lie_distance", "normalise_h33"]


def normalise_h33(H, name: str = "H") -> np.ndarray:
    """Scale homographies ``(..., 3, 3)`` so that ``H[2, 2] = 1``.

    Raises ``ValueError`` naming ``name`` when some ``H[2, 2]`` is zero (or
    negligible against the matrix): no such scaling exists.
    """
    H = check_array(H, name, shape=(Ellipsis, 3, 3))
    h33 = H[..., 2, 2]
    if np.any(np.abs(h33) <= 1e-12 * np.abs(H).max(axis=(-2, -1))):
        raise ValueError(f"{name}: H[2, 2] is zero, cannot normalise so that H33 = 1")
    return H / h33[..., None, None]


def lie_distance(H, H_gt) -> np.ndarray:
    """The paper's evaluation metric ``||log(H_gt^-1 H)||_F`` (Figs. 6-8 captions).

    Both matrices are first normalised so that ``H33 = 1``; ``log`` is the
    principal matrix logarithm (complex when ``H_gt^-1 H`` has a negative real
    eigenvalue; its Frobenius norm is still defined). Batched over leading axes.
    Not a true metric: symmetric, zero only for equal normalised matrices, but
    the triangle inequality can fail.

    Examples
    --------
    >>> H = np.diag([1.1, 1.0, 1.0])
    >>> print(f"{float(lie_distance(H, np.eye(3))):.6f}")
    0.095310
    """
    A = normalise_h33(H, "H")
    B = normalise_h33(H_gt, "H_gt")
    L = logm(np.linalg.solve(B, A))
    return np.sqrt(np.sum(np.abs(L) ** 2, axis=(-2, -1)))


def frobenius_distance(H1, H2) -> np.ndarray:
    """``||H1 - H2||_F`` of the ``H33 = 1`` normalised matrices (a true metric on them,
    but not invariant to a change of image coordinates)."""
    return np.sqrt(np.sum((normalise_h33(H1, "H1") - normalise_h33(H2, "H2")) ** 2,
                          axis=(-2, -1)))


class Homography(MatrixLieGroup):
    """Planar homographies ``(..., 3, 3)`` with the chart ``log(H_base^-1 H)``.

    Parameters
    ----------
    normalization : {"h33", "det"}
        ``"h33"``: scale so that ``H[2, 2] = 1`` (the paper's convention).
        ``"det"``: scale to determinant 1 (the group SL(3); the logarithm is
        then traceless, 8 degrees of freedom).

    Notes
    -----
    The tangent vector is the 3 x 3 logarithm flattened row-major (9 numbers;
    complex where the principal logarithm is). The distance
    ``||log(H1^-1 H2)||_F`` is symmetric but not a true metric; with
    ``"det"`` it is left-invariant, with ``"h33"`` only up to the scale the
    normalisation introduces.

    Examples
    --------
    >>> g = Homography()
    >>> H = np.array([[1.0, 0.1, 5.0], [0.0, 1.0, 0.0], [0.0, 0.0, 2.0]])
    >>> g.projection(H)[2, 2]
    np.float64(1.0)
    """

    dim = 9
    matrix_size = 3
    is_metric = False
    name = "homographies"

    def __init__(self, normalization: str = "h33"):
        self.normalization = check_choice(normalization, "normalization", {"h33", "det"})
        super().__init__()

    def __repr__(self) -> str:
        return f"Homography(normalization={self.normalization!r})"

    def projection(self, points, name: str = "H") -> np.ndarray:
        H = check_array(points, name, shape=(Ellipsis, 3, 3))
        if self.normalization == "h33":
            return normalise_h33(H, name)
        det = np.linalg.det(H)
        if np.any(det == 0):
            raise ValueError(f"{name}: singular matrix, cannot normalise to det = 1")
        return H / np.cbrt(det)[..., None, None]

    def hat(self, tangent) -> np.ndarray:
        t = np.asarray(tangent)
        return t.reshape(*t.shape[:-1], 3, 3)

    def vee(self, matrix) -> np.ndarray:
        m = np.asarray(matrix)
        return m.reshape(*m.shape[:-2], 9)

    def expmap(self, tangent) -> np.ndarray:
        return expm(self.hat(tangent))

    def logmap(self, point) -> np.ndarray:
        return self.vee(logm(point))

    def log(self, point, base_point) -> np.ndarray:
        A = self.projection(point, "point")
        B = self.projection(base_point, "base_point")
        A, B = np.broadcast_arrays(A, B)
        return self.logmap(np.linalg.solve(B, A))

    def exp(self, tangent, base_point) -> np.ndarray:
        out = np.matmul(self.projection(base_point, "base_point"), self.expmap(tangent))
        return self.projection(out.real if np.iscomplexobj(out) else out, "H")
