"""3 x 3 matrices up to scale and sign: the projective space P^8, with a frame.

A fundamental matrix ``F`` is defined up to scale (``F``, ``-F`` and ``2 F``
are one model), so its hypotheses live in the real projective space of
3 x 3 matrices. :class:`ProjectiveMatrices` compares them there:

* each matrix ``P`` is first expressed in a frame, ``G = L P R`` (for
  fundamental matrices ``L = T2^-T`` and ``R = T1^-1`` with the Hartley
  normalisations ``T1``, ``T2`` of the two images' points: ``G`` is ``F`` in
  normalised coordinates, entries of order one; without a frame the entries
  of a pixel ``F`` differ by orders of magnitude and the last row and column
  dominate every distance), then scaled to a unit 9-vector ``u``;
* the distance is the angle between the lines spanned by ``u`` and ``v``,
  ``d = 2 arcsin(min(||u - v||, ||u + v||) / 2)`` in ``[0, pi / 2]`` (the
  Fubini-Study metric of ``RP^8``): a true metric on the projective space, and
  on matrices a metric up to scale and sign (``d(F, -F) = d(F, 2 F) = 0``);
* ``log`` and ``exp`` are those of the unit sphere ``S^8`` at the base, with
  the point's sign chosen on the base's side, in coordinates of an
  orthonormal basis of the tangent space (a Householder reflection), so the
  Karcher mean, the median and the randomized Hough chart work unchanged;
* the chordal embedding ``u -> vec(u u^T) / sqrt(2)`` (45 numbers: the upper
  triangle, off-diagonal entries times ``sqrt(2)``) does not depend on the
  sign of ``u``, and its Euclidean distance is ``sin(d) <= d``: it bounds the
  distance from below, so CLAP's ``prune`` (a k-d tree count at twice the
  bandwidth) loses no cluster member. The class does not declare
  ``embedding_bounds_distance`` all the same: in 45 dimensions a k-d tree
  prunes little, and blocks of one matrix product of the unit vectors answer
  CLAP's neighbour queries faster (no benchmark of the library repeats that
  comparison; ``bench/bench_fundamental.py`` times CLAP on fundamental
  matrices as it is), so beyond its dense limit CLAP takes the blocked path.

Points returned by ``exp`` and the means are in the original (pixel) frame,
scaled to unit Frobenius norm with their entry of largest magnitude positive
(:func:`normalise_projective`).
"""

from __future__ import annotations

import numpy as np

from .._validation import check_array
from .base import Manifold

__all__ = ["ProjectiveMatrices", "normalise_projective"]

_UPPER = np.triu_indices(9)
_UPPER_WEIGHT = np.where(_UPPER[0] == _UPPER[1], 1.0 / np.sqrt(2.0), 1.0)


def normalise_projective(P) -> np.ndarray:
    """Matrices scaled to unit Frobenius norm, their largest-magnitude entry positive.

    One representative of each projective class, batched over leading axes
    (a zero matrix gives NaN).

    Examples
    --------
    >>> normalise_projective(np.diag([-2.0, 0.0, 0.0])).tolist()
    [[1.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]
    """
    P = np.asarray(P, dtype=float)
    flat = P.reshape(*P.shape[:-2], 9)
    big = np.take_along_axis(flat, np.argmax(np.abs(flat), axis=-1)[..., None], axis=-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        scale = np.where(big < 0, -1.0, 1.0) / np.linalg.norm(flat, axis=-1, keepdims=True)
    return (flat * scale + 0.0).reshape(P.shape)  # + 0.0: no negative zeros


def _householder(b, t):
    """``Q t`` with ``Q`` the reflection sending the unit vector ``b`` to ``-s e_9``.

    ``s`` is the sign of ``b[..., 8]`` (``+1`` at zero), so ``w = b + s e_9``
    has norm at least 1. ``Q`` is symmetric and its own inverse; it maps the
    tangent space at ``b`` (vectors orthogonal to ``b``) onto the first eight
    coordinates.
    """
    s = np.where(b[..., 8] < 0, -1.0, 1.0)
    w = b.copy()
    w[..., 8] += s
    coef = 2.0 * np.einsum("...i,...i->...", w, t) / np.einsum("...i,...i->...", w, w)
    return t - coef[..., None] * w


class ProjectiveMatrices(Manifold):
    """Nonzero 3 x 3 matrices up to scale and sign, compared in a frame ``G = L P R``.

    Parameters
    ----------
    left, right : ndarray of shape (3, 3), optional
        Invertible frame matrices (identity by default). For fundamental
        matrices of matches ``(x1, y1, x2, y2)``: ``left = T2^-T``,
        ``right = T1^-1`` with the Hartley normalisations of the points
        (:meth:`~clap_unified.spaces.fundamental.FundamentalSpace.for_data`).

    Examples
    --------
    >>> g = ProjectiveMatrices()
    >>> F = np.array([[0.0, -1.0, 0.5], [1.0, 0.0, -2.0], [-0.5, 2.0, 0.0]])
    >>> float(g.distance(F, -3.0 * F))
    0.0
    >>> G = F.copy()
    >>> G[0, 2] += 0.01
    >>> round(float(g.distance(F, G)), 6) == round(float(g.distance(G, F)), 6) > 0
    True
    >>> np.allclose(g.exp(g.log(G, F), F), normalise_projective(G))
    True
    """

    is_metric = True
    #: ``||e(a) - e(b)|| = sin(d(a, b)) <= d(a, b)`` (not declared as
    #: ``embedding_bounds_distance``: see the module docstring).
    has_chordal_embedding = True
    small_pairwise = 4096
    name = "projective 3x3 matrices"
    dim = 8
    point_shape = (3, 3)

    def __init__(self, left=None, right=None):
        super().__init__()
        self.left, self._left_inv = self._frame(left, "left")
        self.right, self._right_inv = self._frame(right, "right")

    @staticmethod
    def _frame(M, name):
        if M is None:
            return np.eye(3), np.eye(3)
        M = check_array(M, name, shape=(3, 3)).copy()
        s = np.linalg.svd(M, compute_uv=False)
        if not s[-1] > 1e-12 * s[0]:
            raise ValueError(f"{name}: expected an invertible 3 x 3 frame matrix")
        inv = np.linalg.inv(M)
        M.setflags(write=False)
        inv.setflags(write=False)
        return M, inv

    def __repr__(self) -> str:
        framed = not (np.array_equal(self.left, np.eye(3))
                      and np.array_equal(self.right, np.eye(3)))
        return f"ProjectiveMatrices(framed={framed})"

    # ------------------------------------------------------------ the frame
    def unit_vectors(self, points) -> np.ndarray:
        """``vec(L P R) / ||L P R||``, shape ``(..., 9)`` (NaN rows for zero matrices)."""
        P = np.asarray(points, dtype=float)
        G = (self.left @ P @ self.right).reshape(*P.shape[:-2], 9)
        with np.errstate(invalid="ignore", divide="ignore"):
            return G / np.linalg.norm(G, axis=-1, keepdims=True)

    def _from_unit(self, u) -> np.ndarray:
        G = np.asarray(u).reshape(*np.shape(u)[:-1], 3, 3)
        return normalise_projective(self._left_inv @ G @ self._right_inv)

    def validate(self, points, name: str = "points") -> np.ndarray:
        """Finite arrays of shape ``(..., 3, 3)``, none of them zero."""
        P = check_array(points, name, shape=(Ellipsis, 3, 3))
        if np.any(np.all(P.reshape(*P.shape[:-2], 9) == 0, axis=-1)):
            raise ValueError(f"{name}: a zero matrix is no point of the projective space")
        return P

    def projection(self, points) -> np.ndarray:
        """The representative of each class (:func:`normalise_projective`)."""
        return normalise_projective(points)

    def reference_point(self) -> np.ndarray:
        """``[e_1]_x`` in the frame (a translation along x), back in the original frame."""
        cross = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])
        return self._from_unit(cross.reshape(9) / np.sqrt(2.0))

    # ------------------------------------------------------------ the chart
    def log(self, point, base_point) -> np.ndarray:
        u, b = np.broadcast_arrays(self.unit_vectors(point), self.unit_vectors(base_point))
        c = np.einsum("...i,...i->...", u, b)
        u = np.where((c < 0)[..., None], -u, u)
        chord = np.linalg.norm(u - b, axis=-1)
        angle = 2.0 * np.arcsin(np.minimum(chord / 2.0, 1.0))
        v = u - np.abs(c)[..., None] * b
        vn = np.linalg.norm(v, axis=-1)
        with np.errstate(invalid="ignore", divide="ignore"):
            t = np.where((vn > 0)[..., None], v * (angle / vn)[..., None], 0.0)
        return _householder(b, t)[..., :8]

    def exp(self, tangent, base_point) -> np.ndarray:
        tangent = np.asarray(tangent, dtype=float)
        b = self.unit_vectors(base_point)
        t9 = np.concatenate([tangent, np.zeros((*tangent.shape[:-1], 1))], axis=-1)
        b, t9 = np.broadcast_arrays(b, t9)
        t = _householder(b, t9)
        angle = np.linalg.norm(t, axis=-1)[..., None]
        u = np.cos(angle) * b + np.sinc(angle / np.pi) * t
        return self._from_unit(u)

    # ------------------------------------------------------------ distances
    def distance(self, point_a, point_b) -> np.ndarray:
        """The angle between the two matrices' lines in the frame, in ``[0, pi / 2]``."""
        u, v = self.unit_vectors(point_a), self.unit_vectors(point_b)
        chord = np.minimum(np.linalg.norm(u - v, axis=-1), np.linalg.norm(u + v, axis=-1))
        return 2.0 * np.arcsin(np.minimum(chord / 2.0, 1.0))

    def pairwise_distance(self, points_a, points_b=None) -> np.ndarray:
        """All ``(N, M)`` distances, ``arccos |u . v|``, from one product of the unit vectors.

        The cosine is rounded to about ``1e-16``, so distances below about
        ``1e-8`` come out as that resolution (:meth:`distance`, from the
        chord, resolves them); within one set the matrix is symmetric with a
        zero diagonal.
        """
        U = self.unit_vectors(check_array(points_a, "points_a", shape=(None, 3, 3)))
        V = U if points_b is None else self.unit_vectors(
            check_array(points_b, "points_b", shape=(None, 3, 3)))
        out = U @ V.T
        np.abs(out, out=out)
        np.minimum(out, 1.0, out=out)
        np.arccos(out, out=out)
        if points_b is None:
            out += out.T
            out *= 0.5
            np.fill_diagonal(out, 0.0)
        return out

    def chordal_embedding(self, points) -> np.ndarray:
        """``vec(u u^T) / sqrt(2)`` (upper triangle), shape ``(..., 45)``; sign-free."""
        u = self.unit_vectors(points)
        return u[..., _UPPER[0]] * u[..., _UPPER[1]] * _UPPER_WEIGHT
