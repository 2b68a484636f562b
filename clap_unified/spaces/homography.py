"""Hypothesis space of planar homographies.

Convention: ``x2 ~ H x1`` for correspondences ``(x1, y1, x2, y2)`` (the VPG
format). Models are normalised so that ``H[2, 2] = 1``; a homography whose ``H[2, 2]``
is zero (it sends the image origin to infinity) has unit Frobenius norm instead
(:func:`~clap_unified.geometry.homography_arithmetic.scale_homography`).

The arithmetic every homography module uses lives on the geometry floor,
:mod:`clap_unified.geometry.homography_arithmetic` (re-exported here):

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
from .._validation import (
    Checked,
    as_generator,
    check_array,
    check_choice,
    check_int,
    check_points,
    unwrap_checked,
)
from ..geometry.homography_arithmetic import (
    SINGULAR_RATIO,
    _centre_scale,
    _four_point,
    dlt,
    four_point_homography,  # noqa: F401  (re-exported: the arithmetic as before)
    normalise_points,
    scale_homography,
    symmetric_transfer_error,
    transfer,  # noqa: F401  (re-exported)
    transfer_error,
)
from ..refine import refit_on_inliers
from . import homography_compiled
from .base import HypothesisSet, HypothesisSpace

__all__ = ["DEFAULT_THRESHOLD", "HomographySpace"]

#: The inlier threshold of homographies, in pixels (OpenCV's default
#: ``ransacReprojThreshold``): the space's default and every preset's
#: (:mod:`clap_unified.presets`).
DEFAULT_THRESHOLD = 3.0

class _NewSamples:
    """The samples of each batch never taken before, in order, up to a count.

    The numpy path keeps a Python set of the rows; the compiled one
    (:func:`~clap_unified.spaces.homography_compiled.take_new_samples`) a
    hash table, with the same answer (tested) in less time
    (``bench/bench_compiled.py`` times the default CLAP estimate, whose
    progressive candidates use it, with and without the kernels).
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
    hundreds of candidates. :func:`~clap_unified.fit` on a plain space
    therefore builds the space its preset names (:mod:`~clap_unified.presets`:
    the homography CLAP's compares hypotheses by where they send anchors of
    the matched region); to choose the frame yourself, use :meth:`for_data`
    (the Hartley frame of the matches) or :meth:`for_images` (the image-size
    frame), which ``fit`` uses as given.
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
        self._framed = False  # for_data / for_images set their own manifold

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

        data = unwrap_checked(matches, cls().check_data)
        space = cls(residual=residual, normalization="h33", polish=polish)
        if metric == "transfer":
            from ..geometry.homography_transfer import HomographyTransfer, region_anchors

            space._manifold = HomographyTransfer(region_anchors(Checked(data[:, :2])))
            space._framed = True
            return space
        T1, T2 = normalise_points(data.reshape(-1, 2, 2).transpose(1, 0, 2))[1]
        space._manifold = HomographyInFrame(T1, T2, metric=metric, normalization=normalization,
                                            screen=screen)
        space._framed = True
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
        space._framed = True
        return space

    @property
    def is_plain(self) -> bool:
        """Built as ``HomographySpace()``: every constructor default, no frame.

        :func:`~clap_unified.fit` builds the space a preset asks for
        (:mod:`~clap_unified.presets`) from a plain space only; a space
        configured by hand is used as given.

        Examples
        --------
        >>> HomographySpace().is_plain, HomographySpace(polish=True).is_plain
        (True, False)
        >>> src = np.random.default_rng(0).uniform(0, 640, (20, 2))
        >>> HomographySpace.for_data(np.c_[src, src + 1.0]).is_plain
        False
        """
        return (type(self) is HomographySpace and not self._framed
                and self.residual == "transfer" and self.normalization == "h33"
                and self.polish is False)

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
                self._framed)
        idx = samples.T  # (4, S)
        x, y = q[0, :, 0][idx] * s1, q[0, :, 1][idx] * s1
        u, v = q[1, :, 0][idx] * s2, q[1, :, 1][idx] * s2
        H, dets_src, dets_dst = _four_point(x, y, u, v, (c[0], s1, c[1], s2))  # (3, 3, S)
        # no three points of a sample (nearly) collinear, on either side
        tol_src = 1e-9 * max(np.abs(x).max(initial=0.0), np.abs(y).max(initial=0.0), 1.0) ** 2
        tol_dst = 1e-9 * max(np.abs(u).max(initial=0.0), np.abs(v).max(initial=0.0), 1.0) ** 2
        ok = ~(np.any(np.abs(dets_src) <= tol_src, axis=0)
               | np.any(np.abs(dets_dst) <= tol_dst, axis=0))
        owner = np.flatnonzero(ok)
        # H33 = 1, or scale_homography's fallback where H33 is zero (the image origin
        # maps to infinity: a homography all the same, OpenCV fits it)
        H = np.moveaxis(scale_homography(np.moveaxis(H[..., owner], -1, 0)), 0, -1)
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
            if self._framed:  # not merely read: the manifold for_data gave
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
        H = scale_homography(H)  # H33 = 1, or the fallback where H33 is zero
        if not np.all(np.isfinite(H)):
            return None
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
        return {"H": scale_homography(model).tolist()}

    def default_threshold(self, data) -> float:
        return DEFAULT_THRESHOLD

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
        data = np.asarray(data, dtype=float)  # checked (check_data) by the caller
        if neighbours is not None:
            if quality is not None:
                raise ValueError("neighbours: local sampling does not take a quality")
            return generate_hypotheses(self, Checked(data), n, rng=rng,
                                       batch_size=n + n // 4 + 8, neighbours=neighbours)
        if quality is None:
            # one batch with a margin for degenerate samples, not a second full batch
            return generate_hypotheses(self, Checked(data), n, rng=rng,
                                       batch_size=n + n // 4 + 8)
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
