"""Hypothesis space of planar homographies, and the one home of their arithmetic.

Convention: ``x2 ~ H x1`` for correspondences ``(x1, y1, x2, y2)`` (the VPG
format). Models are normalised so that ``H[2, 2] = 1``.

The arithmetic every homography module uses lives here, once:

* :func:`normalise_points`: Hartley normalisation;
* :func:`dlt`: the (weighted) normalised direct linear transform, from the
  9 x 9 normal equations;
* :func:`four_point_homography`: the closed-form 4-point minimal solver in
  the Hartley frame of the data, batched with cofactors (no per-sample solve
  or inverse);
* :func:`transfer`, :func:`transfer_error`, :func:`symmetric_transfer_error`:
  points mapped by ``H``, the forward transfer error of many homographies,
  and the symmetric transfer error (the paper's SRE).

:class:`HomographySpace` draws its hypotheses uniformly or progressively
(PROSAC-like pools ordered by match quality) and refines a model by a DLT
refit on its inliers, followed, with ``polish=True``, by a reweighted DLT
(:func:`~clap_unified.spaces.homography_polish.polish_homography`).
"""

from __future__ import annotations

import numpy as np

from .. import _compiled
from .._validation import as_generator, check_array, check_choice, check_int, check_points
from ..refine import refit_on_inliers
from . import homography_compiled
from .base import HypothesisSet, HypothesisSpace

__all__ = ["HomographySpace", "dlt", "four_point_homography", "normalise_points",
           "symmetric_transfer_error", "transfer", "transfer_error"]

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
    q, centre, s = _centre_scale(np.asarray(points, dtype=float), weights)
    q *= s[..., None, None]
    return q, _similarity(centre, s)


def _similarity(centre, s) -> np.ndarray:
    """``[[s, 0, -s cx], [0, s, -s cy], [0, 0, 1]]``, batched over ``s`` ``(...)``."""
    T = np.zeros((*np.shape(s), 3, 3))
    T[..., 0, 0] = T[..., 1, 1] = s
    T[..., 0, 2] = -s * centre[..., 0]
    T[..., 1, 2] = -s * centre[..., 1]
    T[..., 2, 2] = 1.0
    return T


def _centre_scale(p, weights=None):
    """Centred points, centroid and Hartley scale of ``p`` ``(..., N, 2)``.

    Sums are products with the weights (BLAS) rather than reductions over
    the short last axes, which cost more in numpy than the arithmetic.
    """
    if weights is None:
        n = p.shape[-2]
        w, wsum = np.full(n, 1.0 / max(n, 1)), 1.0
    else:
        w = np.asarray(weights, dtype=float)
        wsum = w.sum(axis=-1)
    centre = (w[..., None, :] @ p)[..., 0, :]
    if weights is not None:
        centre /= wsum[..., None]
    q = p - centre[..., None, :]
    mean_d = (w[..., None, :] @ np.sqrt(q[..., 0] * q[..., 0] + q[..., 1] * q[..., 1])[..., None]
              )[..., 0, 0] / wsum
    s = np.sqrt(2.0) / np.where(mean_d > 0, mean_d, 1.0)
    return q, centre, s


def dlt(src, dst, weights=None) -> np.ndarray:
    """Normalised direct linear transform, batched: ``dst ~ H src``.

    After Hartley normalisation of both point sets, ``H`` is the eigenvector
    of the smallest eigenvalue of the 9 x 9 matrix ``A^T A`` (built from
    weighted moments of the points, never forming the ``2N x 9`` ``A``), as
    in OpenCV; fewer than 8 correspondences take the SVD of ``A``.

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
    return _dlt(np.stack([np.asarray(src, dtype=float), np.asarray(dst, dtype=float)]), weights)


def _dlt(points, weights=None) -> np.ndarray:
    """:func:`dlt` of ``points = [src, dst]`` ``(2, ..., N, 2)``, both normalised in one pass."""
    q, centre, s = _centre_scale(points, weights)
    q *= s[..., None, None]
    x, y, u, v = q[0, ..., 0], q[0, ..., 1], q[1, ..., 0], q[1, ..., 1]
    if x.shape[-1] < _NORMAL_EQUATIONS_MIN:
        one, zero = np.ones_like(x), np.zeros_like(x)
        r1 = np.stack([-x, -y, -one, zero, zero, zero, u * x, u * y, u], axis=-1)
        r2 = np.stack([zero, zero, zero, -x, -y, -one, v * x, v * y, v], axis=-1)
        A = np.concatenate([r1, r2], axis=-2)  # (..., 2N, 9)
        if weights is not None:
            sw = np.sqrt(np.asarray(weights, dtype=float))
            A = A * np.concatenate([sw, sw], axis=-1)[..., None]
        # the null vector is the last right singular vector (of the full V when
        # there are fewer than 9 rows)
        _, _, vt = np.linalg.svd(A, full_matrices=A.shape[-2] < 9)
        Hn = vt[..., -1, :]
    else:
        # A^T A from four weighted moments of the monomials of p p^T, p = (x, y, 1):
        # one (4, N) @ (N, 6) product instead of the (2N, 9) matrix and its SVD
        w = np.ones_like(x) if weights is None else np.asarray(weights, dtype=float)
        mono = np.stack([x * x, x * y, x, y * y, y, np.ones_like(x)], axis=-1)
        wm = np.stack([w, w * u, w * v, w * (u * u + v * v)], axis=-2)
        m = (wm @ mono).reshape(*x.shape[:-1], 24)
        _, V = np.linalg.eigh(m[..., _NORMAL_INDEX] * _NORMAL_SIGN)
        Hn = V[..., :, 0]  # eigenvector of the smallest eigenvalue
    # back to pixels: T_dst^-1 Hn T_src
    Hn = Hn.reshape(*x.shape[:-1], 3, 3)
    if Hn.ndim == 2:  # one problem: the frames from floats cost less than array arithmetic
        (csx, csy), (cdx, cdy) = centre.tolist()
        ss, sd = s.tolist()
        G = (np.array([[1.0, 0.0, sd * cdx], [0.0, 1.0, sd * cdy], [0.0, 0.0, sd]]) @ Hn
             @ np.array([[1.0, 0.0, -csx], [0.0, 1.0, -csy], [0.0, 0.0, 1.0 / ss]]))
    else:
        G = _similarity_inverse(_similarity(centre[1], s[1])) @ Hn @ _similarity(centre[0], s[0])
    return G / np.sqrt(np.sum(G * G, axis=(-2, -1), keepdims=True))


def _normal_tables():
    """Gather table and signs building the 9 x 9 ``A^T A`` of the DLT from its moments.

    With ``r1 = (-p, 0, u p)`` and ``r2 = (0, -p, v p)`` the rows of a match,
    ``A^T A`` has 3 x 3 blocks ``[[P, 0, -Pu], [0, P, -Pv], [-Pu, -Pv, Puuvv]]``
    (``P = sum w p p^T``, ``Pu = sum w u p p^T``, ...), each symmetric and
    stored as the 6 moments of ``xx, xy, x, yy, y, 1``.
    """
    sym = np.array([[0, 1, 2], [1, 3, 4], [2, 4, 5]])
    moment = [[0, None, 1], [None, 0, 2], [1, 2, 3]]
    sign = [[1.0, 0.0, -1.0], [0.0, 1.0, -1.0], [-1.0, -1.0, 1.0]]
    index, signs = np.zeros((9, 9), dtype=np.intp), np.zeros((9, 9))
    for bi in range(3):
        for bj in range(3):
            if moment[bi][bj] is not None:
                index[3 * bi:3 * bi + 3, 3 * bj:3 * bj + 3] = 6 * moment[bi][bj] + sym
                signs[3 * bi:3 * bi + 3, 3 * bj:3 * bj + 3] = sign[bi][bj]
    return index, signs


_NORMAL_INDEX, _NORMAL_SIGN = _normal_tables()

#: From this many correspondences on, :func:`dlt` solves the 9 x 9 normal
#: equations (``eigh``) instead of taking the SVD of the ``2N x 9`` matrix.
_NORMAL_EQUATIONS_MIN = 8


def _similarity_inverse(T) -> np.ndarray:
    """Inverse of the similarities ``(..., 3, 3)`` made by :func:`normalise_points`."""
    s = T[..., 0, 0]
    out = np.zeros_like(T)
    out[..., 0, 0] = out[..., 1, 1] = 1.0 / s
    out[..., 0, 2] = -T[..., 0, 2] / s
    out[..., 1, 2] = -T[..., 1, 2] / s
    out[..., 2, 2] = 1.0
    return out


def _four_point(x, y, u, v, frames=None):
    """Closed-form 4-point homographies, unnormalised, component-major.

    ``x, y`` (source) and ``u, v`` (destination) have shape ``(4, S)``. With
    ``M = [p1 p2 p3]`` (homogeneous columns), the rows of ``adj(M)`` are the
    cross products ``r1 = p2 x p3``, ``r2 = p3 x p1``, ``r3 = p1 x p2`` and
    ``lam = adj(M) p4`` holds the determinants of the other three triples:
    ``A = M diag(lam)`` maps the projective basis onto the points (up to
    scale), ``A^-1 ~ diag(1 / lam) adj(M)``, and ``H = B A^-1`` is
    ``sum_i mu_i lam_j lam_k q_i r_i^T`` (``mu`` the destination's ``lam``,
    ``{i, j, k} = {1, 2, 3}``): no solve, no inverse.

    ``frames = (centre1, scale1, centre2, scale2)`` says the points are
    ``(p - centre) * scale`` of the original ones (Hartley normalisation):
    ``H`` is then returned in the original frame, ``T2^-1 H T1``, by mapping
    the ``q_i`` and ``r_i`` (one step each, no 3 x 3 products).

    Returns
    -------
    H : ndarray of shape (3, 3, S)
        ``H[a, b]`` over the samples, arbitrary scale and sign.
    dets_src, dets_dst : ndarray of shape (4, S)
        The determinants of the four point triples of each sample (twice the
        signed triangle areas; up to sign): near zero for collinear triples.
    """
    def adjugate(x, y):
        xa, xb, ya, yb = x[[1, 2, 0]], x[[2, 0, 1]], y[[1, 2, 0]], y[[2, 0, 1]]
        r = np.stack([ya - yb, xb - xa, xa * yb - xb * ya], axis=1)  # (3 rows, 3, S)
        lam = r[:, 0] * x[3] + r[:, 1] * y[3] + r[:, 2]
        d123 = r[0, 0] * x[0] + r[0, 1] * y[0] + r[0, 2]
        return r, lam, np.concatenate([d123[None], lam])

    r, lam, dets_src = adjugate(x, y)
    _, mu, dets_dst = adjugate(u, v)
    c = mu * (lam[[1, 2, 0]] * lam[[2, 0, 1]])
    u, v = u[:3], v[:3]
    if frames is not None:
        (c1x, c1y), s1, (c2x, c2y), s2 = frames
        r[:, 2] = r[:, 2] / s1 - c1x * r[:, 0] - c1y * r[:, 1]  # r_i^T T1 / s1
        u, v = u / s2 + c2x, v / s2 + c2y  # T2^-1 q_i
    cr = c[:, None] * r  # (3 rows i, 3, S)
    H = np.stack([(u[:, None] * cr).sum(axis=0), (v[:, None] * cr).sum(axis=0),
                  cr.sum(axis=0)])
    return H, dets_src, dets_dst


class _NewSamples:
    """The samples of each batch never taken before, in order, up to a count.

    The numpy path keeps a Python set of the rows; the compiled one
    (:func:`~clap_unified.spaces.homography_compiled.take_new_samples`) a
    hash table, with the same answer (tested): with the compiled solver,
    10000 progressive candidates of an EVD pair take about a third of the
    numpy path's time.
    """

    def __init__(self, n: int, most: int):
        self.n = n
        self.compiled = _compiled.AVAILABLE
        if self.compiled:
            size = 1 << int(2 * most + 2).bit_length()
            self.table = np.zeros((size, 2), dtype=np.int64)
            self.used = np.zeros(size, dtype=np.bool_)
        else:
            self.seen = set()

    def __call__(self, rows, want: int) -> np.ndarray:
        """``rows`` ``(B, 4)`` (sorted indices): the first ``want`` new ones."""
        rows = np.ascontiguousarray(rows, dtype=np.int64)
        if self.compiled:
            take = homography_compiled.take_new_samples(rows, self.n, self.table, self.used,
                                                        want)
            return rows[take]
        out = []
        for row in rows:
            if len(out) >= want:
                break
            key = row.tobytes()
            if key not in self.seen:
                self.seen.add(key)
                out.append(row)
        return np.array(out, dtype=np.int64).reshape(-1, 4)


def four_point_homography(src, dst) -> np.ndarray:
    """Exact homographies through 4 correspondences, batched, in closed form.

    ``H = B A^-1`` where ``A`` (``B``) maps the projective basis onto the four
    source (destination) points, written with cofactors (cross products of
    the points) instead of solves and inverses of 3 x 3 stacks. No three
    points of a sample may be collinear (check first).

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
    src = np.asarray(src, dtype=float)
    dst = np.asarray(dst, dtype=float)
    H = _four_point(src[..., 0].T, src[..., 1].T, dst[..., 0].T, dst[..., 1].T)[0]
    H = np.moveaxis(H, -1, 0)
    return H / np.linalg.norm(H, axis=(-2, -1), keepdims=True)


def transfer(H, points) -> np.ndarray:
    """Points ``(N, 2)`` mapped by one homography ``H`` (``inf`` where they go to infinity).

    Examples
    --------
    >>> transfer(np.diag([2.0, 2.0, 1.0]), np.array([[1.0, 2.0]])).tolist()
    [[2.0, 4.0]]
    """
    p = np.c_[np.asarray(points, dtype=float), np.ones(len(points))] @ np.asarray(H).T
    with np.errstate(divide="ignore", invalid="ignore"):
        q = p[:, :2] / p[:, 2:]
    return np.where(np.isfinite(q), q, np.inf)


def transfer_error(H, src, dst) -> np.ndarray:
    """Forward transfer errors ``||dst - H src||`` of many homographies, shape ``(H, N)``.

    ``H`` is a stack ``(H, 3, 3)``; ``src, dst`` are ``(N, 2)``. A point sent
    to infinity has error ``inf``.
    """
    p = H[:, :, :2] @ src.T + H[:, :, 2:]  # (H, 3, N)
    with np.errstate(all="ignore"):
        d = p[:, :2] / p[:, 2:] - dst.T
        d *= d
        err = np.sqrt(d[:, 0] + d[:, 1])
    return np.where(np.isfinite(err), err, np.inf)


def symmetric_transfer_error(H, matches) -> np.ndarray:
    """Symmetric transfer error ``sqrt((|x2 - H x1|^2 + |x1 - H^-1 x2|^2) / 2)`` per match.

    ``H`` is one ``(3, 3)`` homography and ``matches`` a checked ``(N, 4)``
    array (no validation here: the hot path of the polish and the metrics).
    The backward map is the adjugate of ``H`` (``det(H) H^-1``: the same
    transfer, no inverse call), both directions in one product; a singular
    ``H`` gives ``inf`` everywhere.

    Examples
    --------
    >>> scale = np.diag([2.0, 2.0, 1.0])                   # x2 = 2 x1
    >>> symmetric_transfer_error(scale, np.array([[1.0, 1.0, 2.0, 2.0], [1, 0, 4, 0]])).tolist()
    [0.0, 1.5811388300841898]
    """
    (a, b, c), (d, e, f), (g, h, i) = H.tolist()
    adj = [[e * i - f * h, c * h - b * i, b * f - c * e],
           [f * g - d * i, a * i - c * g, c * d - a * f],
           [d * h - e * g, b * g - a * h, a * e - b * d]]
    if a * adj[0][0] + b * adj[1][0] + c * adj[2][0] == 0:
        return np.full(len(matches), np.inf)
    pts = matches.T.reshape(2, 2, -1)  # [[x1, y1], [x2, y2]]
    both = np.array([H.tolist(), adj])
    p = both[:, :, :2] @ pts + both[:, :, 2:]  # (2 directions, 3, N)
    with np.errstate(all="ignore"):
        dd = p[:, :2] / p[:, 2:] - pts[::-1]
        dd *= dd
        out = np.sqrt(0.5 * ((dd[0, 0] + dd[0, 1]) + (dd[1, 0] + dd[1, 1])))
    return np.where(np.isfinite(out), out, np.inf)


class HomographySpace(HypothesisSpace):
    """Planar homographies from point correspondences ``(x1, y1, x2, y2)``.

    Parameters
    ----------
    residual : {"transfer", "symmetric"}
        ``transfer``: ``||x2 - H x1||``; ``symmetric``: root mean square of
        the forward and backward transfer errors (pixels).
    normalization : {"h33", "det"}
        Normalisation of the homography group used for distances.
    polish : bool
        :meth:`refine` finishes the DLT refit on the inliers with a
        reweighted DLT on the symmetric transfer error
        (:func:`~clap_unified.spaces.homography_polish.polish_homography`): the
        library's default CLAP (``polish=2.0``) and the package's earlier
        reading of the paper's CLAP (``"clap_densest"``). Without it (the
        paper's protocol for both CLAP and RANSAC) the refit is the whole
        refinement. A number ``s`` polishes with weights
        that reach zero at ``s`` times the inlier threshold (``True`` is 1):
        matches just beyond the threshold still pull a little, as in
        MAGSAC++'s marginalisation over noise scales; the inliers are still
        those within the threshold.

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

    def __init__(self, residual: str = "transfer", normalization: str = "h33", *,
                 polish: bool = False):
        self.residual = check_choice(residual, "residual", {"transfer", "symmetric"})
        self.normalization = check_choice(normalization, "normalization", {"h33", "det"})
        if isinstance(polish, (bool, np.bool_)):
            polish = bool(polish)
        elif not (isinstance(polish, (int, float, np.floating, np.integer))
                  and np.isfinite(polish) and polish > 0):
            raise ValueError(f"polish: expected True, False or a positive number, "
                             f"got {polish!r}")
        else:
            polish = float(polish)
        self.polish = polish
        self._manifold = None

    @classmethod
    def for_data(cls, matches, *, residual: str = "transfer", metric: str = "lie_linear",
                 normalization: str = "det", screen: float = 1.0,
                 polish: bool = False) -> HomographySpace:
        """A space that compares hypotheses in the normalised frame of ``matches``.

        The manifold is a :class:`~clap_unified.geometry.homography_frame.HomographyInFrame`
        with the Hartley normalisations ``T1`` of the source and ``T2`` of the
        destination points: hypotheses are compared as ``T2 H T1^-1`` (entries
        of order one, fast all-pairs distances), while models, residuals and
        refits stay in pixels. ``polish`` as in the constructor.

        ``metric="transfer"`` compares hypotheses instead by where they send
        five anchors inside the matched region of the source image, in
        destination pixels
        (:class:`~clap_unified.geometry.homography_transfer.HomographyTransfer`
        with :func:`~clap_unified.geometry.homography_transfer.region_anchors`):
        a distance with a unit, and an embedding on which CLAP's density
        queries run on a k-d tree.

        Examples
        --------
        >>> rng = np.random.default_rng(0)
        >>> src = rng.uniform(0, 640, (50, 2))
        >>> space = HomographySpace.for_data(np.c_[src, src + 5.0])
        >>> space.manifold
        HomographyInFrame(metric='lie_linear', normalization='det', screen=1)
        >>> HomographySpace.for_data(np.c_[src, src + 5.0], metric="transfer").manifold
        HomographyTransfer(anchors=5)
        """
        from ..geometry.homography_frame import HomographyInFrame

        data = check_points(matches, "matches", dim=4, min_count=cls.min_samples)
        space = cls(residual=residual, normalization="h33", polish=polish)
        if metric == "transfer":
            from ..geometry.homography_transfer import HomographyTransfer, region_anchors

            space._manifold = HomographyTransfer(region_anchors(data[:, :2]))
            return space
        T1, T2 = normalise_points(data.reshape(-1, 2, 2).transpose(1, 0, 2))[1]
        space._manifold = HomographyInFrame(T1, T2, metric=metric, normalization=normalization,
                                            screen=screen)
        return space

    @classmethod
    def for_images(cls, size1, size2, *, residual: str = "transfer", metric: str = "lie_linear",
                   normalization: str = "det", screen: float = 1.0,
                   polish: bool = False) -> HomographySpace:
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

        space = cls(residual=residual, normalization="h33", polish=polish)
        space._manifold = HomographyInFrame(frame(size1, "size1"), frame(size2, "size2"),
                                            metric=metric, normalization=normalization,
                                            screen=screen)
        return space

    def __repr__(self) -> str:
        return (f"HomographySpace(residual={self.residual!r}, "
                f"normalization={self.normalization!r}, polish={self.polish!r})")

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
        data = np.asarray(data, dtype=float)
        # both point sets normalised in one batched pass
        q, c, (s1, s2) = _centre_scale(data.reshape(-1, 2, 2).transpose(1, 0, 2))
        samples = np.asarray(samples)
        # the same arithmetic, compiled (tested against the below), for samples in its
        # domain: the kernel does not check indices, so anything else (a float or
        # out-of-range index, another shape) takes the numpy path and its IndexError
        n = len(data)
        if (_compiled.AVAILABLE and samples.ndim == 2 and samples.shape[1] == 4
                and np.issubdtype(samples.dtype, np.integer)
                and (samples.size == 0 or (samples.min() >= -n and samples.max() < n))):
            (c1x, c1y), (c2x, c2y) = c.tolist()
            return homography_compiled.four_point_solve(
                np.ascontiguousarray(q), np.ascontiguousarray(samples, dtype=np.intp),
                float(s1), float(s2), c1x, c1y, c2x, c2y, SINGULAR_RATIO,
                self._manifold is not None)
        idx = samples.T  # (4, S)
        x, y = q[0, :, 0][idx] * s1, q[0, :, 1][idx] * s1
        u, v = q[1, :, 0][idx] * s2, q[1, :, 1][idx] * s2
        H, dets_src, dets_dst = _four_point(x, y, u, v, (c[0], s1, c[1], s2))  # (3, 3, S)
        # no three points of a sample (nearly) collinear, on either side
        tol_src = 1e-9 * max(np.abs(x).max(initial=0.0), np.abs(y).max(initial=0.0), 1.0) ** 2
        tol_dst = 1e-9 * max(np.abs(u).max(initial=0.0), np.abs(v).max(initial=0.0), 1.0) ** 2
        ok = ~(np.any(np.abs(dets_src) <= tol_src, axis=0)
               | np.any(np.abs(dets_dst) <= tol_dst, axis=0))
        h33 = H[2, 2]
        ok &= np.abs(h33) > 1e-12 * np.abs(H).max(axis=(0, 1), initial=0.0)
        owner = np.flatnonzero(ok)
        H = H[..., owner] / h33[owner]
        # near-singular models (a sample close to degenerate) are no homography:
        # |det G| against Hadamard's bound (the product of the row norms), a
        # ratio in [0, 1] free of H's scale, compared squared; a non-finite entry
        # makes the comparison false. G is H in the frame where the manifold compares
        # hypotheses: pixels for this class's own manifold, else the data's Hartley
        # frame T2 H T1^-1, where the test depends neither on the data's unit nor on
        # its origin (in pixels the translation column grows with the coordinates, and
        # the bound with it: at a unit of 1e-6 pixel every hypothesis would fail)
        with np.errstate(all="ignore"):
            G = H
            if self._manifold is not None:
                (c1x, c1y), (c2x, c2y) = c[0], c[1]
                K = np.stack([H[:, 0], H[:, 1], H[:, 0] * (c1x * s1) + H[:, 1] * (c1y * s1)
                              + H[:, 2] * s1], axis=1)  # s1 H T1^-1
                G = np.stack([K[0] - c2x * K[2], K[1] - c2y * K[2], K[2] / s2])  # T2 K / s2
            det = (G[0, 0] * (G[1, 1] * G[2, 2] - G[1, 2] * G[2, 1])
                   - G[0, 1] * (G[1, 0] * G[2, 2] - G[1, 2] * G[2, 0])
                   + G[0, 2] * (G[1, 0] * G[2, 1] - G[1, 1] * G[2, 0]))
            rows2 = np.sum(G * G, axis=1)
            keep = det * det > SINGULAR_RATIO**2 * (rows2[0] * rows2[1] * rows2[2])
        return np.ascontiguousarray(np.moveaxis(H[..., keep], -1, 0)), owner[keep]

    def refit(self, data, weights=None, initial=None):
        data = np.asarray(data, dtype=float)
        w = None if weights is None else np.asarray(weights, dtype=float)
        if w is not None:
            keep = w > 0
            data, w = data[keep], w[keep]
        if len(data) < 4:
            return None
        if _compiled.AVAILABLE:  # the same DLT, compiled (tested against dlt)
            H = homography_compiled.weighted_dlt(np.ascontiguousarray(data),
                                                 np.ones(len(data)) if w is None else w)
        else:
            H = dlt(data[:, :2], data[:, 2:], w)
        if abs(H[2, 2]) <= 1e-12 or not np.all(np.isfinite(H)):
            return None
        H = H / H[2, 2]
        sv = np.linalg.svd(H, compute_uv=False)  # rank < 3 as numpy.linalg.matrix_rank says
        if sv[-1] <= sv[0] * 3 * np.finfo(float).eps:
            return None
        return H

    def residuals(self, models, data) -> np.ndarray:
        H = np.asarray(models, dtype=float).reshape(-1, 3, 3)
        data = np.asarray(data, dtype=float)
        if self.residual == "transfer":
            return transfer_error(H, data[:, :2], data[:, 2:])
        return np.array([symmetric_transfer_error(h, data) for h in H]).reshape(len(H),
                                                                                len(data))

    def model_to_dict(self, model) -> dict:
        H = np.asarray(model, dtype=float)
        return {"H": (H / H[2, 2]).tolist()}

    def default_threshold(self, data) -> float:
        return 3.0  # pixels, OpenCV's default ransacReprojThreshold

    def default_cell_size(self, data) -> float:
        """Randomized Hough cell edge: 0.05 in the space's (normalised-frame) log chart."""
        return 0.05

    def hypotheses(self, data, n, *, rng=None, prior=None, radius=None, quality=None,
                   pools: int = 8, min_pool: int = 8,
                   neighbours: int | None = None) -> HypothesisSet:
        """Candidate homographies from 4-match samples, uniform or progressive.

        Parameters
        ----------
        data : ndarray of shape (N, 4)
            Checked matches.
        n : int
            Candidates wanted.
        rng : None, int or numpy.random.Generator
        prior, radius
            Ignored: homography hypotheses do not depend on a prior.
        quality : ndarray of shape (N,), optional
            Lower is better (e.g. the SIFT ratio of each match). Without it,
            uniform random samples (one batch with a margin for degenerate
            ones). With it, progressive sampling as in PROSAC: the ``n``
            draws are split into ``pools`` groups drawn from the best
            ``m_1 < m_2 < ... = N`` matches (geometrically growing, the first
            ``min_pool``); no 4-subset is drawn twice (a small pool may then
            give fewer candidates).
        pools, min_pool : int
        neighbours : int, optional
            Local sampling instead (not with ``quality``): each sample is a
            match and three others among its ``neighbours`` nearest, in both
            images (:func:`~clap_unified.spaces.sampling.sample_local_subsets`).

        Returns
        -------
        HypothesisSet

        Examples
        --------
        >>> rng = np.random.default_rng(0)
        >>> src = rng.uniform(0, 640, (60, 2))
        >>> data = np.c_[src, src + 5.0]
        >>> hs = HomographySpace().hypotheses(data, 40, quality=np.arange(60), rng=0)
        >>> len(hs), int(hs.samples[:5].max()) < 8
        (40, True)
        """
        from .sampling import generate_hypotheses, sample_subsets

        n = check_int(n, "n", minimum=1)
        if neighbours is not None:
            if quality is not None:
                raise ValueError("neighbours: local sampling does not take a quality")
            return generate_hypotheses(self, data, n, rng=rng, batch_size=n + n // 4 + 8,
                                       neighbours=neighbours)
        if quality is None:
            # one batch with a margin for degenerate samples, not a second full batch
            return generate_hypotheses(self, data, n, rng=rng, batch_size=n + n // 4 + 8)
        q = check_array(quality, "quality", shape=(len(data),))
        pools = check_int(pools, "pools", minimum=1)
        order = np.argsort(q, kind="stable")
        sizes = np.unique(np.geomspace(min(max(min_pool, 4), len(data)), len(data), pools)
                          .round().astype(int))
        per = np.diff(np.linspace(0, n, len(sizes) + 1).round().astype(int))
        g = as_generator(rng)
        models, samples = [], []
        drawn = bad = 0
        new_rows = _NewSamples(len(data), int(per.sum()) + 8 * len(per))
        for size, k in zip(sizes, per, strict=True):
            if k == 0:
                continue
            # distinct samples only: the first pools are small (8 matches have 70
            # 4-subsets), and a repeated sample would add a copy of a candidate,
            # support that no new data gives (and exact ties between clusters).
            # A few extra draws so degenerate samples do not leave the pool short.
            want = int(k) + 8
            idx, have = [], 0
            for _ in range(8):
                rows = np.sort(order[sample_subsets(int(size), 4, want, rng=g)], axis=1)
                idx.append(new_rows(rows, want - have))
                have += len(idx[-1])
                if have >= want:
                    break
            idx = np.concatenate(idx)
            if len(idx) == 0:
                continue
            mod, owner = self.solve_minimal(data, idx)
            drawn += len(idx)
            bad += len(idx) - len(owner)
            models.append(mod[:k])
            samples.append(idx[owner[:k]])
        models = np.concatenate(models) if models else np.empty((0, 3, 3))
        samples = np.concatenate(samples) if samples else np.empty((0, 4), dtype=np.intp)
        return HypothesisSet(models, samples, drawn, bad, False, self)

    def refine(self, model, data, threshold):
        """DLT refit on the inliers, then, with ``polish``, the reweighted DLT.

        With ``polish=s`` (a number) the reweighted DLT uses ``s * threshold``.

        The one refinement route of the space (:func:`~clap_unified.fit`
        calls it). With ``polish`` the inliers returned are the matches whose
        symmetric transfer error is below ``threshold`` (the polish's rule).
        """
        model, inliers = refit_on_inliers(self, model, data, threshold)
        if self.polish:
            from .homography_polish import polish_checked

            scale = 1.0 if self.polish is True else self.polish
            model, inliers = polish_checked(model, data, scale * threshold)
            if scale != 1.0:
                inliers = symmetric_transfer_error(model, data) < threshold
        return model, inliers
