"""``clap-unified segment {line,circle,homography}``: every model in one CSV file."""

import json
import tempfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from test_cli_fuzz import FEW, FUZZ, check_clean, csv_texts, write
from test_cli_fuzz import run as fuzz_run

from clap_unified.cli import main
from clap_unified.imaging.segment_matches import SEGMENT_DEFAULTS
from clap_unified.registry import segmenter_names
from clap_unified.segment_cli import KINDS, MAX_T_LINKAGE_ROWS
from clap_unified.spaces import LineSpace
from clap_unified.spaces.homography import HomographySpace


def run(args, capsys):
    code = main([str(a) for a in args])
    out, err = capsys.readouterr()
    return code, out, err


def _csv(path, rows, header=None):
    np.savetxt(path, rows, delimiter=",", header=header or "", comments="")
    return path


@pytest.fixture(scope="module")
def lines_csv(tmp_path_factory):
    """Two lines (120 and 100 points) and 80 points of clutter."""
    rng = np.random.default_rng(0)
    x = rng.uniform(-5, 5, 300)
    pts = np.c_[x, np.where(np.arange(300) < 120, 0.5 * x + 1, -x)]
    pts += rng.normal(0, 0.02, pts.shape)
    pts[220:] = rng.uniform(-5, 5, (80, 2))
    return _csv(tmp_path_factory.mktemp("seg") / "lines.csv", pts, header="x,y")


@pytest.fixture(scope="module")
def noise_csv(tmp_path_factory):
    """40 points of noise: no 10 of them on one line or circle."""
    pts = np.random.default_rng(0).uniform(-5, 5, (40, 2))
    return _csv(tmp_path_factory.mktemp("seg") / "noise.csv", pts)


@pytest.fixture(scope="module")
def planes_csv(tmp_path_factory):
    """Matches of two planes (a shift and a zoom, 100 each) and 40 random matches."""
    rng = np.random.default_rng(1)
    src = rng.uniform(0, 640, (240, 2))
    dst = np.where(np.arange(240)[:, None] < 100, src + [20.0, -5.0], 1.1 * src)
    dst = dst + rng.normal(0, 0.3, dst.shape)
    dst[200:] = rng.uniform(0, 640, (40, 2))
    return _csv(tmp_path_factory.mktemp("seg") / "matches.csv", np.c_[src, dst])


def _line_hits(model, slope, intercept):
    """Whether ``{"normal", "offset"}`` is the line y = slope x + intercept."""
    a, b = model["normal"]
    c = model["offset"]
    n = np.array([-slope, 1.0]) / np.hypot(slope, 1.0)
    offset = abs(intercept) / np.hypot(slope, 1)
    return abs(abs(n @ [a, b]) - 1) < 1e-3 and abs(abs(c) - offset) < 0.05


@pytest.mark.parametrize("method", ["clap", "ransac", "t_linkage"])
def test_two_lines_and_clutter(lines_csv, capsys, method):
    code, out, err = run(["segment", "line", lines_csv, "--method", method], capsys)
    assert code == 0 and err == ""
    d = json.loads(out)
    assert d["success"] is True and d["method"] == method and d["reason"] == "ok"
    assert len(d["models"]) == 2 and d["data"] == 300 and len(d["labels"]) == 300
    assert set(d["labels"]) <= {-1, 0, 1}
    assert sorted(m["support"] for m in d["models"]) == pytest.approx([100, 120], abs=5)
    assert [d["labels"].count(k) for k in (0, 1)] == [m["support"] for m in d["models"]]
    models = [m["model"] for m in d["models"]]
    assert any(_line_hits(m, 0.5, 1.0) for m in models)
    assert any(_line_hits(m, -1.0, 0.0) for m in models)
    assert d["threshold"] == pytest.approx(
        LineSpace().default_threshold(np.loadtxt(lines_csv, delimiter=",", skiprows=1)))
    assert set(d) == {"method", "success", "reason", "models", "labels", "selection", "data",
                      "threshold", "seconds"}


def test_two_circles(tmp_path, capsys):
    rng = np.random.default_rng(2)
    t = rng.uniform(0, 2 * np.pi, 200)
    pts = np.where(np.arange(200)[:, None] < 120, np.c_[3 * np.cos(t), 3 * np.sin(t)],
                   np.c_[6 + 2 * np.cos(t), 1 + 2 * np.sin(t)]) + rng.normal(0, 0.01, (200, 2))
    f = _csv(tmp_path / "c.csv", pts)
    code, out, _ = run(["segment", "circle", f, "--threshold", "0.05"], capsys)
    d = json.loads(out)
    assert code == 0 and len(d["models"]) == 2 and d["threshold"] == 0.05
    radii = sorted(m["model"]["radius"] for m in d["models"])
    assert radii == pytest.approx([2.0, 3.0], abs=0.02)


@pytest.mark.parametrize("kind", ["line", "circle"])
def test_pure_noise_exits_1_with_no_model(noise_csv, capsys, kind):
    code, out, err = run(["segment", kind, noise_csv], capsys)
    assert code == 1 and err == ""
    d = json.loads(out)
    assert d["success"] is False and d["models"] == [] and d["reason"] != "ok"
    assert d["labels"] == [-1] * 40 and d["data"] == 40


def test_min_support_above_every_structure_exits_1(lines_csv, capsys):
    code, out, _ = run(["segment", "line", lines_csv, "--min-support", "150"], capsys)
    d = json.loads(out)
    assert code == 1 and d["models"] == [] and set(d["labels"]) == {-1}


def test_fewer_rows_than_a_sample_is_a_failed_estimate(tmp_path, capsys):
    """As ``fit``: too few data for one model is exit 1 with a reason, not bad input."""
    f = _csv(tmp_path / "two.csv", [[0.0, 0.0], [1.0, 1.0]])
    code, out, err = run(["segment", "circle", f], capsys)
    d = json.loads(out)
    assert code == 1 and err == ""
    assert d["reason"] == "need at least 3 rows for one circle, got 2"
    assert d["labels"] == [-1, -1] and d["models"] == []


@pytest.mark.parametrize("content, argv, needle", [
    (None, [], "no such file"),
    ("", [], "no data"),
    ("x,y\n", [], "no data"),
    ("1,2,3\n4,5,6\n", [], "line 1: expected 2 values, got 3"),
    ("1,2\nnan,3\n", [], "line 2: non-finite value"),
    ("1,2\n3,abc\n", [], "line 2: non-numeric"),
    ("1,2\n3,4\n", ["--threshold", "0"], "argument --threshold: expected a finite number above"),
    ("1,2\n3,4\n", ["--threshold", "-1"], "argument --threshold"),
    ("1,2\n3,4\n", ["--method", "magic"], "argument --method: invalid choice: 'magic'"),
    ("1,2\n3,4\n", ["--min-support", "1"], "--min-support: expected at least 2"),
    ("1,2\n3,4\n", ["--hypotheses", "0"], "argument --hypotheses"),
    ("1,2\n3,4\n", ["--seed", "-1"], "argument --seed"),
    ("1,2\n3,4\n", ["--coherence", "-0.1"], "argument --coherence: expected a finite number"),
    ("1,2\n3,4\n", ["--coherence", "nan"], "argument --coherence"),
])
def test_bad_input_exits_2_with_one_line(tmp_path, capsys, content, argv, needle):
    f = tmp_path / "bad.csv"
    if content is not None:
        f.write_text(content)
    code, out, err = run(["segment", "line", f, *argv], capsys)
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and needle in err, err
    assert err.startswith("clap-unified segment line: error: ")
    if content is not None and not argv:
        assert str(f) in err  # the file is named


def test_unknown_method_lists_the_kinds_segmenters(tmp_path, capsys):
    f = _csv(tmp_path / "m.csv", np.zeros((10, 4)))
    code, _, err = run(["segment", "homography", f, "--method", "magic"], capsys)
    assert code == 2
    for name in segmenter_names(HomographySpace()):
        assert repr(name) in err
    code, _, err = run(["segment", "line", f, "--method", "magsac"], capsys)  # homography only
    assert code == 2 and "invalid choice: 'magsac'" in err


def test_homography_wants_four_columns(lines_csv, capsys):
    code, out, err = run(["segment", "homography", lines_csv], capsys)
    assert code == 2 and out == "" and "expected 4 values, got 2" in err and str(lines_csv) in err


def test_sizes_beyond_the_limits_are_refused(tmp_path, capsys):
    pts = np.random.default_rng(0).normal(size=(MAX_T_LINKAGE_ROWS + 1, 2))
    f = _csv(tmp_path / "big.csv", pts)
    code, out, err = run(["segment", "line", f, "--method", "t_linkage"], capsys)
    assert code == 2 and out == "" and "--method: t_linkage" in err
    code, out, err = run(["segment", "line", f, "--hypotheses", "1000000"], capsys)
    assert code == 2 and out == "" and "--hypotheses" in err


def test_same_seed_same_output(lines_csv, capsys):
    outs = []
    for _ in range(2):
        code, out, _ = run(["segment", "line", lines_csv, "--seed", "7"], capsys)
        assert code == 0
        d = json.loads(out)
        d.pop("seconds")
        outs.append(json.dumps(d))
    assert outs[0] == outs[1]


def test_homography_two_planes(planes_csv, capsys):
    code, out, err = run(["segment", "homography", planes_csv], capsys)
    assert code == 0 and err == ""
    d = json.loads(out)
    assert len(d["models"]) == 2 and d["data"] == 240 and len(d["labels"]) == 240
    assert d["threshold"] == SEGMENT_DEFAULTS["homography"]["threshold"]
    labels = np.array(d["labels"])
    # each plane is one model: the first 100 matches share a label, the next 100 another
    a, b = np.bincount(labels[:100] + 1).argmax() - 1, np.bincount(labels[100:200] + 1).argmax() - 1
    assert a >= 0 and b >= 0 and a != b
    assert np.mean(labels[:100] == a) > 0.95 and np.mean(labels[100:200] == b) > 0.95
    H = np.array(d["models"][a]["model"]["H"])
    assert H.shape == (3, 3) and H[:2, 2] == pytest.approx([20.0, -5.0], abs=1.0)


@pytest.mark.parametrize("method", ["ransac", "t_linkage"])
def test_homography_other_methods(planes_csv, capsys, method):
    code, out, _ = run(["segment", "homography", planes_csv, "--method", method,
                        "--hypotheses", "500", "--min-support", "20"], capsys)
    d = json.loads(out)
    assert code == 0 and d["method"] == method and len(d["models"]) >= 2
    labels = np.array(d["labels"])
    # no model mixes the planes (T-Linkage on local samples may split one in two)
    first, second = set(labels[:100]) - {-1}, set(labels[100:200]) - {-1}
    assert first and second and not first & second
    if method == "ransac":
        assert len(d["models"]) == 2


def test_homography_matches_the_library(planes_csv, capsys):
    """The command is segment_matches with its defaults: the same labels."""
    from clap_unified.imaging.segment_matches import segment_matches

    code, out, _ = run(["segment", "homography", planes_csv, "--seed", "3"], capsys)
    res = segment_matches(np.loadtxt(planes_csv, delimiter=","), rng=3)
    assert code == 0 and json.loads(out)["labels"] == res.labels.tolist()


def test_coherence_option_is_the_library_s(planes_csv, lines_csv, capsys):
    """--coherence W is segment's coherence: 0 gives the nearest-model finish, the default
    for matches is SEGMENT_DEFAULTS', for points 0."""
    from clap_unified import segment
    from clap_unified.imaging.segment_matches import segment_matches

    data = np.loadtxt(planes_csv, delimiter=",")
    for argv, w in [([], SEGMENT_DEFAULTS["homography"]["coherence"]), (["--coherence", "0"], 0.0),
                    (["--coherence", "0.02"], 0.02)]:
        code, out, _ = run(["segment", "homography", planes_csv, "--seed", "2", *argv], capsys)
        res = segment_matches(data, rng=2, coherence=w)
        assert code == 0 and json.loads(out)["labels"] == res.labels.tolist()
        assert res.diagnostics["coherence"] == w
    pts = np.loadtxt(lines_csv, delimiter=",", skiprows=1)
    code, out, _ = run(["segment", "line", lines_csv, "--coherence", "0.2"], capsys)
    res = segment(LineSpace.for_data(pts, metric="transfer"), pts, "clap", rng=0, coherence=0.2)
    assert code == 0 and json.loads(out)["labels"] == res.labels.tolist()


def test_help_lists_kinds_and_exit_statuses(capsys):
    code, top, _ = run(["segment", "--help"], capsys)
    assert code == 0 and "{line,circle,homography,fundamental}" in top and "exit status:" in top
    for kind in KINDS:
        assert f"find every {kind} in" in top
        code, out, _ = run(["segment", kind, "--help"], capsys)
        assert code == 0 and "exit status:" in out and "2    bad input" in out
        assert "labels" in out and "--min-support" in out and "--hypotheses" in out
        assert "inliers, data," not in out  # not fit's output form
    code, out, _ = run(["segment", "homography", "--help"], capsys)
    assert "default 5" in out and "magsac" in out


# --- fuzzing: any CSV ends with 0, 1 or 2 and nothing else (the convention of test_cli_fuzz) ---

@FUZZ
@given(text=csv_texts(2), kind=st.sampled_from(["line", "circle"]),
       method=st.sampled_from(["clap", "ransac", "randomized_hough", "t_linkage"]))
def test_segment_points_any_csv(text, kind, method):
    with tempfile.TemporaryDirectory() as d:
        f = write(Path(d), "p.csv", text)
        out = check_clean(*fuzz_run(["segment", kind, f, "--method", method,
                                     "--hypotheses", "200"]))
        if out is not None:
            assert len(out["labels"]) == out["data"]
            assert (out["models"] == []) is (out["success"] is False)


@FEW
@given(text=csv_texts(4), method=st.sampled_from(["clap", "ransac", "t_linkage"]))
def test_segment_homography_any_csv(text, method):
    with tempfile.TemporaryDirectory() as d:
        f = write(Path(d), "m.csv", text)
        out = check_clean(*fuzz_run(["segment", "homography", f, "--method", method,
                                     "--hypotheses", "200"]))
        if out is not None:
            assert len(out["labels"]) == out["data"]


@pytest.mark.parametrize("kind", ["line", "circle"])
def test_huge_coordinates_without_overflow(tmp_path, kind):
    """Coordinates up to 1e150 are read; the circumcircle's cubes of them must not overflow
    (a warning would be an error here)."""
    rows = "".join(f"{x},{y}\n" for x, y in [(1e150, 0)] + [(0, 0)] * 8 + [(0, 1e150)] * 2)
    f = write(tmp_path, "huge.csv", rows)
    check_clean(*fuzz_run(["segment", kind, f, "--method", "clap"]))


def test_two_rigid_motions_give_two_fundamental_matrices(tmp_path, capsys):
    """Two objects moving differently between the views: two fundamental matrices."""
    from clap_unified.imaging.datasets import synthetic_two_view

    pair = synthetic_two_view(280, outliers=40 / 280, noise=0.3, motions=2, rng=3)
    data, truth = pair.input.matches, pair.truth.labels
    path = tmp_path / "motions.csv"
    np.savetxt(path, data, delimiter=",")
    code, out, _ = run(["segment", "fundamental", str(path), "--seed", "0"], capsys)
    d = json.loads(out)
    assert code == 0 and len(d["models"]) == 2, d["reason"]
    labels = np.array(d["labels"])
    for k in (1, 2):
        own = labels[truth == k]
        assert np.bincount(own[own >= 0]).max() > 100  # one motion (120 matches), one label
