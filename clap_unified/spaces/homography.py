"""Hypothesis space of planar homographies: four correspondences make one.

Convention: ``x2 ~ H x1`` for correspondences ``(x1, y1, x2, y2)`` (the VPG
format). Minimal solver: normalised DLT, batched over all samples with one
``numpy.linalg.svd`` call. Models are normalised so that ``H[2, 2] = 1``.
"""

from __future__ import annotations

import numpy as np

from .._validation import check_choice, check_points
from .base import HypothesisSpace

__all__ = ["HomographySpace", "dlt", "four_point_homography", "normalise_points"]

#: Minimal-sample homographies with |det H| / prod_i |row_i| at or below this are rejected.
SINGULAR_RATIO = 1e-10


def normalise_points(points, weights=None):
    """Hartley normalisation of point sets, batched.

    Parameters
    ----------
    points : ndarray of shape (..., N, 2)
    weights : ndarray of shape (..., N), optional

    Returns
    -------
    normalised : ndarray of shape (..., N, 2)
        Centroid at the origin, mean distance sqrt(2).
    T : ndarray of shape (..., 3, 3)
        The similarity with ``normalised = T @ points`` (homogeneous).
    """
    p = np.asarray(points, dtype=float)
    w = np.ones(p.shape[:-1]) if weights is None else np.asarray(weights, dtype=float)
    wsum = w.sum(axis=-1, keepdims=True)
    centre = (w[..., None] * p).sum(axis=-2) / wsum
    d = np.linalg.norm(p - centre[..., None, :], axis=-1)
    mean_d = (w * d).sum(axis=-1) / wsum[..., 0]
    s = np.sqrt(2.0) / np.where(mean_d > 0, mean_d, 1.0)
    T = np.zeros((*p.shape[:-2], 3, 3))
    T[..., 0, 0] = T[..., 1, 1] = s
    T[..., 0, 2] = -s * centre[..., 0]
    T[..., 1, 2] = -s * centre[..., 1]
    T[..., 2, 2] = 1.0
    return (p - centre[..., None, :]) * s[..., None, None], T


def dlt(src, dst, weights=None) -> np.ndarray:
    """Normalised direct linear transform, batched: ``dst ~ H src``.

    Parameters
    ----------
    src, dst : ndarray of shape (..., N, 2), N >= 4
    weights : ndarray of shape (..., N), optional

    Returns
    -------
    ndarray of shape (..., 3, 3)
        Homographies scaled to unit Frobenius norm (not yet ``H33 = 1``).

    Examples
    --------
    >>> H = np.array([[1.0, 0.2, 3.0], [0.1, 0.9, -2.0], [1e-3, 2e-3, 1.0]])
    >>> src = np.array([[0.0, 0.0], [100.0, 0.0], [100.0, 80.0], [0.0, 80.0], [50.0, 30.0]])
    >>> h = np.c_[src, np.ones(5)] @ H.T
    >>> est = dlt(src, h[:, :2] / h[:, 2:])
    >>> np.allclose(est / est[2, 2], H)
    True
    """
    s, Ts = normalise_points(src, weights)
    d, Td = normalise_points(dst, weights)
    x, y = s[..., 0], s[..., 1]
    u, v = d[..., 0], d[..., 1]
    one, zero = np.ones_like(x), np.zeros_like(x)
    r1 = np.stack([-x, -y, -one, zero, zero, zero, u * x, u * y, u], axis=-1)
    r2 = np.stack([zero, zero, zero, -x, -y, -one, v * x, v * y, v], axis=-1)
    A = np.concatenate([r1, r2], axis=-2)  # (..., 2N, 9)
    if weights is not None:
        sw = np.sqrt(np.asarray(weights, dtype=float))
        A = A * np.concatenate([sw, sw], axis=-1)[..., None]
    # the null vector is the last right singular vector; the thin SVD has it
    # whenever there are at least 9 rows (and never builds the 2N x 2N U)
    _, _, vt = np.linalg.svd(A, full_matrices=A.shape[-2] < 9)
    Hn = vt[..., -1, :].reshape(*A.shape[:-2], 3, 3)
    H = np.linalg.inv(Td) @ Hn @ Ts
    return H / np.linalg.norm(H, axis=(-2, -1), keepdims=True)


def _basis_to_points(p):
    """``(S, 3, 3)`` matrices mapping the projective basis onto the 4 points ``(S, 4, 2)``."""
    ph = np.concatenate([p, np.ones((*p.shape[:-1], 1))], axis=-1)  # (S, 4, 3)
    M = np.swapaxes(ph[:, :3], 1, 2)  # columns p1, p2, p3
    lam = np.linalg.solve(M, ph[:, 3, :, None])[..., 0]
    return M * lam[:, None, :]


def four_point_homography(src, dst) -> np.ndarray:
    """Exact homographies through 4 correspondences, batched, in closed form.

    ``H = B A^-1`` where ``A`` (``B``) maps the projective basis onto the four
    source (destination) points: two batched 3 x 3 solves per sample instead
    of an SVD of the 8 x 9 DLT matrix. No three points of a sample may be
    collinear (check first).

    Parameters
    ----------
    src, dst : ndarray of shape (S, 4, 2)

    Returns
    -------
    ndarray of shape (S, 3, 3)
        Scaled to unit Frobenius norm.

    Examples
    --------
    >>> H = np.array([[1.0, 0.2, 3.0], [0.1, 0.9, -2.0], [1e-3, 2e-3, 1.0]])
    >>> src = np.array([[[0.0, 0.0], [100.0, 0.0], [100.0, 80.0], [0.0, 80.0]]])
    >>> h = np.c_[src[0], np.ones(4)] @ H.T
    >>> est = four_point_homography(src, (h[:, :2] / h[:, 2:])[None])[0]
    >>> np.allclose(est / est[2, 2], H)
    True
    """
    A = _basis_to_points(np.asarray(src, dtype=float))
    B = _basis_to_points(np.asarray(dst, dtype=float))
    H = B @ np.linalg.inv(A)
    return H / np.linalg.norm(H, axis=(-2, -1), keepdims=True)


def _has_collinear_triple(p, tol: float) -> np.ndarray:
    """True for samples ``(S, 4, 2)`` in which some three points are (nearly) collinear."""
    out = np.zeros(p.shape[0], bool)
    scale = max(float(np.max(np.abs(p), initial=0.0)), 1.0) ** 2
    for i, j, k in ((0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3)):
        a, b, c = p[:, i], p[:, j], p[:, k]
        ab, ac = b - a, c - a
        cross = ab[:, 0] * ac[:, 1] - ab[:, 1] * ac[:, 0]
        out |= np.abs(cross) <= tol * scale
    return out


class HomographySpace(HypothesisSpace):
    """Planar homographies from point correspondences ``(x1, y1, x2, y2)``.

    Parameters
    ----------
    residual : {"transfer", "symmetric"}
        ``transfer``: ``||x2 - H x1||``; ``symmetric``: root mean square of
        the forward and backward transfer errors (pixels).
    normalization : {"h33", "det"}
        Normalisation of the homography group used for distances.

    Notes
    -----
    The plain space compares hypotheses as pixel homographies (the paper's
    metric as written), which is slow and badly conditioned for clustering
    hundreds of candidates. For CLAP use :meth:`for_data` (the Hartley frame
    of the matches) or :meth:`for_images` (the image-size frame).
    """

    min_samples = 4
    model_shape = (3, 3)
    name = "homography"

    def __init__(self, residual: str = "transfer", normalization: str = "h33"):
        self.residual = check_choice(residual, "residual", {"transfer", "symmetric"})
        self.normalization = check_choice(normalization, "normalization", {"h33", "det"})
        self._manifold = None

    @classmethod
    def for_data(cls, matches, *, residual: str = "transfer", metric: str = "lie_linear",
                 normalization: str = "det", screen: float = 1.0) -> HomographySpace:
        """A space that compares hypotheses in the normalised frame of ``matches``.

        The manifold is a :class:`~clap_unified.geometry.homography_frame.HomographyInFrame`
        with the Hartley normalisations ``T1`` of the source and ``T2`` of the
        destination points: hypotheses are compared as ``T2 H T1^-1`` (entries
        of order one, fast all-pairs distances), while models, residuals and
        refits stay in pixels.

        Examples
        --------
        >>> rng = np.random.default_rng(0)
        >>> src = rng.uniform(0, 640, (50, 2))
        >>> space = HomographySpace.for_data(np.c_[src, src + 5.0])
        >>> space.manifold
        HomographyInFrame(metric='lie_linear', normalization='det', screen=1)
        """
        from ..geometry.homography_frame import HomographyInFrame

        data = check_points(matches, "matches", dim=4, min_count=cls.min_samples)
        _, T1 = normalise_points(data[:, :2])
        _, T2 = normalise_points(data[:, 2:])
        space = cls(residual=residual, normalization="h33")
        space._manifold = HomographyInFrame(T1, T2, metric=metric, normalization=normalization,
                                            screen=screen)
        return space

    @classmethod
    def for_images(cls, size1, size2, *, residual: str = "transfer", metric: str = "lie_linear",
                   normalization: str = "det", screen: float = 1.0) -> HomographySpace:
        """Like :meth:`for_data`, with the frames fixed by the image sizes instead.

        ``T = [[2/w, 0, -1], [0, 2/h, -1], [0, 0, 1]]`` maps each image onto
        ``[-1, 1]^2``: the frame does not depend on which matches were found.

        Examples
        --------
        >>> space = HomographySpace.for_images((640, 480), (640, 480))
        >>> space.manifold.T1.tolist()[0]
        [0.003125, 0.0, -1.0]
        """
        from ..geometry.homography_frame import HomographyInFrame

        def frame(size, name):
            w, h = (float(v) for v in size)
            if not (np.isfinite(w) and np.isfinite(h) and w > 0 and h > 0):
                raise ValueError(f"{name}: expected a positive (width, height), got {size!r}")
            return np.array([[2.0 / w, 0.0, -1.0], [0.0, 2.0 / h, -1.0], [0.0, 0.0, 1.0]])

        space = cls(residual=residual, normalization="h33")
        space._manifold = HomographyInFrame(frame(size1, "size1"), frame(size2, "size2"),
                                            metric=metric, normalization=normalization,
                                            screen=screen)
        return space

    def __repr__(self) -> str:
        return f"HomographySpace(residual={self.residual!r}, normalization={self.normalization!r})"

    @property
    def manifold(self):
        if self._manifold is None:
            from ..geometry.homography import Homography

            self._manifold = Homography(normalization=self.normalization)
        return self._manifold

    def check_data(self, data) -> np.ndarray:
        return check_points(data, "matches", dim=4, min_count=self.min_samples)

    def solve_minimal(self, data, samples):
        # closed-form 4-point solutions in the data's Hartley frame, mapped back
        sn, T1 = normalise_points(data[:, :2])
        dn, T2 = normalise_points(data[:, 2:])
        src, dst = sn[samples], dn[samples]
        ok = ~(_has_collinear_triple(src, 1e-9) | _has_collinear_triple(dst, 1e-9))
        if np.any(ok):
            H = np.linalg.inv(T2) @ four_point_homography(src[ok], dst[ok]) @ T1
        else:
            H = np.empty((0, 3, 3))
        h33 = H[:, 2, 2]
        good = np.abs(h33) > 1e-12 * np.abs(H).max(axis=(1, 2))
        H = H[good] / h33[good, None, None]
        owner = np.flatnonzero(ok)[good]
        # near-singular models (a sample close to degenerate) are no homography:
        # |det H| against Hadamard's bound, a scale-free ratio in [0, 1]
        with np.errstate(all="ignore"):
            ratio = np.abs(np.linalg.det(H)) / np.prod(np.linalg.norm(H, axis=-1), axis=-1)
        keep = np.all(np.isfinite(H), axis=(1, 2)) & (ratio > SINGULAR_RATIO)
        return H[keep], owner[keep]

    def refit(self, data, weights=None, initial=None):
        data = np.asarray(data, dtype=float)
        w = None if weights is None else np.asarray(weights, dtype=float)
        if w is not None:
            keep = w > 0
            data, w = data[keep], w[keep]
        if len(data) < 4:
            return None
        H = dlt(data[:, :2], data[:, 2:], w)
        if abs(H[2, 2]) <= 1e-12 or not np.all(np.isfinite(H)):
            return None
        H = H / H[2, 2]
        if np.linalg.matrix_rank(H) < 3:
            return None
        return H

    @staticmethod
    def _transfer(H, src, dst):
        p = np.einsum("hij,nj->hni", H, np.c_[src, np.ones(len(src))])
        with np.errstate(divide="ignore", invalid="ignore"):
            proj = p[..., :2] / p[..., 2:]
        err = np.linalg.norm(proj - dst[None], axis=-1)
        return np.where(np.isfinite(err), err, np.inf)

    def residuals(self, models, data) -> np.ndarray:
        H = np.asarray(models, dtype=float).reshape(-1, 3, 3)
        data = np.asarray(data, dtype=float)
        fwd = self._transfer(H, data[:, :2], data[:, 2:])
        if self.residual == "transfer":
            return fwd
        with np.errstate(all="ignore"):
            Hinv = np.linalg.inv(H)
        bwd = self._transfer(Hinv, data[:, 2:], data[:, :2])
        return np.sqrt(0.5 * (fwd**2 + bwd**2))

    def model_to_dict(self, model) -> dict:
        H = np.asarray(model, dtype=float)
        return {"H": (H / H[2, 2]).tolist()}

    def default_residual_threshold(self, data) -> float:
        return 3.0  # pixels, OpenCV's default ransacReprojThreshold
