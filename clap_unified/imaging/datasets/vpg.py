"""The VPG stitching dataset (Chen et al., "Vanishing Point Guided Natural Image
Stitching", 2020) in its own layout, and anything written in that layout.

Layout of one set ``Sxx/`` (36 sets; S01-S12 synthetic with ground-truth
correspondences, S13-S36 real):

* ``NN.jpg``: the images, ``NN`` from ``01``;
* ``mNN-MM.txt``: ground-truth correspondences between images NN and MM, one
  per line ``x1,y1,x2,y2`` (point in NN, point in MM): evaluation data, in
  ``VPGSet.truth``, never an estimator's input;
* ``camera-NN.txt``: a 3 x 3 rotation (three lines) then the camera position
  (one line), comma separated;
* ``Sxx-STITCH-GRAPH.txt``: ``{key | value | description}`` lines: the
  centre image index, the image count and the matching-graph edges
  ``matching_graph_image_edges-k | v``, read here as an edge between images
  ``k + 1`` and ``v + 1`` (0-based indices; the files are 1-based).

The dataset root is ``$CLAP_UNIFIED_VPG`` when set, else ``vpg/`` of the local
mirror (:func:`~clap_unified.imaging.datasets.sources.mirror_dir`), else the
download cache. :func:`vpg_root` downloads and unpacks the archive named in
the packaged manifest ``manifests/vpg.json`` when it has one and the network allows, and
otherwise raises ``FileNotFoundError`` saying where to put the files.
"""

from __future__ import annotations

import os
import re
import zipfile
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType

import numpy as np

from ...datatypes import readonly
from .sources import _download, cache_dir, load_manifest, mirror_dir

__all__ = ["VPGInput", "VPGSet", "VPGTruth", "list_vpg_sets", "load_vpg_set", "read_camera",
           "read_correspondences", "read_stitch_graph", "vpg_root"]

_SET = re.compile(r"S\d{2}")


def _frozen_mapping(d: dict) -> MappingProxyType:
    """A read-only view of ``d`` whose arrays (also inside tuples) are read-only copies."""
    def ro(v):
        if isinstance(v, np.ndarray):
            return readonly(v)
        if isinstance(v, tuple):
            return tuple(ro(x) for x in v)
        return v
    return MappingProxyType({k: ro(v) for k, v in d.items()})


@dataclass(frozen=True)
class VPGInput:
    """What a stitching method may see of a VPG set: the images and the matching graph.

    Attributes
    ----------
    images : mapping of int to Path
        Image files by 1-based index (may be empty when only text is present).
    graph : mapping
        ``center``, ``count``, ``edges`` (list of 1-based index pairs) and the
        raw ``{key: value}`` ``entries`` of ``Sxx-STITCH-GRAPH.txt``.
    """

    images: Mapping = field(default_factory=dict)
    graph: Mapping = field(default_factory=dict)

    def __post_init__(self):
        object.__setattr__(self, "images", _frozen_mapping(self.images))
        graph = dict(self.graph)
        if "edges" in graph:
            graph["edges"] = tuple(tuple(e) for e in graph["edges"])
        if "entries" in graph:
            graph["entries"] = MappingProxyType(dict(graph["entries"]))
        object.__setattr__(self, "graph", _frozen_mapping(graph))


@dataclass(frozen=True)
class VPGTruth:
    """Evaluation data of a VPG set: never input to an estimator.

    Attributes
    ----------
    correspondences : mapping of (int, int) to ndarray of shape (N, 4)
        The ground-truth correspondences ``mNN-MM.txt`` by ``(NN, MM)``
        (read-only; S01-S12 only).
    cameras : mapping of int to (ndarray (3, 3), ndarray (3,))
        Rotation and position of each camera file (read-only).
    """

    correspondences: Mapping = field(default_factory=dict)
    cameras: Mapping = field(default_factory=dict)

    def __post_init__(self):
        object.__setattr__(self, "correspondences", _frozen_mapping(self.correspondences))
        object.__setattr__(self, "cameras", _frozen_mapping(self.cameras))

    def H(self, i: int, j: int) -> np.ndarray:
        """``H_gt`` mapping image ``i`` to image ``j``: DLT fit to ``mII-JJ.txt``.

        Raises
        ------
        ValueError
            The set has no ground-truth correspondences for ``(i, j)``.
        """
        from ...geometry.homography_arithmetic import dlt

        if (i, j) not in self.correspondences:
            raise ValueError(f"(i, j): no ground-truth correspondences m{i:02d}-{j:02d}.txt")
        m = self.correspondences[(i, j)]
        H = dlt(m[:, :2], m[:, 2:])
        return readonly(H / H[2, 2])


@dataclass(frozen=True)
class VPGSet:
    """One set of the VPG layout: the ``input`` a method may use, the ``truth`` that scores it.

    VPG's ``mNN-MM.txt`` files hold the **ground-truth** correspondences of
    the synthetic sets S01-S12 (exact, or in the generated stand-in exact up to
    6 decimals): they define ``H_gt`` and are evaluation data. A method's input
    is the images (and the matching graph, which only says which images
    overlap); its matches come from the images (SIFT, see
    :func:`clap_unified.imaging.evaluation.vpg_pair_matches`). Camera files
    give the true rotations and are evaluation data too.

    Attributes
    ----------
    name : str
        ``"Sxx"``.
    path : Path
    input : VPGInput
        ``images``, ``graph``.
    truth : VPGTruth
        ``correspondences``, ``cameras``; ``truth.H(i, j)`` is the ground-truth
        homography.
    """

    name: str
    path: Path
    input: VPGInput
    truth: VPGTruth

    def pairs(self) -> list[tuple[int, int]]:
        """Image pairs with ground-truth correspondences, else the graph's edges."""
        return sorted(self.truth.correspondences) or list(self.input.graph.get("edges", []))


def _read_rows(path: Path, width: int, what: str) -> np.ndarray:
    rows = []
    try:
        text = path.read_text()
    except (OSError, UnicodeDecodeError) as exc:
        raise ValueError(f"{path}: cannot read {what} ({exc})") from None
    for lineno, line in enumerate(text.splitlines(), start=1):
        if not line.strip():
            continue
        parts = line.replace(" ", "").split(",")
        try:
            vals = [float(v) for v in parts]
        except ValueError:
            raise ValueError(f"{path}: line {lineno}: non-numeric {what} {line!r}") from None
        if len(vals) != width or not np.all(np.isfinite(vals)):
            raise ValueError(f"{path}: line {lineno}: expected {width} finite numbers, "
                             f"got {line!r}")
        rows.append(vals)
    return np.array(rows, dtype=float).reshape(-1, width)


def read_correspondences(path) -> np.ndarray:
    """``mNN-MM.txt`` as an array ``(N, 4)`` of ``x1, y1, x2, y2``."""
    m = _read_rows(Path(path), 4, "correspondence")
    if len(m) < 4:
        raise ValueError(f"{path}: fewer than 4 correspondences")
    return m


def read_camera(path):
    """``camera-NN.txt`` as ``(R (3, 3), position (3,))``."""
    c = _read_rows(Path(path), 3, "camera row")
    if c.shape != (4, 3):
        raise ValueError(f"{path}: expected 4 lines of 3 numbers (rotation, position)")
    return c[:3], c[3]


def read_stitch_graph(path) -> dict:
    """``Sxx-STITCH-GRAPH.txt`` as ``{"center", "count", "edges", "entries"}``."""
    path = Path(path)
    entries = {}
    for lineno, line in enumerate(path.read_text().splitlines(), start=1):
        line = line.strip()
        if not line:
            continue
        m = re.fullmatch(r"\{\s*([^|]+?)\s*\|\s*([^|]*?)\s*\|\s*([^}]*?)\s*\}", line)
        if m is None:
            raise ValueError(f"{path}: line {lineno}: expected '{{key | value | description}}'")
        entries[m.group(1)] = m.group(2)
    edges = []
    for key, value in entries.items():
        e = re.fullmatch(r"matching_graph_image_edges-(\d+)", key)
        if e:
            edges.append((int(e.group(1)) + 1, int(value) + 1))
    try:
        center = int(entries.get("center_image_index", 0))
        count = int(entries.get("images_count", 0))
    except ValueError:
        raise ValueError(f"{path}: non-integer centre index or image count") from None
    return {"center": center, "count": count, "edges": sorted(edges), "entries": entries}


def load_vpg_set(path) -> VPGSet:
    """Read one set folder ``Sxx/`` (any of its files may be absent but the graph).

    Parameters
    ----------
    path : path
        The set folder, named ``Sxx``.

    Returns
    -------
    VPGSet
        ``input``: the images and the matching graph; ``truth``: the
        ground-truth correspondences and the cameras.

    Raises
    ------
    FileNotFoundError
        No ``Sxx-STITCH-GRAPH.txt`` in ``path``.
    ValueError
        A malformed correspondence, camera or graph file (named).
    """
    path = Path(path)
    name = path.name
    graph_file = path / f"{name}-STITCH-GRAPH.txt"
    if not graph_file.is_file():
        raise FileNotFoundError(f"{path}: no {graph_file.name}; not a VPG set folder")
    graph = read_stitch_graph(graph_file)
    images, correspondences, cameras = {}, {}, {}
    for f in sorted(path.iterdir()):
        if m := re.fullmatch(r"(\d{2})\.(jpg|png)", f.name):
            images[int(m.group(1))] = f
        elif m := re.fullmatch(r"m(\d{2})-(\d{2})\.txt", f.name):
            correspondences[(int(m.group(1)), int(m.group(2)))] = read_correspondences(f)
        elif m := re.fullmatch(r"camera-(\d{2})\.txt", f.name):
            cameras[int(m.group(1))] = read_camera(f)
    return VPGSet(name, path, VPGInput(images, graph), VPGTruth(correspondences, cameras))


def list_vpg_sets(root) -> list[str]:
    """Set names ``Sxx`` under ``root``, sorted."""
    root = Path(root)
    return sorted(p.name for p in root.iterdir() if p.is_dir() and _SET.fullmatch(p.name))


def vpg_root(*, download: bool = True) -> Path:
    """The VPG dataset root (a folder holding ``S01/ ... S36/``).

    Looked for at ``$CLAP_UNIFIED_VPG``, the mirror ``vpg/`` and the cache
    ``vpg/``; otherwise the manifest's archive is downloaded and unpacked into
    the cache when it names one.

    Raises
    ------
    FileNotFoundError
        With the exact folders where the sets can be put.
    """
    man = load_manifest("vpg")
    env = os.environ.get("CLAP_UNIFIED_VPG")
    mirror = mirror_dir("vpg")
    places = ([Path(env)] if env else []) + ([] if mirror is None else [mirror]) + \
        [cache_dir("vpg")]
    for p in places:
        if p.is_dir() and list_vpg_sets(p):
            return p
    url = man.get("archive_url")
    reason = "the manifest names no downloadable archive"
    if url and download:
        target = cache_dir("vpg") / "vpg.zip"
        try:
            _download(url, target)
            with zipfile.ZipFile(target) as z:
                z.extractall(cache_dir("vpg"))
        except (OSError, zipfile.BadZipFile) as exc:
            reason = f"download of {url} failed ({exc})"
        else:
            for p in [cache_dir("vpg"), *cache_dir("vpg").iterdir()]:
                if p.is_dir() and list_vpg_sets(p):
                    return p
            reason = f"{url} held no Sxx/ folders"
    raise FileNotFoundError(
        f"VPG dataset not found ({reason}). Get it from {man['source']} and put the set "
        f"folders S01/ ... S36/ (each with NN.jpg, mNN-MM.txt, camera-NN.txt, "
        f"Sxx-STITCH-GRAPH.txt) in {' or '.join(str(p) for p in places)}, or set "
        "CLAP_UNIFIED_VPG to the folder holding them")
