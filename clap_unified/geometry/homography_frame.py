"""Homographies compared in a normalised image frame, with fast all-pairs distances.

Pixel homographies mix entries of very different sizes (translations in
hundreds of pixels, perspective terms around ``1e-4``), so their relative
matrices ``H1^-1 H2`` are badly balanced and wild outlier hypotheses push the
matrix logarithm onto its slow fallbacks. :class:`HomographyInFrame` takes
pixel homographies in and out but measures them in the frame of the data:
``Hn = T2 H T1^-1`` with the Hartley normalisations ``T1`` (source points) and
``T2`` (destination points), where every entry is of order one.

Distances (``metric``):

* ``"lie"``: ``||log(Hn1^-1 Hn2)||_F`` of the normalised frame. All pairs are
  first screened with the symmetrised first-order value of ``"lie_linear"``,
  ``(||Hn1^-1 Hn2 - I||_F + ||Hn2^-1 Hn1 - I||_F) / 2``, which costs a few
  small matrix products for all pairs at once; the exact logarithm is
  computed only for pairs below ``screen`` (the only ones that can sit in
  one cluster), the others keep that first-order value (both are large for
  them). ``screen=np.inf`` computes
  every logarithm.
* ``"lie_linear"``: the first-order Lie distance, the symmetrised
  ``(||Hn1^-1 Hn2 - I||_F + ||Hn2^-1 Hn1 - I||_F) / 2``. It equals
  ``||log(Hn1^-1 Hn2)||_F`` up to terms of second order in the distance
  (``log(I + X) = X - X^2 / 2 + ...``), so it ranks nearby candidates like the
  Lie distance, and for all pairs it is two 9-column matrix products: no
  logarithm at all. Far pairs (outlier candidates) come out far under both.
* ``"frobenius"``: ``||Hn1 - Hn2||_F`` of the normalised-frame matrices, one
  Gram matrix product for all pairs.

Neither is a true metric (see :func:`~clap_unified.geometry.homography.lie_distance`).
"""

from __future__ import annotations

import contextlib
import hashlib
import threading

import numpy as np

from .._validation import check_array, check_choice
from ._matrix import expm, logm
from .homography import Homography, _check_invertible, normalise_h33
from .homography_arithmetic import scale_homography

__all__ = ["HomographyInFrame", "reuse_pairwise_distances"]

#: Per thread, the all-pairs matrices kept inside :func:`reuse_pairwise_distances`.
_LOCAL = threading.local()


@contextlib.contextmanager
def reuse_pairwise_distances(size: int = 4):
    """Within the block (in this thread), all-pairs distances of one set are computed once.

    :meth:`~clap_unified.geometry.homography_frame.HomographyInFrame.pairwise_distance`
    of a single set (``points_b`` None) keeps its last ``size`` matrices, keyed
    by the frame, the metric and the homographies' bytes, and returns the kept
    matrix (read-only) when asked again: several estimates on the same
    candidates (e.g. CLAP with and without the polish, or trimming over all
    candidates and inside a cluster) then pay for the distances once. The
    answers are those computed without the block.

    Examples
    --------
    >>> T = np.diag([1 / 320, 1 / 240, 1.0])
    >>> g = HomographyInFrame(T, T)
    >>> H = np.stack([np.eye(3), np.diag([1.1, 1.0, 1.0])])
    >>> with reuse_pairwise_distances():
    ...     a, b = g.pairwise_distance(H), g.pairwise_distance(H.copy())
    >>> a is b, a.flags.writeable, bool(np.array_equal(a, g.pairwise_distance(H)))
    (True, False, True)
    """
    outer = getattr(_LOCAL, "reused", None)
    _LOCAL.reused = {"size": int(size), "kept": {}}
    try:
        yield
    finally:
        _LOCAL.reused = outer


def _first_order(Ainv, A, B, Binv) -> np.ndarray:
    """Symmetrised first-order distances ``(e_ij + e'_ij) / 2`` for all pairs.

    ``e_ij = ||Ainv_i B_j - I||_F`` and ``e'_ij = ||Binv_j A_i - I||_F``, each
    from one matrix product over all pairs:
    ``||Ainv_i B_j - I||^2 = <Ainv_i^T Ainv_i, B_j B_j^T> - 2 tr(Ainv_i B_j) + 3``
    (the constant rides in the product as a last column).
    """

    def squared(Pinv, Q):
        n, m = len(Pinv), len(Q)
        left = np.empty((n, 19))
        right = np.empty((m, 19))
        left[:, :9] = np.matmul(np.swapaxes(Pinv, 1, 2), Pinv).reshape(n, 9)
        left[:, 9:18] = Pinv.reshape(n, 9)
        left[:, 9:18] *= -2.0
        left[:, 18] = 1.0
        right[:, :9] = np.matmul(Q, np.swapaxes(Q, 1, 2)).reshape(m, 9)
        right[:, 9:18] = np.swapaxes(Q, 1, 2).reshape(m, 9)
        right[:, 18] = 3.0
        out = left @ right.T
        np.maximum(out, 0.0, out=out)
        return np.sqrt(out, out=out)

    out = squared(Ainv, B)
    out += out.T if Binv is None else squared(Binv, A).T
    out *= 0.5
    return out


def _frame_inverse(T, name: str) -> np.ndarray:
    """The inverse of a normalising transform ``T``; ``ValueError`` naming ``name`` if it has none.

    A frame is a change of coordinates, not a homography between images: a Hartley
    normalisation ``[[s, 0, -s cx], [0, s, -s cy], [0, 0, 1]]`` of points far from the origin
    (``|c| s`` of order one, ``s`` tiny) has a determinant far below Hadamard's bound, yet an
    exact inverse. So ``T`` is refused only when its inverse is not finite or does not undo it
    (``T T^-1 = I`` to ``1e-8``).
    """
    with np.errstate(all="ignore"):
        try:
            Tinv = np.linalg.inv(T)
        except np.linalg.LinAlgError:
            Tinv = np.full((3, 3), np.nan)
        ok = np.all(np.isfinite(Tinv)) and np.allclose(T @ Tinv, np.eye(3), rtol=0, atol=1e-8)
    if not ok:
        raise ValueError(f"{name}: a singular matrix (det = 0), not a change of frame")
    return Tinv


def _det_adjugate(M):
    """Determinants and adjugates of ``(..., 3, 3)`` matrices from row cross products."""
    r0, r1, r2 = M[..., 0, :], M[..., 1, :], M[..., 2, :]
    adj = np.stack([np.cross(r1, r2), np.cross(r2, r0), np.cross(r0, r1)], axis=-1)
    det = np.einsum("...i,...i->...", r0, adj[..., :, 0])
    return det, adj


class HomographyInFrame(Homography):
    """Pixel homographies measured in a normalised frame (``Hn = T2 H T1^-1``).

    Parameters
    ----------
    T1, T2 : ndarray of shape (3, 3)
        Invertible normalising transforms of the source and destination image
        (e.g. Hartley normalisations of the matched points, or a scaling by
        the image size).
    metric : {"lie", "lie_linear", "frobenius"}
        Distance in the normalised frame (see the module docstring).
    normalization : {"det", "h33"}
        Representative of the normalised-frame matrices: ``"det"`` (SL(3),
        defined for every invertible matrix, the default) or ``"h33"``.
        Points given to and returned by every method are pixel homographies
        with ``H33 = 1``.
    screen : float
        ``"lie"`` metric: exact logarithms only for pairs whose first-order
        distance ``(||Hn1^-1 Hn2 - I||_F + ||Hn2^-1 Hn1 - I||_F) / 2`` is below
        ``screen``.

    Examples
    --------
    >>> T = np.diag([1 / 320, 1 / 240, 1.0])
    >>> g = HomographyInFrame(T, T)
    >>> H = np.array([[1.0, 0.0, 3.2], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    >>> print(f"{float(g.distance(np.eye(3), H)):.4f}")
    0.0100
    >>> D = g.pairwise_distance(np.stack([np.eye(3), H, H]))
    >>> D.round(4).tolist()
    [[0.0, 0.01, 0.01], [0.01, 0.0, 0.0], [0.01, 0.0, 0.0]]
    """

    def __init__(self, T1, T2, *, metric: str = "lie", normalization: str = "det",
                 screen: float = 1.0):
        super().__init__(normalization=normalization)
        self.T1 = check_array(T1, "T1", shape=(3, 3))
        self.T2 = check_array(T2, "T2", shape=(3, 3))
        self.T1inv = _frame_inverse(self.T1, "T1")
        self.T2inv = _frame_inverse(self.T2, "T2")
        self.metric = check_choice(metric, "metric", {"lie", "lie_linear", "frobenius"})
        self.screen = float(screen)
        if not self.screen > 0:  # np.inf allowed: every logarithm exact
            raise ValueError(f"screen: expected a positive number or inf, got {screen!r}")

    def __repr__(self) -> str:
        return (f"HomographyInFrame(metric={self.metric!r}, "
                f"normalization={self.normalization!r}, screen={self.screen:g})")

    # ------------------------------------------------------------ frames
    def projection(self, points, name: str = "H") -> np.ndarray:
        """Pixel homographies scaled to ``H33 = 1`` (unit norm where ``H33`` is zero: see
        :func:`~clap_unified.geometry.homography_arithmetic.scale_homography`), refused if
        singular in the frame.

        Invertibility is judged on ``T2 H T1^-1``: in pixels, coordinates far from the
        origin (or in a small unit) give a valid homography a translation column so large
        that its determinant falls below any bound relative to its entries.
        """
        # H33 = 1, or unit norm where H33 is zero (the pixel origin maps to infinity: a
        # homography all the same, invertible in the frame)
        H = scale_homography(check_array(points, name, shape=(Ellipsis, 3, 3)))
        _check_invertible(self.T2 @ H @ self.T1inv, name)
        return H

    def to_frame(self, H, name: str = "H") -> np.ndarray:
        """Normalised-frame representatives ``T2 H T1^-1`` of pixel homographies."""
        return self._frame_and_inverse(H, name)[0]

    def _frame_and_inverse(self, H, name: str):
        """Normalised-frame representatives and their inverses (adjugate over determinant)."""
        Hn = self.T2 @ check_array(H, name, shape=(Ellipsis, 3, 3)) @ self.T1inv
        det, adj = _det_adjugate(Hn)
        _check_invertible(Hn, name, det=det)
        if self.normalization == "det":  # real cube root: determinant 1, sign fixed too
            c = np.cbrt(det)[..., None, None]
            return Hn / c, adj / (c * c)
        h = Hn[..., 2:, 2:]
        A = normalise_h33(Hn, name)
        return A, adj * (h / det[..., None, None])

    def from_frame(self, Hn, name: str = "H") -> np.ndarray:
        """Pixel homographies ``T2^-1 Hn T1`` scaled by ``scale_homography`` (``Hn`` invertible)."""
        Hn = check_array(Hn, name, shape=(Ellipsis, 3, 3))
        _check_invertible(Hn, name)
        return scale_homography(self.T2inv @ Hn @ self.T1)

    # ------------------------------------------------------------ chart
    def log(self, point, base_point) -> np.ndarray:
        """``vee(logm(Bn^-1 Hn))`` in the normalised frame."""
        A = self.to_frame(point, "point")
        B = self.to_frame(base_point, "base_point")
        return self.vee(logm(np.matmul(np.linalg.inv(B), A)))

    def exp(self, tangent, base_point) -> np.ndarray:
        """Pixel homography ``T2^-1 Bn expm(xi) T1``."""
        B = self.to_frame(base_point, "base_point")
        E = np.matmul(B, expm(self.hat(tangent)))
        return self.from_frame(E.real if np.iscomplexobj(E) else E)

    def reference_point(self) -> np.ndarray:
        """The pixel homography whose normalised-frame matrix is the identity."""
        return self.from_frame(np.eye(3))

    # ------------------------------------------------------------ distances
    def distance(self, point_a, point_b) -> np.ndarray:
        A, Ainv = self._frame_and_inverse(point_a, "point_a")
        B, Binv = self._frame_and_inverse(point_b, "point_b")
        if self.metric == "frobenius":
            D = A - B
            return np.sqrt(np.einsum("...ij,...ij->...", D, D))
        M = np.matmul(Ainv, B)
        first = M - np.eye(3)
        back = np.matmul(Binv, A) - np.eye(3)
        d = 0.5 * (np.sqrt(np.einsum("...ij,...ij->...", first, first))
                   + np.sqrt(np.einsum("...ij,...ij->...", back, back)))
        if self.metric == "lie_linear":
            return d
        near = d < self.screen
        if np.any(near):
            Mb = np.broadcast_to(M, (*d.shape, 3, 3))
            L = logm(Mb[near])
            L = np.abs(L) if np.iscomplexobj(L) else L
            d = np.array(d, dtype=float, copy=True)
            d[near] = np.sqrt(np.einsum("...ij,...ij->...", L, L))
        return d

    def pairwise_distance(self, points_a, points_b=None) -> np.ndarray:
        """All ``(N, M)`` distances; screened products instead of ``N M`` logarithms.

        Inside :func:`reuse_pairwise_distances` the matrix of a single set is kept.
        """
        reused = getattr(_LOCAL, "reused", None)
        if reused is None or points_b is not None:
            return self._pairwise_distance(points_a, points_b)
        pts = np.ascontiguousarray(points_a, dtype=float)
        key = hashlib.sha1(b"".join(
            [self.T1.tobytes(), self.T2.tobytes(), pts.tobytes(), str(pts.shape).encode(),
             f"{self.metric} {self.normalization} {self.screen!r}".encode()])).hexdigest()
        kept = reused["kept"]
        if key not in kept:
            out = self._pairwise_distance(pts)
            out.flags.writeable = False
            kept[key] = out
            while len(kept) > reused["size"]:
                kept.pop(next(iter(kept)))
        return kept[key]

    def _pairwise_distance(self, points_a, points_b=None) -> np.ndarray:
        A, Ainv = self._frame_and_inverse(np.asarray(points_a, dtype=float), "points_a")
        if points_b is None:
            B, Binv = A, None
        else:
            B, Binv = self._frame_and_inverse(np.asarray(points_b, dtype=float), "points_b")
        if A.ndim != 3 or B.ndim != 3:
            raise ValueError(f"points: expected shape (N, 3, 3), got {A.shape} and {B.shape}")
        if self.metric == "frobenius":
            a, b = A.reshape(len(A), 9), B.reshape(len(B), 9)
            sq = (a * a).sum(1)[:, None] + (b * b).sum(1)[None] - 2.0 * a @ b.T
            out = np.sqrt(np.maximum(sq, 0.0))
            if points_b is None:
                np.fill_diagonal(out, 0.0)
            return out
        out = _first_order(Ainv, A, B, Binv)
        if self.metric == "lie_linear":
            if points_b is None:
                np.fill_diagonal(out, 0.0)
            return out
        if points_b is None:
            np.fill_diagonal(out, 0.0)
            i, j = np.nonzero(np.triu(out < self.screen, 1))
        else:
            i, j = np.nonzero(out < self.screen)
        if len(i):
            L = logm(np.matmul(Ainv[i], B[j]))
            L = np.abs(L) if np.iscomplexobj(L) else L
            out[i, j] = np.sqrt(np.einsum("...ij,...ij->...", L, L))
            if points_b is None:
                out[j, i] = out[i, j]
        return out
