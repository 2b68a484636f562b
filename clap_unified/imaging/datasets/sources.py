"""Finding dataset files: local mirror, download cache, public source; sha256 checked.

A dataset is described by a manifest ``manifests/<dataset>.json``, package data
next to this module (read with ``importlib.resources``, so an installed
package has it): ``base_url`` (public source), ``files`` (relative path ->
sha256) and optionally ``remote`` (relative path -> path under ``base_url``
where the public source lays files out differently; with ``"remote_complete":
false`` a file without a ``remote`` entry has no known public location). A file
is looked up, in order, in

1. the mirror: ``$CLAP_UNIFIED_DATA/<mirror_dir>`` when that environment
   variable is set, else, when the package runs from a checkout,
   ``../shared/data/<mirror_dir>`` next to the repository root (an installed
   package has no such default);
2. the download cache ``$CLAP_UNIFIED_CACHE/<mirror_dir>`` (default
   ``~/.cache/clap_unified/<mirror_dir>``);
3. the public source ``base_url + path``, downloaded into the cache.

Every file is checked against its sha256 before use; a missing file raises
``FileNotFoundError`` (an ``OSError``) saying where to put it, a corrupt one
``ValueError``.
"""

from __future__ import annotations

import hashlib
import json
import os
import urllib.request
from functools import cache
from importlib import resources
from pathlib import Path

__all__ = ["MANIFESTS", "cache_dir", "fetch", "load_manifest", "manifest_file", "mirror_dir",
           "sha256"]

#: The packaged manifests (``manifests/<dataset>.json``), an ``importlib.resources``
#: traversable.
MANIFESTS = resources.files(__package__).joinpath("manifests")

#: The repository root when the package runs from a checkout (it holds ``pyproject.toml``),
#: else None (an installed package).
_CHECKOUT = Path(__file__).resolve().parents[3]
CHECKOUT = _CHECKOUT if (_CHECKOUT / "pyproject.toml").is_file() else None

#: Seconds before a download attempt gives up.
TIMEOUT = 20.0


def sha256(path) -> str:
    """Hex sha256 of a file."""
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def manifest_file(dataset: str):
    """The packaged manifest of ``dataset`` (an ``importlib.resources`` traversable).

    Examples
    --------
    >>> manifest_file("homography").name
    'homography.json'
    """
    return MANIFESTS.joinpath(f"{dataset}.json")


@cache
def load_manifest(dataset: str) -> dict:
    """The manifest of ``dataset`` (``manifests/<dataset>.json``, package data) as a dict.

    Examples
    --------
    >>> sorted(load_manifest("stitching_sets")["sets"])[:2]
    ['boat', 'bridge']
    """
    path = manifest_file(dataset)
    if not path.is_file():
        raise FileNotFoundError(f"dataset {dataset!r}: no manifest {path}")
    return json.loads(path.read_text())


def mirror_dir(name: str) -> Path | None:
    """Where a local mirror of ``name`` is looked for (may not exist); None when no mirror is
    configured (``CLAP_UNIFIED_DATA`` unset and the package installed, not in a checkout)."""
    env = os.environ.get("CLAP_UNIFIED_DATA")
    if env:
        return Path(env) / name
    if CHECKOUT is None:
        return None
    return CHECKOUT.parent / "shared" / "data" / name


def cache_dir(name: str) -> Path:
    """Download cache of ``name`` (may not exist)."""
    env = os.environ.get("CLAP_UNIFIED_CACHE")
    base = Path(env) if env else Path.home() / ".cache" / "clap_unified"
    return base / name


def _download(url: str, target: Path) -> None:
    target.parent.mkdir(parents=True, exist_ok=True)
    tmp = target.with_suffix(target.suffix + ".part")
    with urllib.request.urlopen(url, timeout=TIMEOUT) as r, open(tmp, "wb") as f:
        f.write(r.read())
    tmp.replace(target)


def _url(man: dict, relpath: str) -> str | None:
    """Public URL of ``relpath``: ``base_url`` + its ``remote`` path; None when the
    manifest says the file is in the mirror only (``"remote_complete": false`` and
    no ``remote`` entry)."""
    remote = man.get("remote", {})
    if relpath in remote:
        return man["base_url"] + remote[relpath]
    if man.get("remote_complete", True):
        return man["base_url"] + relpath
    return None


def fetch(dataset: str, relpath: str, *, download: bool = True) -> Path:
    """Path of a verified local copy of ``relpath`` of ``dataset``.

    Parameters
    ----------
    dataset : str
        Manifest name (``manifests/<dataset>.json``, e.g. ``"homography"``); its
        ``mirror_dir`` key (default the same name) names the mirror folder.
    relpath : str
        A path listed in the manifest's ``files``.
    download : bool
        Try the public source when the file is neither mirrored nor cached.

    Raises
    ------
    FileNotFoundError
        Not available locally and not downloadable; the message lists the
        places looked at and the URL.
    ValueError
        ``relpath`` is not in the manifest, or a copy fails its sha256 check.
    """
    man = load_manifest(dataset)
    files = man["files"]
    if relpath not in files:
        raise ValueError(f"{dataset}: {relpath!r} is not in the manifest")
    want = files[relpath]
    name = man.get("mirror_dir", dataset)
    mirror = mirror_dir(name)
    places = ([] if mirror is None else [mirror / relpath]) + [cache_dir(name) / relpath]
    for p in places:
        if p.is_file():
            got = sha256(p)
            if got != want:
                raise ValueError(f"{p}: corrupt file (sha256 {got[:12]}..., expected "
                                 f"{want[:12]}...); delete it or restore it from "
                                 f"{_url(man, relpath) or man.get('source', man['base_url'])}")
            return p
    url = _url(man, relpath)
    if url is None:
        url = man.get("source", man["base_url"])
        reason = "no public download location is known for this file; get it from the source"
    elif download:
        try:
            _download(url, places[-1])
        except OSError as exc:
            reason = f"download failed ({exc})"
        else:
            return fetch(dataset, relpath, download=False)
    else:
        reason = "downloads disabled"
    where = (f"Put the file at {places[0]} (or set CLAP_UNIFIED_DATA to a folder holding "
             f"{name}/), or at {places[-1]}" if mirror is not None else
             f"Set CLAP_UNIFIED_DATA to a folder holding {name}/{relpath}, or put the file at "
             f"{places[-1]}")
    raise FileNotFoundError(f"{dataset}: {relpath} not found ({reason}). {where}; "
                            f"source: {url}")
