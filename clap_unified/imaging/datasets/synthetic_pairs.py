"""Synthetic hard homography pairs: few inliers, a coherent decoy motion, exact truth.

A pair of two 640 x 480 views of one plane, with the true homography drawn
like a hand-held camera's (rotation, scale, a moderate perspective, a shift)
and ``n_matches`` tentative matches of three kinds:

* **inliers**: points spread over the part of view 1 that view 2 sees, their
  images under the true ``H`` with Gaussian noise (``noise`` px, in view 2);
* **decoys**: matches consistent with a second, different homography on a
  smaller region of view 1 (a coherent but wrong motion, like an object
  moving across the plane): a cluster of agreeing matches that is not the
  answer;
* **outliers**: uniform random points in both views.

Every pair is a :class:`~clap_unified.imaging.datasets.HomographyPair` like
homogr's and EVD's: ``input`` holds the (shuffled) matches and a simulated
SIFT-like ratio per match as ``quality`` (lower is better; inliers and decoys
tend to be better than outliers, but the distributions overlap: quality
helps, it is no oracle); ``truth`` (a :class:`SyntheticTruth`) holds ``H``,
the inlier labels, 8 to 20 noise-free validation points of the plane mapped
by ``H`` (evaluation only, never rows of the input), and the decoy
homography and labels. Everything is deterministic for a seed.

Examples
--------
>>> pair = synthetic_pair(0.2, decoy_ratio=0.1, rng=0)
>>> pair.input.matches.shape, round(pair.inlier_ratio, 2), int(pair.truth.decoys.sum())
((500, 4), 0.2, 50)
>>> [p.name for p in synthetic_pairs()][:2]
['synthetic r=0.08 decoy=0 #0', 'synthetic r=0.08 decoy=0.1 #1']
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..._validation import as_generator, check_fraction, check_int, check_positive
from .homography_benchmarks import HomographyInput, HomographyPair, HomographyTruth

__all__ = ["DECOY_SHARES", "INLIER_RATIOS", "SyntheticTruth", "synthetic_pair",
           "synthetic_pairs"]

#: Inlier ratios of the fixed hard set :func:`synthetic_pairs`.
INLIER_RATIOS = (0.08, 0.12, 0.2, 0.3)
#: Decoys of the fixed hard set :func:`synthetic_pairs`, as a share of its inliers: the decoy
#: motion is always the smaller one (with more decoys than inliers the "true" motion would be
#: the minority, and no estimator could be asked to prefer it).
DECOY_SHARES = (0.0, 0.5, 0.75)


@dataclass(frozen=True)
class SyntheticTruth(HomographyTruth):
    """:class:`~clap_unified.imaging.datasets.HomographyTruth` plus the decoy motion.

    Attributes
    ----------
    H, inliers, validation
        As in :class:`~clap_unified.imaging.datasets.HomographyTruth`:
        ``inliers`` are the planted inliers, ``validation`` 8 to 20
        noise-free points of the plane, ``(x1, y1, x2, y2)`` with
        ``x2 ~ H x1``.
    decoy_H : ndarray of shape (3, 3)
        The decoy homography (``H33 = 1``), drawn even when there are no
        decoys.
    decoys : ndarray of bool, shape (N,)
        The matches made by ``decoy_H``.
    """

    decoy_H: np.ndarray = None
    decoys: np.ndarray = None


def _apply(H, p):
    q = p @ H[:, :2].T + H[:, 2]
    return q[:, :2] / q[:, 2:]


def _from_corners(src, dst):
    """The homography sending the four points ``src`` to ``dst`` (``H33 = 1``)."""
    A = np.zeros((8, 8))
    b = np.zeros(8)
    for k, ((x, y), (u, v)) in enumerate(zip(src, dst, strict=True)):
        A[2 * k] = [x, y, 1, 0, 0, 0, -u * x, -u * y]
        A[2 * k + 1] = [0, 0, 0, x, y, 1, -v * x, -v * y]
        b[2 * k], b[2 * k + 1] = u, v
    return np.append(np.linalg.solve(A, b), 1.0).reshape(3, 3)


def _inside(p, size, margin=0.0):
    w, h = size
    return ((p[:, 0] >= margin) & (p[:, 0] <= w - margin) & (p[:, 1] >= margin)
            & (p[:, 1] <= h - margin))


def _true_homography(rng, size):
    """A hand-held camera's homography: most of view 1 stays in view 2."""
    w, h = size
    corners = np.array([[0, 0], [w, 0], [w, h], [0, h]], float)
    centre = np.array([w, h]) / 2
    grid = np.stack(np.meshgrid(np.linspace(0, w, 17), np.linspace(0, h, 13)), -1)
    grid = grid.reshape(-1, 2)
    while True:
        angle = np.deg2rad(rng.uniform(-25, 25))
        scale = rng.uniform(0.75, 1.3)
        R = scale * np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
        shift = rng.uniform(-0.1, 0.1, 2) * [w, h]
        dst = (corners - centre) @ R.T + centre + shift
        dst += rng.uniform(-0.08, 0.08, (4, 2)) * [w, h]  # a moderate perspective
        H = _from_corners(corners, dst)
        if np.mean(_inside(_apply(H, grid), size)) >= 0.45:
            return H


def _draw(rng, n, region, accept, batch=4096):
    """``n`` uniform points of the box ``region`` that ``accept`` keeps (rejection)."""
    (x0, y0), (x1, y1) = region
    out = np.empty((0, 2))
    for _ in range(200):
        if len(out) >= n:
            return out[:n]
        p = rng.uniform([x0, y0], [x1, y1], (batch, 2))
        out = np.concatenate([out, p[accept(p)]])
    if len(out) >= n:
        return out[:n]
    raise RuntimeError("could not place the points (region too small)")


def _decoy(rng, H, size, n):
    """A second motion on a smaller region of view 1, and ``n`` of its noise-free matches."""
    w, h = size
    for _ in range(100):
        rw, rh = rng.uniform(0.22, 0.35) * w, rng.uniform(0.22, 0.35) * h
        x0, y0 = rng.uniform(0, w - rw), rng.uniform(0, h - rh)
        centre = np.array([x0 + rw / 2, y0 + rh / 2])
        angle = np.deg2rad(rng.uniform(8, 20) * rng.choice([-1, 1]))
        c, s = np.cos(angle), np.sin(angle)
        shift = rng.uniform(40, 100) * np.array([np.cos(a := rng.uniform(0, 2 * np.pi)),
                                                 np.sin(a)])
        M = np.eye(3)
        M[:2, :2] = [[c, -s], [s, c]]
        M[:2, 2] = centre - M[:2, :2] @ centre + shift
        D = H @ M
        D /= D[2, 2]
        box = ((x0, y0), (x0 + rw, y0 + rh))
        probe = rng.uniform(box[0], box[1], (400, 2))
        if np.mean(_inside(_apply(D, probe), size)) < 0.5:
            continue
        try:
            src = _draw(rng, n, box, lambda p, D=D: _inside(_apply(D, p), size))
        except RuntimeError:
            continue
        return D, src
    raise RuntimeError("could not place the decoy region")


def synthetic_pair(inlier_ratio: float, *, decoy_ratio: float = 0.0, n_matches: int = 500,
                   noise: float = 1.0, size=(640, 480), rng=None,
                   name: str | None = None) -> HomographyPair:
    """One synthetic pair with the given share of inliers and of decoys.

    Parameters
    ----------
    inlier_ratio : float
        Fraction of the matches that are inliers of the true homography, in
        (0, 1]; at least 4 inliers.
    decoy_ratio : float
        Fraction consistent with the decoy homography, in [0, 1);
        ``inlier_ratio + decoy_ratio <= 1``; the rest are uniform outliers.
    n_matches : int
        Number of matches (at least 8).
    noise : float
        Standard deviation in pixels of the Gaussian noise on the inliers'
        and decoys' points in view 2 (0 for exact matches).
    size : (width, height)
        Both views' size in pixels.
    rng : None, int or numpy.random.Generator
        The seed: the same int gives the same pair.
    name : str, optional
        Default ``"synthetic r=<inlier_ratio> decoy=<decoy_ratio>"``.

    Returns
    -------
    HomographyPair
        ``dataset="synthetic"``; ``input``: the shuffled matches and their
        simulated ratio (``quality``, in (0, 1), lower is better); ``truth``:
        a :class:`SyntheticTruth`.

    Raises
    ------
    ValueError
        A ratio out of range, fewer than 4 inliers, a bad count, noise or
        size.

    Examples
    --------
    >>> pair = synthetic_pair(0.3, n_matches=200, noise=0.0, rng=1)
    >>> from clap_unified.imaging.metrics import symmetric_reprojection_error
    >>> m = pair.input.matches[pair.truth.inliers]
    >>> len(m), bool(symmetric_reprojection_error(pair.truth.H, m).max() < 1e-6)
    (60, True)
    >>> 8 <= len(pair.truth.validation) <= 20
    True
    """
    inlier_ratio = check_fraction(inlier_ratio, "inlier_ratio", inclusive=(False, True))
    decoy_ratio = check_fraction(decoy_ratio, "decoy_ratio", inclusive=(True, False))
    n = check_int(n_matches, "n_matches", minimum=8)
    noise = float(noise)
    if not np.isfinite(noise) or noise < 0:
        raise ValueError(f"noise: expected a non-negative number of pixels, got {noise!r}")
    try:
        w, h = (check_positive(float(v), "size") for v in size)
    except (TypeError, ValueError):
        raise ValueError(f"size: expected (width, height) in pixels, got {size!r}") from None
    if inlier_ratio + decoy_ratio > 1 + 1e-12:
        raise ValueError(f"decoy_ratio: inlier_ratio + decoy_ratio must be at most 1, got "
                         f"{inlier_ratio} + {decoy_ratio}")
    n_in = int(round(inlier_ratio * n))
    n_dec = min(int(round(decoy_ratio * n)), n - n_in)
    if n_in < 4:
        raise ValueError(f"inlier_ratio: {inlier_ratio} of {n} matches is fewer than 4 inliers")
    size = (w, h)
    g = as_generator(rng)

    H = _true_homography(g, size)
    src_in = _draw(g, n_in, ((0, 0), size), lambda p: _inside(_apply(H, p), size))
    dst_in = _apply(H, src_in) + g.normal(0, noise, (n_in, 2))
    D, src_dec = _decoy(g, H, size, n_dec)
    dst_dec = _apply(D, src_dec) + g.normal(0, noise, (n_dec, 2))
    n_out = n - n_in - n_dec
    out = np.c_[g.uniform((0, 0), size, (n_out, 2)), g.uniform((0, 0), size, (n_out, 2))]
    matches = np.concatenate([np.c_[src_in, dst_in], np.c_[src_dec, dst_dec], out])
    kind = np.repeat([0, 1, 2], [n_in, n_dec, n_out])
    # SIFT-like ratio: real matches (inliers, decoys) a bit better than outliers, overlapping
    quality = np.where(kind < 2, g.beta(6.0, 4.0, n), g.beta(9.0, 3.0, n))
    order = g.permutation(n)
    matches, kind, quality = matches[order], kind[order], quality[order]

    n_val = int(g.integers(8, 21))
    val_src = _draw(g, n_val, ((0, 0), size), lambda p: _inside(_apply(H, p), size))
    validation = np.c_[val_src, _apply(H, val_src)]
    if name is None:
        name = f"synthetic r={inlier_ratio:g} decoy={decoy_ratio:g}"
    return HomographyPair(name, "synthetic", HomographyInput(matches, quality),
                          SyntheticTruth(H, kind == 0, validation, D, kind == 1))


def synthetic_pairs(seed: int = 0, *, n_matches: int = 500, noise: float = 1.0
                    ) -> list[HomographyPair]:
    """The fixed hard set: every inlier ratio of ``INLIER_RATIOS`` with every decoy share.

    A pair with inlier ratio ``r`` and decoy share ``f`` (``DECOY_SHARES``) has
    ``f * r`` of its matches on the decoy motion.

    Parameters
    ----------
    seed : int
        Pair ``k`` is drawn with ``rng=numpy.random.default_rng((seed, k))``.
    n_matches, noise
        As in :func:`synthetic_pair`.

    Returns
    -------
    list of HomographyPair
        12 pairs, ``"synthetic r=<ratio> decoy=<ratio> #<k>"``, inlier ratio
        in the outer loop.

    Examples
    --------
    >>> pairs = synthetic_pairs()
    >>> len(pairs), pairs[-1].name
    (12, 'synthetic r=0.3 decoy=0.225 #11')
    >>> bool(np.array_equal(pairs[3].input.matches, synthetic_pairs()[3].input.matches))
    True
    """
    seed = check_int(seed, "seed", minimum=0)
    out = []
    for k, (r, f) in enumerate((r, f) for r in INLIER_RATIOS for f in DECOY_SHARES):
        d = round(f * r, 4)
        out.append(synthetic_pair(r, decoy_ratio=d, n_matches=n_matches, noise=noise,
                                  rng=np.random.default_rng((seed, k)),
                                  name=f"synthetic r={r:g} decoy={d:g} #{k}"))
    return out
