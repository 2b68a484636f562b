"""AdelaideRMF: the correspondences, scores and images are the input, the labels are truth.

Every sequence of the mirror is loaded and compared with the ``.mat`` read here
directly (no loader code); the labels never reach the input object; the
manifest pins every file's sha256 and a corrupt or malformed file is refused
with its name. The published numbers name their source.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json

import numpy as np
import pytest
from scipy.io import loadmat, savemat
from split_checks import assert_split

from clap_unified.imaging.datasets import (
    MultiModelInput,
    MultiModelPair,
    MultiModelTruth,
    adelaidermf_names,
    fetch,
    load_adelaidermf,
    published_results,
)
from clap_unified.imaging.datasets.adelaidermf import KINDS, read_adelaidermf_mat
from clap_unified.imaging.datasets.sources import manifest_file, mirror_dir
from clap_unified.imaging.segmentation_metrics import misclassification_error

MANIFEST = json.loads(manifest_file("adelaidermf").read_text())
ALL = [(kind, name) for kind in KINDS for name in MANIFEST[kind]]


def _mirror_available():
    try:
        fetch("adelaidermf", "H/bonython.mat", download=False)
        fetch("adelaidermf", "F/biscuit.mat", download=False)
    except (OSError, ValueError):
        return False
    return True


needs_mirror = pytest.mark.skipif(not _mirror_available(), reason="AdelaideRMF mirror not present")


def _present(kind, name):
    mirror = mirror_dir("adelaidermf")
    return mirror is not None and (mirror / KINDS[kind] / f"{name}.mat").is_file()


def test_the_manifest_lists_17_homography_and_19_fundamental_sequences():
    assert adelaidermf_names("homography") == MANIFEST["homography"]
    assert len(adelaidermf_names()) == 17 and len(adelaidermf_names("fundamental")) == 19
    assert not {"johnsona", "johnsonb"} & set(adelaidermf_names("homography"))
    assert sorted(MANIFEST["files"]) == sorted(f"{KINDS[k]}/{n}.mat" for k, n in ALL)
    assert sorted(MANIFEST["remote"]) == sorted(MANIFEST["files"])
    for rel, remote in MANIFEST["remote"].items():
        url = MANIFEST["base_url"] + remote
        assert url.startswith("https://raw.githubusercontent.com/") and url.endswith(
            rel.rsplit("/", 1)[1])
        # pinned to a full commit of the public repository
        assert len(remote.split("/")[2]) == 40
    assert "matthew-brett" in MANIFEST["remote"]["H/unionhouse.mat"]
    # the manifest holds names, sources and checksums: no labels
    assert "label" not in json.dumps(MANIFEST["files"])


@needs_mirror
@pytest.mark.parametrize("kind,name", ALL)
def test_every_sequence_loads_as_the_file_says(kind, name):
    if not _present(kind, name):
        pytest.skip(f"{kind} {name} not mirrored")
    path = fetch("adelaidermf", f"{KINDS[kind]}/{name}.mat", download=False)
    # the sha256 in the manifest is the file's
    assert hashlib.sha256(path.read_bytes()).hexdigest() == MANIFEST["files"][
        f"{KINDS[kind]}/{name}.mat"]
    raw = loadmat(path)
    pair = load_adelaidermf(name, kind)
    assert_split(pair)
    assert (pair.name, pair.kind) == (name, kind)
    n = raw["data"].shape[1]
    assert pair.input.matches.shape == (n, 4) and pair.input.matches.dtype == float
    np.testing.assert_array_equal(pair.input.matches, raw["data"][[0, 1, 3, 4]].T)
    np.testing.assert_array_equal(pair.input.score, raw["score"].ravel())
    np.testing.assert_array_equal(pair.input.image_a, raw["img1"])
    np.testing.assert_array_equal(pair.input.image_b, raw["img2"])
    assert pair.input.image_a.dtype == np.uint8 and pair.input.image_a.ndim in (2, 3)
    labels = raw["label"].ravel().astype(int)
    np.testing.assert_array_equal(pair.truth.labels, labels)
    assert pair.truth.n_structures == labels.max() >= 1
    # labels are 0..K with every structure present
    assert set(np.unique(labels)) == set(range(labels.max() + 1))
    assert pair.outlier_ratio == pytest.approx(np.mean(labels == 0))
    # the true labelling scores zero against itself, in the library's convention
    assert misclassification_error(labels - 1, labels) == 0.0


@needs_mirror
@pytest.mark.parametrize("kind,name", [("homography", "physics"), ("fundamental", "cube"),
                                       ("fundamental", "boardgame")])
def test_the_labels_never_reach_the_input(kind, name):
    pair = load_adelaidermf(name, kind)
    labels = pair.truth.labels
    # the input object holds exactly the allowed fields, none of them the labels
    assert [f.name for f in dataclasses.fields(pair.input)] == ["matches", "score", "image_a",
                                                                "image_b"]
    assert not hasattr(pair.input, "label") and not hasattr(pair.input, "labels")
    arrays = [pair.input.matches, pair.input.score, pair.input.image_a, pair.input.image_b]
    for a in arrays:
        assert not a.flags.writeable
        # no input array is the label vector, nor holds it as a row or column
        assert not (a.shape == labels.shape and np.array_equal(a, labels))
        if a.ndim >= 2 and a.shape[0] == len(labels):
            for j in range(a.shape[1]):
                assert not np.array_equal(a[:, j], labels)
        if a.ndim >= 2 and a.shape[1] == len(labels):
            for i in range(a.shape[0]):
                assert not np.array_equal(a[i], labels)
    # without images, nothing else arrives: the images are None, not decoded
    light = load_adelaidermf(name, kind, images=False)
    assert light.input.image_a is None and light.input.image_b is None
    np.testing.assert_array_equal(light.input.matches, pair.input.matches)


def test_unknown_kind_and_name_are_named():
    with pytest.raises(ValueError, match="kind: expected one of"):
        adelaidermf_names("H")
    with pytest.raises(ValueError, match="kind"):
        load_adelaidermf("bonython", "affine")
    with pytest.raises(ValueError, match="name: 'johnsona'"):
        load_adelaidermf("johnsona")
    # a fundamental sequence is not a homography one
    with pytest.raises(ValueError, match="name: 'biscuit'"):
        load_adelaidermf("biscuit", "homography")


def test_missing_files_say_where_to_put_them(tmp_path, monkeypatch):
    monkeypatch.setenv("CLAP_UNIFIED_DATA", str(tmp_path / "none"))
    monkeypatch.setenv("CLAP_UNIFIED_CACHE", str(tmp_path / "cache"))
    monkeypatch.setattr("clap_unified.imaging.datasets.sources._download",
                        lambda url, target: (_ for _ in ()).throw(OSError("offline")))
    with pytest.raises(FileNotFoundError, match=r"H/bonython.mat.*CLAP_UNIFIED_DATA"):
        load_adelaidermf("bonython")


def _write_mat(path, **arrays):
    savemat(path, arrays)
    return path


def _good(n=5):
    rng = np.random.default_rng(0)
    xy = rng.uniform(0, 100, (4, n))
    data = np.vstack([xy[:2], np.ones(n), xy[2:], np.ones(n)])
    img = np.zeros((4, 6, 3), np.uint8)
    return dict(data=data, score=np.arange(n)[None], label=np.array([[0, 1, 1, 2, 2]][:n]),
                img1=img, img2=img)


def test_a_corrupt_mirror_copy_is_refused_with_its_name(tmp_path, monkeypatch):
    """A file in the mirror (CLAP_UNIFIED_DATA) whose sha256 differs is refused."""
    bad = tmp_path / "adelaidermf" / "H"
    bad.mkdir(parents=True)
    _write_mat(bad / "bonython.mat", **_good())
    monkeypatch.setenv("CLAP_UNIFIED_DATA", str(tmp_path))
    with pytest.raises(ValueError, match=r"bonython.mat: corrupt file"):
        load_adelaidermf("bonython")
    (bad / "bonython.mat").write_bytes(b"not a mat file")
    with pytest.raises(ValueError, match=r"bonython.mat: corrupt file"):
        load_adelaidermf("bonython")


def test_a_malformed_mat_is_refused_with_its_name(tmp_path):
    good = read_adelaidermf_mat(_write_mat(tmp_path / "good.mat", **_good()))
    np.testing.assert_array_equal(good["labels"], [0, 1, 1, 2, 2])
    assert good["matches"].shape == (5, 4) and good["image_a"].dtype == np.uint8
    pair = MultiModelPair("good", "homography",
                          MultiModelInput(good["matches"], good["score"], good["image_a"],
                                          good["image_b"]),
                          MultiModelTruth(good["labels"]))
    assert_split(pair)
    assert pair.truth.n_structures == 2
    cases = {
        "notmat": None,
        "nolabel": {k: v for k, v in _good().items() if k != "label"},
        "data5": {**_good(), "data": _good()["data"][:5]},
        "homog": {**_good(), "data": _good()["data"] * 2},
        "nan": {**_good(), "data": np.where(np.eye(6, 5) > 0, np.nan, _good()["data"])},
        "score4": {**_good(), "score": np.arange(4)[None]},
        "label4": {**_good(), "label": np.array([[0, 1, 1, 2]])},
        "labelneg": {**_good(), "label": np.array([[0, 1, -1, 2, 2]])},
        "labelfrac": {**_good(), "label": np.array([[0, 1, 1.5, 2, 2]])},
        "imgfloat": {**_good(), "img1": np.zeros((4, 6, 3))},
        "img4": {**_good(), "img2": np.zeros((4, 6, 4), np.uint8)},
    }
    expected = {"notmat": "not a readable MATLAB file", "nolabel": r"missing \['label'\]",
                "data5": "6 x N", "homog": "homogeneous", "nan": "non-finite values in data",
                "score4": "score must hold 5", "label4": "label must hold 5",
                "labelneg": "labels must be 0", "labelfrac": "labels must be 0",
                "imgfloat": "img1 must be a uint8", "img4": "img2 must be a uint8"}
    for case, arrays in cases.items():
        path = tmp_path / f"{case}.mat"
        if arrays is None:
            path.write_bytes(b"MATLAB 5.0 MAT-file, but nothing after it")
        else:
            _write_mat(path, **arrays)
        with pytest.raises(ValueError, match=rf"{case}\.mat: .*{expected[case]}"):
            read_adelaidermf_mat(path)
    # without images, bad images do not matter
    assert read_adelaidermf_mat(tmp_path / "imgfloat.mat", images=False)["image_a"] is None


def test_the_split_is_frozen_and_checked():
    truth = MultiModelTruth(np.array([0, 1, 1]))
    pair = MultiModelPair("p", "homography", MultiModelInput(np.zeros((3, 4)), np.zeros(3)),
                          truth)
    assert_split(pair)
    with pytest.raises(ValueError):
        pair.input.matches[0, 0] = 1.0
    with pytest.raises(ValueError):
        pair.truth.labels[0] = 2
    with pytest.raises(dataclasses.FrozenInstanceError):
        pair.truth = truth
    with pytest.raises(ValueError, match="truth: 2 labels for 3 matches"):
        MultiModelPair("p", "homography", MultiModelInput(np.zeros((3, 4)), np.zeros(3)),
                       MultiModelTruth(np.array([0, 1])))
    with pytest.raises(ValueError, match="matches"):
        MultiModelInput(np.zeros((3, 6)), np.zeros(3))
    with pytest.raises(ValueError, match="score"):
        MultiModelInput(np.zeros((3, 4)), np.zeros(2))
    with pytest.raises(ValueError, match="labels"):
        MultiModelTruth(np.array([0.0, 1.0]))
    with pytest.raises(ValueError, match="labels"):
        MultiModelTruth(np.array([0, -1]))


def test_published_results_name_their_source():
    results = published_results()
    assert results and all(r["kind"] in KINDS for r in results)
    for r in results:
        assert {"method", "paper", "venue", "year", "kind", "n_sequences", "mean", "median",
                "models_given", "protocol", "source"} <= set(r), r
        assert r["source"].startswith("https://") and r["protocol"]
        assert r["mean"] is None or 0 <= r["mean"] < 100
        assert r["median"] is None or 0 <= r["median"] < 100
        assert isinstance(r["models_given"], bool) and 1 <= r["n_sequences"] <= 19
    # the Progressive-X figure of the authors' notebook (commit 61bcd27)
    px = [r for r in published_results("homography")
          if r["method"] == "Progressive-X" and "61bcd27" in r["source"]]
    assert len(px) == 1
    assert (px[0]["mean"], px[0]["median"], px[0]["seconds_per_sequence"]) == (6.6, 4.1, 0.11)
    assert all(r["kind"] == "fundamental" for r in published_results("fundamental"))
    with pytest.raises(ValueError, match="kind"):
        published_results("F")
    # what could not be checked in a primary source is named, with the reason, and has no numbers
    unverified = json.loads(manifest_file("adelaidermf_published").read_text())["unverified"]
    assert unverified and all(set(u) == {"method", "paper", "reason"} for u in unverified)
    assert {"CONSAC / CONSAC-S", "T-Linkage", "RPA", "J-Linkage", "PEARL", "Multi-X"} <= {
        u["method"] for u in unverified}
    # a copy: editing it leaves the packaged numbers alone
    results[0]["mean"] = -1
    assert published_results()[0]["mean"] != -1
