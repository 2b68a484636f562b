"""Homographies compared by where they send a few anchor points, in pixels.

Two homographies that agree on the matched region of the source image are
the same answer for every purpose of an image-matching application, however
different their matrix entries. :class:`HomographyTransfer` measures exactly
that: with ``K`` anchor points ``a_k`` inside the matched region,

``d(H1, H2) = sqrt(mean_k ||H1(a_k) - H2(a_k)||^2)``

in destination pixels. The map ``H -> (H(a_1), ..., H(a_K)) / sqrt(K)`` is an
embedding into ``R^(2K)`` whose Euclidean distance *is* ``d``
(:meth:`~HomographyTransfer.chordal_embedding`,
``embedding_is_distance = True``), so density queries run on a k-d tree in
``O(H log H)`` instead of on an ``H x H`` matrix, and every distance has a
unit a user can read: "these two candidates disagree by 2.4 px".

A homography that sends an anchor to infinity or behind the camera (the
homogeneous coordinate not of the sign it has at the identity) has no
embedding: its row is NaN and its distance to everything is ``inf``. Near a
strong perspective that is the correct answer: such a candidate cannot be
the motion of the matched region.

The chart (``log``, ``exp``, means) is the one of
:class:`~clap_unified.geometry.homography.Homography` with ``H33 = 1``; only
the distance is the transfer distance. It is a pseudo-metric on matrices
(two homographies that agree on every anchor are at distance 0) and a metric
on what they do to the anchors.
"""

from __future__ import annotations

import numpy as np

from .. import _compiled
from .._validation import check_array, unwrap_checked
from .homography import Homography

__all__ = ["HomographyTransfer", "region_anchors"]

#: Stacks of more homographies than this are embedded by the compiled kernel
#: (``_transfer_embedding``) when ``clap_unified._compiled.AVAILABLE``.
_COMPILED_FROM = 64


def region_anchors(points, *, margin: float = 0.1) -> np.ndarray:
    """Five anchors inside the region of ``points``: four corners and the centre.

    The corners are those of the box between the ``margin`` and
    ``1 - margin`` quantiles of the coordinates (inside the matched region,
    where the mapping is constrained by the data, not the image corners where
    it is extrapolated).

    Parameters
    ----------
    points : ndarray of shape (N, 2)
    margin : float
        Quantile of each coordinate cut off on each side, in ``[0, 0.5)``.

    Returns
    -------
    ndarray of shape (5, 2)

    Examples
    --------
    >>> pts = np.c_[np.arange(11.0) * 10, np.arange(11.0)]
    >>> region_anchors(pts).tolist()
    [[10.0, 1.0], [90.0, 1.0], [90.0, 9.0], [10.0, 9.0], [50.0, 5.0]]
    """
    p = unwrap_checked(points, lambda q: check_array(q, "points", shape=(None, 2)))
    if not 0 <= margin < 0.5:
        raise ValueError(f"margin: expected a number in [0, 0.5), got {margin!r}")
    if len(p) == 0:
        raise ValueError("points: expected at least one point")
    lo, hi = np.quantile(p, margin, axis=0), np.quantile(p, 1 - margin, axis=0)
    return np.array([[lo[0], lo[1]], [hi[0], lo[1]], [hi[0], hi[1]], [lo[0], hi[1]],
                     [(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2]])


class HomographyTransfer(Homography):
    """Pixel homographies, distance: RMS transfer distance of ``anchors``.

    Parameters
    ----------
    anchors : ndarray of shape (K, 2)
        Source-image points (e.g. :func:`region_anchors` of the matches).

    Examples
    --------
    >>> g = HomographyTransfer(np.array([[0.0, 0.0], [100.0, 0.0]]))
    >>> shift = np.array([[1.0, 0.0, 3.0], [0.0, 1.0, 4.0], [0.0, 0.0, 1.0]])
    >>> float(g.distance(np.eye(3), shift))
    5.0
    >>> g.chordal_embedding(shift).round(3).tolist()
    [2.121, 2.828, 72.832, 2.828]
    """

    is_metric = True
    has_chordal_embedding = True
    #: The Euclidean distance of ``chordal_embedding`` equals ``distance``.
    embedding_is_distance = True
    small_pairwise = 4096
    name = "homographies (anchor transfer)"

    def __init__(self, anchors):
        super().__init__(normalization="h33")
        self.anchors = check_array(anchors, "anchors", shape=(None, 2)).copy()
        if len(self.anchors) == 0:
            raise ValueError("anchors: expected at least one anchor point")
        self.anchors.setflags(write=False)

    def __repr__(self) -> str:
        return f"HomographyTransfer(anchors={len(self.anchors)})"

    def chordal_embedding(self, points) -> np.ndarray:
        """``(H(a_1), ..., H(a_K)) / sqrt(K)`` per homography, shape ``(..., 2K)``.

        NaN rows for homographies that send an anchor to infinity or flip the
        sign of its homogeneous coordinate relative to ``H33`` (relative to the
        first anchor's when ``H33`` is zero).
        """
        H = np.asarray(points, dtype=float)
        if (_compiled.AVAILABLE and H.ndim == 3 and H.shape[1:] == (3, 3)
                and len(H) > _COMPILED_FROM):
            return _transfer_embedding(np.ascontiguousarray(H), self.anchors)
        ax, ay = self.anchors[:, 0], self.anchors[:, 1]
        # elementwise, not a stack of tiny matrix products: no BLAS kernel in the last bits
        p = H[..., :, 0, None] * ax + H[..., :, 1, None] * ay + H[..., :, 2, None]  # (..., 3, K)
        w = p[..., 2, :]
        # the sign of w at the anchors must be that of H33 (w at the image origin); when
        # H33 is zero (the origin maps to infinity) that of w at the first anchor: every
        # anchor on one side of the line sent to infinity
        scale = np.abs(H.reshape(*H.shape[:-2], 9)).max(axis=-1)[..., None]
        h33 = H[..., 2, 2]
        sign = np.where(np.abs(h33) > 1e-12 * scale[..., 0], np.sign(h33), np.sign(w[..., 0]))
        with np.errstate(all="ignore"):
            ok = np.all(w * sign[..., None] > 1e-12 * scale, axis=-1)
            xy = p[..., :2, :] / w[..., None, :]
        emb = np.swapaxes(xy, -1, -2).reshape(*H.shape[:-2], 2 * len(ax)) / np.sqrt(len(ax))
        ok &= np.all(np.isfinite(emb), axis=-1)
        return np.where(ok[..., None], emb, np.nan)

    def distance(self, point_a, point_b) -> np.ndarray:
        d = self.chordal_embedding(point_a) - self.chordal_embedding(point_b)
        out = np.sqrt(np.einsum("...i,...i->...", d, d))
        return np.where(np.isnan(out), np.inf, out)

    def pairwise_distance(self, points_a, points_b=None) -> np.ndarray:
        """All ``(N, M)`` distances from the embeddings (``inf`` for rows without one)."""
        from scipy.spatial.distance import cdist

        a = self.chordal_embedding(check_array(points_a, "points_a", shape=(None, 3, 3)))
        b = a if points_b is None else self.chordal_embedding(
            check_array(points_b, "points_b", shape=(None, 3, 3)))
        out = cdist(np.nan_to_num(a), np.nan_to_num(b))
        out[np.isnan(a[:, 0])] = np.inf
        out[:, np.isnan(b[:, 0])] = np.inf
        if points_b is None:
            np.fill_diagonal(out, np.where(np.isnan(a[:, 0]), np.inf, 0.0))
        return out


@_compiled.jit
def _transfer_embedding(H, anchors):
    """:meth:`HomographyTransfer.chordal_embedding` of a stack ``(S, 3, 3)``, compiled.

    The numpy path's arithmetic in the same order, one homography at a time
    (``tests/test_homography_compiled.py`` holds it to the numpy path).
    """
    n_s, n_a = H.shape[0], anchors.shape[0]
    root = np.sqrt(n_a)
    out = np.empty((n_s, 2 * n_a))
    for t in range(n_s):
        scale = 0.0
        bad = False
        for a in range(3):
            for b in range(3):
                e = abs(H[t, a, b])
                if e != e:
                    bad = True
                scale = max(scale, e)
        sign = np.sign(H[t, 2, 2])
        if not abs(H[t, 2, 2]) > 1e-12 * scale:  # H33 = 0: the side of the first anchor
            sign = np.sign(H[t, 2, 0] * anchors[0, 0] + H[t, 2, 1] * anchors[0, 1]
                           + H[t, 2, 2])
        for k in range(n_a):
            x, y = anchors[k, 0], anchors[k, 1]
            px = H[t, 0, 0] * x + H[t, 0, 1] * y + H[t, 0, 2]
            py = H[t, 1, 0] * x + H[t, 1, 1] * y + H[t, 1, 2]
            w = H[t, 2, 0] * x + H[t, 2, 1] * y + H[t, 2, 2]
            ex = px / w / root
            ey = py / w / root
            if bad or not (w * sign > 1e-12 * scale) or not (np.isfinite(ex) and np.isfinite(ey)):
                bad = True
                break
            out[t, 2 * k] = ex
            out[t, 2 * k + 1] = ey
        if bad:
            out[t, :] = np.nan
    return out
