"""stitching_sets: real panorama sets; the photographs are the input, there is no truth."""

from __future__ import annotations

import json

import pytest
from split_checks import assert_split

from clap_unified.imaging.datasets import load_stitching_set, stitching_set_names
from clap_unified.imaging.datasets.sources import manifest_file, mirror_dir

_MIRROR = mirror_dir("stitching_sets")
pytestmark = pytest.mark.skipif(_MIRROR is None or not _MIRROR.is_dir(),
                                reason="stitching_sets mirror not present")


def test_every_set_is_its_images_in_order_and_has_no_truth():
    manifest = json.loads(manifest_file("stitching_sets").read_text())
    assert stitching_set_names() == sorted(manifest["sets"])
    assert len(manifest["files"]) == 32
    for name in stitching_set_names():
        s = load_stitching_set(name)
        assert_split(s)
        assert s.name == name
        images = [p.rsplit("/", 2)[-2:] for p in s.input.images]
        assert ["/".join(p) for p in images] == manifest["sets"][name]
        assert s.input.pairs == [(i, i + 1) for i in range(len(images) - 1)]
        assert not [f for f in vars(s.truth)]  # no ground truth: nothing to leak


def test_bad_name_and_missing_files_are_named(tmp_path, monkeypatch):
    with pytest.raises(ValueError, match="name: 'nope'"):
        load_stitching_set("nope")
    monkeypatch.setenv("CLAP_UNIFIED_DATA", str(tmp_path / "none"))
    monkeypatch.setenv("CLAP_UNIFIED_CACHE", str(tmp_path / "cache"))
    # boat has no known public location: no download is tried, the message says so
    with pytest.raises(FileNotFoundError, match="no public download location"):
        load_stitching_set("boat")


def test_a_corrupt_copy_is_refused(tmp_path, monkeypatch):
    src = mirror_dir("stitching_sets") / "hill"
    dst = tmp_path / "stitching_sets" / "hill"
    dst.mkdir(parents=True)
    for f in src.iterdir():
        (dst / f.name).write_bytes(f.read_bytes())
    (dst / "hill02.JPG").write_bytes(b"not a jpeg")
    monkeypatch.setenv("CLAP_UNIFIED_DATA", str(tmp_path))
    with pytest.raises(ValueError, match="corrupt file"):
        load_stitching_set("hill")
