"""Which data sets the experiments need, and whether they are here.

Each entry of :data:`DATASETS` checks that every file of one data set can be
had (local mirror, download cache or the public source, sha256 verified) and
otherwise returns the loader's message, which says where to put the files.
"""

from __future__ import annotations

__all__ = ["DATASETS", "missing_datasets"]


def _homography() -> None:
    from ..imaging.datasets.sources import fetch, load_manifest

    for relpath in load_manifest("homography")["files"]:
        if relpath.endswith("_pts.txt") or relpath.endswith("_model.txt"):
            fetch("homography", relpath)


def _stitching_sets() -> None:
    from ..imaging.datasets.sources import fetch, load_manifest

    for relpath in load_manifest("stitching_sets")["files"]:
        fetch("stitching_sets", relpath)


def _vpg() -> None:
    from ..imaging.datasets import vpg_root

    vpg_root(download=True)


def _adelaidermf() -> None:
    from ..imaging.datasets.sources import fetch, load_manifest

    for relpath in load_manifest("adelaidermf")["files"]:
        if relpath.startswith("H/"):
            fetch("adelaidermf", relpath)


#: Data set name -> check raising ``OSError`` or ``ValueError`` when it is missing or corrupt.
DATASETS = {
    "adelaidermf": _adelaidermf,
    "homography": _homography,
    "stitching_sets": _stitching_sets,
    "vpg": _vpg,
}


def missing_datasets(names) -> dict[str, str]:
    """``{name: reason}`` for each data set of ``names`` that cannot be had here."""
    out = {}
    for name in sorted(set(names)):
        try:
            DATASETS[name]()
        except (OSError, ValueError) as exc:
            out[name] = str(exc)
    return out
