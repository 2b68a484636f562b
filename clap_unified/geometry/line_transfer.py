"""Lines compared by where they pass a few anchor points, in data units.

Two lines that run through the data region at the same place are the same
answer for a line-fitting application, whatever their angle and offset.
:class:`LineTransfer` measures that, in the spirit of
:class:`~clap_unified.geometry.homography_transfer.HomographyTransfer`: with
``K`` anchor points ``a_k`` inside the data region, each line is represented by
the feet of the perpendiculars from the anchors,

``f_k = a_k - (n . a_k - rho) n``  (``n = (cos theta, sin theta)``),

and ``d(L1, L2) = sqrt(mean_k ||f_k(L1) - f_k(L2)||^2)``. The feet do not
depend on which of the two normals of a line is stored, so there is no
Moebius-band seam to handle, and two anchors that are not equal already
determine the line from its feet: ``d`` is a metric. The map ``L -> (f_1, ...,
f_K) / sqrt(K)`` is an embedding into ``R^(2K)`` whose Euclidean distance *is*
``d`` (``embedding_is_distance = True``), so CLAP's density queries run on a
k-d tree in ``O(H log H)`` instead of on an ``H x H`` matrix.

The chart (``log``, ``exp``, means) is that of
:class:`~clap_unified.geometry.lines.Line2D`, with the length scale and
origin taken from the anchors; only the distance is the transfer distance.
"""

from __future__ import annotations

import numpy as np

from .._validation import check_array
from .lines import Line2D

__all__ = ["LineTransfer"]


class LineTransfer(Line2D):
    """Lines ``(theta, rho)``, distance: RMS distance between the feet of ``anchors``.

    Parameters
    ----------
    anchors : ndarray of shape (K, 2)
        Points of the data region, at least two distinct ones (e.g.
        :func:`~clap_unified.geometry.homography_transfer.region_anchors` of the
        data).

    Examples
    --------
    >>> g = LineTransfer(np.array([[-1.0, 0.0], [1.0, 0.0]]))
    >>> x_axis, shifted = np.array([np.pi / 2, 0.0]), np.array([np.pi / 2, 2.0])
    >>> float(g.distance(x_axis, shifted))
    2.0
    >>> flipped = np.array([3 * np.pi / 2, -2.0])   # the same line as ``shifted``
    >>> float(g.distance(shifted, flipped))
    0.0
    """

    is_metric = True
    has_chordal_embedding = True
    #: The Euclidean distance of :meth:`chordal_embedding` equals ``distance``.
    embedding_is_distance = True
    small_pairwise = 4096
    name = "lines (anchor transfer)"

    def __init__(self, anchors):
        a = check_array(anchors, "anchors", shape=(None, 2)).copy()
        if len(np.unique(a, axis=0)) < 2:
            raise ValueError("anchors: expected at least two distinct anchor points")
        centre = a.mean(axis=0)
        radius = float(np.sqrt(np.mean(np.sum((a - centre) ** 2, axis=1))))
        # the chart's scale only; tiny data (1e-300) underflow to 0
        super().__init__(length_scale=max(radius, np.finfo(float).tiny), origin=centre)
        self.anchors = a
        self.anchors.setflags(write=False)

    def __repr__(self) -> str:
        return f"LineTransfer(anchors={len(self.anchors)})"

    def chordal_embedding(self, points) -> np.ndarray:
        """``(f_1, ..., f_K) / sqrt(K)`` per line, shape ``(..., 2K)``.

        ``f_k`` is the foot of the perpendicular from anchor ``k`` to the line.
        """
        lines = np.asarray(points, dtype=float)
        theta, rho = lines[..., 0], lines[..., 1]
        n = np.stack([np.cos(theta), np.sin(theta)], axis=-1)  # (..., 2)
        a = self.anchors
        off = n @ a.T - rho[..., None]  # (..., K): signed distances of the anchors
        feet = a - off[..., :, None] * n[..., None, :]  # (..., K, 2)
        return feet.reshape(*lines.shape[:-1], 2 * len(a)) / np.sqrt(len(a))

    def distance(self, point_a, point_b) -> np.ndarray:
        d = self.chordal_embedding(point_a) - self.chordal_embedding(point_b)
        return np.sqrt(np.einsum("...i,...i->...", d, d))

    def pairwise_distance(self, points_a, points_b=None) -> np.ndarray:
        """All ``(N, M)`` distances from the embeddings."""
        from scipy.spatial.distance import cdist

        a = self.chordal_embedding(check_array(points_a, "points_a", shape=(None, 2)))
        if points_b is None:
            out = cdist(a, a)
            np.fill_diagonal(out, 0.0)
            return out
        return cdist(a, self.chordal_embedding(check_array(points_b, "points_b",
                                                           shape=(None, 2))))
