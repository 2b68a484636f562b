"""Every image loader keeps the estimator's input apart from the evaluation data.

homogr: the input is exactly the label 0 rows of ``<name>_pts.txt`` (the tentative
matches) and none of the 8 label 1 rows (validation points); EVD: every row is input,
the labels are kept as ``truth.inliers``; VPG and the synthetic VPG-layout sets: the
ground-truth correspondences and cameras are truth, the images are the input, and the
SIFT matches made from the images contain no ground-truth row.
"""

import dataclasses
from pathlib import Path

import numpy as np
import pytest
from split_checks import assert_rows_disjoint, assert_split

from clap_unified.imaging.datasets import (
    HomographyInput,
    HomographyPair,
    HomographyTruth,
    evd_names,
    fetch,
    homogr_names,
    load_evd,
    load_homogr,
    load_synthetic_vpg,
    load_vpg_set,
)
from clap_unified.imaging.datasets.homography_benchmarks import read_homogr_rows
from clap_unified.imaging.evaluation import evaluate_pair, vpg_pair_matches
from clap_unified.imaging.metrics import symmetric_reprojection_error


def _mirror_available():
    try:
        fetch("homography", "city_pts.txt", download=False)
        fetch("homography", "extremeview/graf_pts.txt", download=False)
    except (OSError, ValueError):
        return False
    return True


needs_mirror = pytest.mark.skipif(not _mirror_available(), reason="homogr/EVD mirror not present")


def _raw_rows(path):
    """Every row of a points file, straight from the text (no loader code)."""
    return [line.split() for line in Path(path).read_text().splitlines() if line.strip()]


@needs_mirror
@pytest.mark.parametrize("name", homogr_names() if _mirror_available() else [])
def test_homogr_input_is_exactly_the_label_0_rows(name):
    pair = load_homogr(name, images=False)
    assert_split(pair)
    raw = _raw_rows(fetch("homography", f"{name}_pts.txt"))
    rows = np.array([[float(r[0]), float(r[1]), float(r[3]), float(r[4])] for r in raw])
    label = np.array([int(float(r[6])) for r in raw])
    # counts against the file: 8 validation points per pair, the rest tentative matches
    assert (label == 1).sum() == 8
    assert pair.input.matches.shape == ((label == 0).sum(), 4)
    assert pair.truth.validation.shape == (8, 4)
    np.testing.assert_array_equal(pair.input.matches, rows[label == 0])
    np.testing.assert_array_equal(pair.truth.validation, rows[label == 1])
    assert_rows_disjoint(pair.input.matches, pair.truth.validation)
    assert pair.input.quality is None and pair.truth.inliers.shape == (len(rows) - 8,)
    # the validation points are exact under the ground truth
    assert np.median(symmetric_reprojection_error(pair.truth.H, pair.truth.validation)) < 3.0


@needs_mirror
@pytest.mark.parametrize("name", evd_names() if _mirror_available() else [])
def test_evd_input_is_every_row_and_labels_are_truth(name):
    pair = load_evd(name, images=False)
    assert_split(pair)
    raw = _raw_rows(fetch("homography", f"extremeview/{name}_pts.txt"))
    rows = np.array([[float(v) for v in r[:4]] for r in raw])
    np.testing.assert_array_equal(pair.input.matches, rows)
    np.testing.assert_array_equal(pair.input.quality, [float(r[4]) for r in raw])
    np.testing.assert_array_equal(pair.truth.inliers, [r[8] == "1" for r in raw])
    assert pair.truth.validation.shape == (0, 4)
    assert_rows_disjoint(pair.input.matches, pair.truth.validation)
    assert 0.01 < pair.inlier_ratio < 0.6
    sre = symmetric_reprojection_error(pair.truth.H, rows[pair.truth.inliers])
    assert np.median(sre) < 3.0


def test_homogr_rows_are_split_by_label(tmp_path):
    f = tmp_path / "x_pts.txt"
    f.write_text("1 2 1 3 4 1 0\n5 6 1 7 8 1 1\n9 10 1 11 12 1 0\n")
    matches, validation = read_homogr_rows(f)
    np.testing.assert_array_equal(matches, [[1, 2, 3, 4], [9, 10, 11, 12]])
    np.testing.assert_array_equal(validation, [[5, 6, 7, 8]])
    f.write_text("1 2 1 3 4 1 2\n")
    with pytest.raises(ValueError, match="labels"):
        read_homogr_rows(f)
    f.write_text("1 2 1 3 4\n")
    with pytest.raises(ValueError, match="label"):
        read_homogr_rows(f)


def test_split_is_frozen_and_checked():
    pair = HomographyPair("p", "test", HomographyInput(np.zeros((5, 4))),
                          HomographyTruth(np.eye(3), np.ones(5, bool), np.zeros((0, 4))))
    assert_split(pair)
    with pytest.raises(ValueError):
        pair.input.matches[0, 0] = 1.0
    with pytest.raises(dataclasses.FrozenInstanceError):
        pair.input.matches = np.ones((5, 4))
    with pytest.raises(ValueError, match="truth"):
        HomographyPair("p", "test", HomographyInput(np.zeros((5, 4))),
                       HomographyTruth(np.eye(3), np.ones(4, bool), np.zeros((0, 4))))
    with pytest.raises(ValueError, match="pair"):
        evaluate_pair(np.zeros((5, 4)))


def test_the_split_check_can_fail():
    """assert_rows_disjoint catches an evaluation row hidden among the input."""
    m = np.arange(40.0).reshape(10, 4)
    with pytest.raises(AssertionError):
        assert_rows_disjoint(m, m[3:4])


@pytest.fixture(scope="module")
def synthetic_sets(tmp_path_factory):
    root = tmp_path_factory.mktemp("vpg")
    return load_synthetic_vpg(root, scenes=["astronaut", "brick"], images_per_set=3, rng=0)


def test_synthetic_vpg_truth_is_not_input(synthetic_sets):
    for s in synthetic_sets:
        assert_split(s)
        for part in (s.input, s.truth):
            for value in vars(part).values():
                for v in dict(value).values():
                    for a in (v if isinstance(v, tuple) else (v,)):
                        if isinstance(a, np.ndarray):
                            assert not a.flags.writeable
        assert sorted(s.input.images) == [1, 2, 3] and s.pairs() == [(1, 2), (2, 3)]
        assert sorted(s.truth.correspondences) == [(1, 2), (2, 3)]
        assert sorted(s.truth.cameras) == [1, 2, 3]
        # the input holds image paths and the graph only: no array of coordinates
        assert not any(isinstance(v, np.ndarray) for v in s.input.images.values())
        assert set(s.input.graph) == {"center", "count", "edges", "entries"}
        with pytest.raises(TypeError):
            s.truth.correspondences[(3, 4)] = np.zeros((4, 4))
        # the correspondences are the exact ground truth, 120 per pair as written
        for (i, j), m in s.truth.correspondences.items():
            assert m.shape == (120, 4)
            assert np.max(symmetric_reprojection_error(s.truth.H(i, j), m)) < 1e-3


def test_synthetic_vpg_matches_come_from_the_images(synthetic_sets):
    for s in synthetic_sets:
        for pm in vpg_pair_matches(s):
            assert_split(pm)
            gt = s.truth.correspondences[pm.pair]
            np.testing.assert_array_equal(pm.truth.validation, gt)
            assert_rows_disjoint(pm.input.matches, pm.truth.validation, atol=1e-6)
            assert len(pm.input.matches) > 30
            assert pm.truth.inliers.shape == (len(pm.input.matches),)
            assert pm.input.image_a.endswith(f"{pm.pair[0]:02d}.jpg")


def test_vpg_reader_splits_a_real_layout(tmp_path):
    d = tmp_path / "S03"
    d.mkdir()
    (d / "S03-STITCH-GRAPH.txt").write_text(
        "{center_image_index | 0 | center image index}\n{images_count | 2 | images count}\n"
        "{matching_graph_image_edges-0 | 1 | matching graph image edge 0}\n")
    m = np.array([[0, 0, 10, 0], [100, 0, 110, 0], [0, 100, 10, 100], [100, 100, 110, 100],
                  [50, 50, 60, 50]], float)
    (d / "m01-02.txt").write_text("\n".join(",".join(map(str, r)) for r in m))
    (d / "camera-01.txt").write_text("1,0,0\n0,1,0\n0,0,1\n0,0,0\n")
    (d / "01.jpg").write_bytes(b"")
    s = load_vpg_set(d)
    assert_split(s)
    assert list(s.input.images) == [1] and s.input.graph["edges"] == ((1, 2),)
    np.testing.assert_array_equal(s.truth.correspondences[(1, 2)], m)
    np.testing.assert_allclose(s.truth.H(1, 2), [[1, 0, 10], [0, 1, 0], [0, 0, 1]], atol=1e-9)
    assert not s.truth.correspondences[(1, 2)].flags.writeable
    with pytest.raises(ValueError, match="m02-03"):
        s.truth.H(2, 3)


_CHAPTER_SNIPPET = """
from clap_unified.imaging.datasets import load_evd
from clap_unified.imaging.evaluation import evaluate_trials
for name in ("fox", "dum"):
    pair = load_evd(name, images=False)
    for r in evaluate_trials(pair, 3, methods={"CLAP": ("clap", False),
                                               "CLAP ordered": ("clap", True)}):
        print(name, r["trial"], r["method"], f"{r['recall']:.2f}", f"{r['lie']:.3g}")
"""


@needs_mirror
def test_chapter_results_do_not_depend_on_the_openblas_thread_count():
    """Chapter 5's (05_homographies) EVD experiment prints the same with one and with two
    OpenBLAS threads."""
    import os
    import subprocess
    import sys

    outs = []
    for threads in ("1", "2"):
        env = dict(os.environ, OPENBLAS_NUM_THREADS=threads)
        run = subprocess.run([sys.executable, "-c", _CHAPTER_SNIPPET], env=env, text=True,
                             capture_output=True, timeout=300, check=True)
        outs.append(run.stdout)
    assert outs[0].count("\n") == 2 * 3 * 2 and outs[0] == outs[1], outs
