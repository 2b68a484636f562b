"""Planar homographies as a matrix group, and the paper's homography distances.

A homography is a 3 x 3 matrix up to scale (convention ``x2 ~ H x1``). Two
normalisations pick a representative:

* ``"h33"`` (the paper's evaluation convention): ``H[2, 2] = 1``. Matrices
  with ``H[2, 2] = 0`` have no such representative and raise ``ValueError``.
* ``"det"`` (the group SL(3)): ``det H = 1``, dividing by the real cube root
  of the determinant (which also fixes the sign).

Neither distance here is a true metric on homographies, see
:func:`lie_distance` and :func:`frobenius_distance`.
"""

from __future__ import annotations

import numpy as np

from .._validation import check_array, check_choice
from ._matrix import expm, logm
from .base import MatrixLieGroup

__all__ = ["Homography", "frobenius_distance", "lie_distance", "normalise_h33"]

#: |H[2, 2]| below this fraction of max |H_ij| counts as zero.
_ZERO = 1e-12


def normalise_h33(H, name: str = "H", *, check_invertible: bool = True) -> np.ndarray:
    """Scale homographies so that ``H[2, 2] = 1``.

    Parameters
    ----------
    H : ndarray of shape (..., 3, 3)
    name : str
        Argument name used in error messages.
    check_invertible : bool
        Refuse singular matrices (Hadamard's bound, below). A caller that tests
        invertibility in a better-conditioned frame (the data's normalised frame)
        passes False.

    Returns
    -------
    ndarray of shape (..., 3, 3)

    Raises
    ------
    ValueError
        Naming ``name``, when ``H`` is not a stack of finite 3 x 3 matrices or
        some ``|H[2, 2]|`` is zero or below ``1e-12 max |H_ij|`` (no such
        scaling exists; never a silent division by zero), or some matrix is
        singular (``check_invertible``).

    Examples
    --------
    >>> normalise_h33(np.diag([2.0, 2.0, 4.0])).diagonal().tolist()
    [0.5, 0.5, 1.0]
    """
    H = check_array(H, name, shape=(Ellipsis, 3, 3))
    h33 = H[..., 2, 2]
    bad = ~(np.abs(h33) > _ZERO * np.abs(H).max(axis=(-2, -1)))
    if np.any(bad):
        raise ValueError(f"{name}: H[2, 2] is zero in {int(bad.sum())} matrix(es), "
                         "cannot normalise so that H33 = 1")
    if check_invertible:
        _check_invertible(H, name)
    return H / h33[..., None, None]


def _check_invertible(H, name: str, det=None) -> np.ndarray:
    """Determinants of ``(..., 3, 3)`` matrices; ``ValueError`` if some is singular.

    Singular means ``|det H| <= 1e-13 prod_i |row_i|`` (Hadamard's bound makes
    the ratio scale-free, in [0, 1]); such a matrix is no homography and has no
    logarithm. ``det`` may be given when the caller has it already.
    """
    det = np.linalg.det(H) if det is None else det
    bound = np.prod(np.linalg.norm(H, axis=-1), axis=-1)
    bad = ~(np.abs(det) > 1e-13 * bound)
    if np.any(bad):
        raise ValueError(f"{name}: {int(bad.sum())} singular matrix(es) (det = 0), "
                         "not a homography")
    return det


def _normalise_det(H, name: str) -> np.ndarray:
    H = check_array(H, name, shape=(Ellipsis, 3, 3))
    return H / np.cbrt(_check_invertible(H, name))[..., None, None]


def _relative_log(A, B) -> np.ndarray:
    """``logm(B^-1 A)`` for normalised stacks that broadcast; inverts only the distinct B."""
    return logm(np.matmul(np.linalg.inv(B), A))


def _fro(L) -> np.ndarray:
    L = np.abs(L) if np.iscomplexobj(L) else L
    return np.sqrt(np.einsum("...ij,...ij->...", L, L))


def lie_distance(H, H_gt) -> np.ndarray:
    """The paper's evaluation metric ``d(H, H_gt) = ||log(H_gt^-1 H)||_F``.

    Both matrices are first normalised so that ``H33 = 1``; ``log`` is the
    principal matrix logarithm (:func:`~clap_unified.geometry._matrix.logm`;
    complex when ``H_gt^-1 H`` has a negative real eigenvalue, its Frobenius
    norm ``sqrt(sum |L_ij|^2)`` is still defined). Equals
    ``Homography("h33").distance(H_gt, H)``.

    Not a true metric: it is zero only for equal normalised matrices and
    symmetric (for the principal log, when ``H_gt^-1 H`` has no eigenvalue on
    the negative real axis), but it fails the triangle inequality in general,
    and because of the ``H33 = 1`` scaling it is not exactly left-invariant.

    Parameters
    ----------
    H : ndarray of shape (..., 3, 3)
        Estimates.
    H_gt : ndarray of shape (..., 3, 3)
        Ground truth; broadcast against ``H``.

    Returns
    -------
    ndarray of shape (...)

    Raises
    ------
    ValueError
        Naming ``H`` or ``H_gt`` for a wrong shape, non-finite entries or
        ``H33 = 0`` or a singular matrix.

    Examples
    --------
    >>> H_gt = np.array([[1.0, 0.1, 5.0], [0.0, 1.0, -3.0], [0.0, 0.001, 1.0]])
    >>> H = H_gt @ np.diag([1.1, 1.0, 1.0])
    >>> print(f"{float(lie_distance(H, H_gt)):.6f}")
    0.095310
    >>> lie_distance(np.stack([H, 2 * H_gt]), H_gt).round(6).tolist()
    [0.09531, 0.0]
    """
    A = normalise_h33(H, "H")
    B = normalise_h33(H_gt, "H_gt")
    return _fro(_relative_log(A, B))


def frobenius_distance(H1, H2, *, normalization: str = "h33") -> np.ndarray:
    """Frobenius norm ``||H1 - H2||_F`` of the normalised matrices.

    It is a metric on the normalised representatives, but not on
    homographies as such: it is not invariant to a change of image
    coordinates (neither left- nor right-invariant), weighs translation
    entries in pixels against dimensionless ones, and is undefined for
    ``H33 = 0`` with ``"h33"``.

    Parameters
    ----------
    H1, H2 : ndarray of shape (..., 3, 3)
        Broadcast against each other.
    normalization : {"h33", "det"}

    Returns
    -------
    ndarray of shape (...)

    Examples
    --------
    >>> H = np.array([[1.0, 0.0, 2.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    >>> print(f"{float(frobenius_distance(3 * H, np.eye(3))):.6f}")
    2.000000
    """
    check_choice(normalization, "normalization", {"h33", "det"})
    norm = normalise_h33 if normalization == "h33" else _normalise_det
    D = norm(H1, "H1") - norm(H2, "H2")
    return np.sqrt(np.einsum("...ij,...ij->...", D, D))


class Homography(MatrixLieGroup):
    """Planar homographies, points of shape ``(..., 3, 3)``.

    Every point is kept normalised (:meth:`projection`). The chart at a base
    point ``B`` is ``log(H, B) = vee(logm(B^-1 H))`` for the normalised ``B``
    and ``H``: the 9 entries of the (real or complex) principal matrix
    logarithm, flattened row-major (``dim = 9``). With ``"det"`` the relative
    matrix has determinant 1, so the logarithm is traceless (8 degrees of
    freedom, the Lie algebra sl(3)). With ``"h33"`` the relative matrix is not
    re-normalised (this is the paper's metric, :func:`lie_distance`), so the
    9 coordinates describe an 8-dimensional set: ``log(exp(xi, B), B) = xi``
    holds for tangent vectors that are logarithms of normalised points,
    ``xi = log(H, B)``, not for every ``xi``.

    :meth:`exp` returns ``projection(B expm(hat(xi)))``; for a complex ``xi``
    (possible when a relative matrix has negative eigenvalues) the real part
    of the product is used.

    The distance ``||log(H2, H1)||_F`` is symmetric for the principal log but
    not a true metric: the triangle inequality fails in general. With
    ``"det"`` it is left-invariant, ``d(G H1, G H2) = d(H1, H2)``; with
    ``"h33"`` it is not exactly left-invariant, because normalising ``G H1``
    and ``G H2`` rescales them by different factors.

    Parameters
    ----------
    normalization : {"h33", "det"}
        ``"h33"``: scale so that ``H[2, 2] = 1`` (the paper's convention);
        ``"det"``: scale to determinant 1 (SL(3)).

    Examples
    --------
    >>> g = Homography()
    >>> H = np.array([[1.0, 0.1, 5.0], [0.0, 1.0, 0.0], [0.0, 0.0, 2.0]])
    >>> print(f"{float(g.projection(H)[2, 2]):.1f}")
    1.0
    >>> D = g.pairwise_distance(g.random(3, rng=0, scale=0.1))
    >>> bool(np.allclose(D, D.T)), bool(np.all(np.diag(D) == 0))
    (True, True)
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
        """Normalise ``(..., 3, 3)`` matrices (``H33 = 1`` or ``det = 1``).

        Raises ``ValueError`` naming ``name`` for a wrong shape, non-finite
        entries, ``H33 = 0`` (``"h33"``) or a singular matrix.
        """
        if self.normalization == "h33":
            return normalise_h33(points, name)
        return _normalise_det(points, name)

    def compose(self, a, b) -> np.ndarray:
        """Normalised product ``a b``."""
        return self.projection(np.matmul(a, b), "H")

    def inverse(self, a) -> np.ndarray:
        """Normalised inverse."""
        return self.projection(np.linalg.inv(self.projection(a, "H")), "H")

    def hat(self, tangent) -> np.ndarray:
        """``(..., 9) -> (..., 3, 3)``, row-major."""
        t = np.asarray(tangent)
        return t.reshape(*t.shape[:-1], 3, 3)

    def vee(self, matrix) -> np.ndarray:
        """``(..., 3, 3) -> (..., 9)``, row-major."""
        m = np.asarray(matrix)
        return m.reshape(*m.shape[:-2], 9)

    def expmap(self, tangent) -> np.ndarray:
        """``projection(expm(hat(tangent)))`` (real part for complex tangents)."""
        E = expm(self.hat(tangent))
        return self.projection(E.real if np.iscomplexobj(E) else E, "H")

    def logmap(self, point) -> np.ndarray:
        """``vee(logm(projection(point)))``, equal to ``log(point, identity)``."""
        return self.vee(logm(self.projection(point, "point")))

    def log(self, point, base_point) -> np.ndarray:
        """``vee(logm(B^-1 H))`` of the normalised matrices, broadcast over leading axes."""
        A = self.projection(point, "point")
        B = self.projection(base_point, "base_point")
        return self.vee(_relative_log(A, B))

    def exp(self, tangent, base_point) -> np.ndarray:
        """``projection(B expm(hat(tangent)))`` with ``B`` normalised."""
        B = self.projection(base_point, "base_point")
        E = np.matmul(B, expm(self.hat(tangent)))
        return self.projection(E.real if np.iscomplexobj(E) else E, "H")
