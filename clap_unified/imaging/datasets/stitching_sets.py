"""Real panorama sets with parallax: the substitute for VPG's real-world sets S13-S36.

Eleven multi-image sets of real photographs (boat, bridge, hill, ledge,
newspaper, pier, prague, railtracks, scottsdale, snow, uttower; 32 images)
gathered from public stitching demos and the APAP project (Zaragoza et al.,
CVPR 2013). Consecutive images of a set overlap. The scenes are not planar:
no homography explains them exactly and there is no ground truth, so they are
scored like the paper scores S13-S36, by the symmetric reprojection error and
the inlier ratio of each method on the matches the pipeline computes.

Files come from the manifest ``manifests/stitching_sets.json`` (package data) through
:func:`~clap_unified.imaging.datasets.sources.fetch` (mirror, cache or the
public source, sha256 checked).
"""

from __future__ import annotations

from dataclasses import dataclass

from .sources import fetch, load_manifest

__all__ = ["PanoramaInput", "PanoramaSet", "PanoramaTruth", "load_stitching_set",
           "stitching_set_names"]

_DATASET = "stitching_sets"


@dataclass(frozen=True)
class PanoramaInput:
    """What an estimator may see: the photographs, in panorama order.

    Attributes
    ----------
    images : tuple of str
        Paths of the images; ``images[i]`` overlaps ``images[i + 1]``.
    """

    images: tuple

    @property
    def pairs(self) -> list[tuple[int, int]]:
        """Index pairs of overlapping images ``(0, 1), (1, 2), ...``."""
        return [(i, i + 1) for i in range(len(self.images) - 1)]


@dataclass(frozen=True)
class PanoramaTruth:
    """Evaluation data of a real panorama set: there is none (no ground truth)."""


@dataclass(frozen=True)
class PanoramaSet:
    """One real panorama set.

    Attributes
    ----------
    name : str
    input : PanoramaInput
    truth : PanoramaTruth
        Empty: these sets have no ground truth.
    """

    name: str
    input: PanoramaInput
    truth: PanoramaTruth


def stitching_set_names() -> list[str]:
    """Names of the sets, from the manifest.

    Examples
    --------
    >>> stitching_set_names()[:3]
    ['boat', 'bridge', 'hill']
    """
    return sorted(load_manifest(_DATASET)["sets"])


def load_stitching_set(name: str) -> PanoramaSet:
    """One set, its files fetched (mirror, cache or public source) and verified.

    Raises
    ------
    ValueError
        ``name`` is not a set of the manifest, or a file is corrupt.
    FileNotFoundError
        A file is neither mirrored, cached nor downloadable; the message says
        where to put it.

    Examples
    --------
    >>> s = load_stitching_set("hill")          # doctest: +SKIP
    >>> len(s.input.images), s.input.pairs      # doctest: +SKIP
    (3, [(0, 1), (1, 2)])
    """
    names = stitching_set_names()
    if name not in names:
        raise ValueError(f"name: {name!r} is not a stitching set; expected one of {names}")
    files = load_manifest(_DATASET)["sets"][name]
    return PanoramaSet(name, PanoramaInput(tuple(str(fetch(_DATASET, f)) for f in files)),
                       PanoramaTruth())
