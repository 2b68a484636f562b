"""Defects a review of the command line found, kept as regression tests."""

import subprocess
import sys

import cv2
import numpy as np
import pytest

from clap_unified.cli import EXIT_PIPE, EXIT_WRITE, main
from clap_unified.fitting import fit_line
from clap_unified.imaging.estimate import estimate_homography, method_names
from clap_unified.imaging.stitching import stitch
from clap_unified.spaces.homography import transfer


def _line_csv(path, n=60, bom=False):
    x = np.linspace(0, 10, n)
    text = "\n".join(f"{a:.6f},{2 * a + 1:.6f}" for a in x) + "\n"
    path.write_text(("\ufeff" if bom else "") + text, encoding="utf-8")
    return path


def test_a_byte_order_mark_does_not_eat_the_first_row(tmp_path, capsys):
    # Excel's "CSV UTF-8" starts with a BOM: the first row was taken for a header
    assert main(["fit", "line", str(_line_csv(tmp_path / "bom.csv", bom=True)), "-q"]) == 0
    out = capsys.readouterr().out
    assert '"data": 60' in out


@pytest.mark.parametrize("scale", [1e-300, 1e-200, 1e-100, 1e-20, 1e-5])
@pytest.mark.parametrize("method", ["clap", "ransac", "randomized_hough"])
def test_tiny_coordinates_are_fitted(scale, method):
    # at 1e-300 a ValueError named an internal length_scale; then every minimal sample was
    # "degenerate" below 1e-12 (an absolute tolerance), and the refit's covariance underflowed
    x = np.arange(1.0, 11.0)
    res = fit_line(np.c_[x, 2 * x + 1] * scale, method, rng=0)
    assert res.success, res.reason
    model = res.to_dict()["model"]
    (a, b), c = model["normal"], model["offset"]
    assert -a / b == pytest.approx(2, rel=1e-9) and c / b / scale == pytest.approx(1, rel=1e-9)
    assert res.n_inliers == 10


def test_a_closed_pipe_and_a_full_disk_are_no_traceback(tmp_path):
    csv = _line_csv(tmp_path / "p.csv")
    cmd = [sys.executable, "-m", "clap_unified", "fit", "line", str(csv), "-q"]
    with open("/dev/full", "w") as full:
        run = subprocess.run(cmd, stdout=full, stderr=subprocess.PIPE, text=True, timeout=120)
    assert run.returncode == EXIT_WRITE, run.stderr
    assert "Traceback" not in run.stderr and run.stderr.count("\n") == 1
    with subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                          text=True) as proc:
        proc.stdout.close()  # the reader goes away before the result is written
        err = proc.stderr.read()
        status = proc.wait(timeout=120)
    assert status == EXIT_PIPE, err
    assert "Traceback" not in err


def test_feathering_an_image_inside_the_other_is_not_garbage():
    g = np.random.default_rng(0)
    left = cv2.resize(g.uniform(0, 255, (30, 40)).astype(np.uint8), (200, 150))
    left = cv2.merge([left, left, left])
    right = left[30:90, 40:140]
    H = np.array([[1.0, 0, -40], [0, 1.0, -30], [0, 0, 1]])  # left to right: right is inside
    with np.errstate(all="raise"):  # the blend overflowed to NaN
        pano = stitch(left, right, H, blend="feather")
    assert pano.shape[:2] == left.shape[:2]
    assert np.abs(pano.astype(float)[: left.shape[0], : left.shape[1]] - left).mean() < 3


def _homography_matches(n=200, seed=0):
    """Matches (pixels, 0..640) of a known homography: noise 0.5 px, 30 % outliers."""
    g = np.random.default_rng(seed)
    H = np.array([[1.1, 0.05, 20.0], [-0.03, 0.95, 10.0], [1e-4, 5e-5, 1.0]])
    src = g.uniform(0, 640, (n, 2))
    dst = transfer(H, src) + g.normal(0, 0.5, (n, 2))
    out = g.random(n) < 0.3
    dst[out] = g.uniform(0, 640, (out.sum(), 2))
    return np.c_[src, dst]


@pytest.mark.parametrize("scale", [1e-4, 1e4, 1e6])
@pytest.mark.parametrize("method", method_names())
def test_homography_in_any_unit(scale, method):
    # x 1e4: clap_paper and randomized_hough raised "T1: singular matrix" (the Hartley frame
    # of points far from the origin failed a determinant test meant for homographies); x 1e6:
    # every minimal sample was "degenerate" (the same test on the pixel hypotheses). The
    # methods that compare hypotheses in the data's frame must work; the others (ransac
    # tests its hypotheses in pixels, other libraries) may fail, with a reason, not raise
    data = _homography_matches()
    res = estimate_homography(data * scale, method, rng=0, threshold=3 * scale)
    assert res.success or res.reason
    if method in ("clap", "clap_paper", "randomized_hough"):
        assert res.success, res.reason
    if res.success and method in ("clap", "clap_paper", "randomized_hough", "ransac"):
        err = transfer(res.model, data[:, :2] * scale) / scale - data[:, 2:]
        assert np.median(np.linalg.norm(err, axis=1)) < 1.5 and res.n_inliers >= 140


@pytest.mark.parametrize("method", ["clap_paper", "randomized_hough"])
def test_fit_homography_in_a_large_unit_is_no_bad_input(tmp_path, capsys, method):
    csv = tmp_path / "m.csv"
    np.savetxt(csv, _homography_matches() * 1e4, delimiter=",")
    status = main(["fit", "homography", str(csv), "--method", method, "--threshold", "3e4", "-q"])
    assert status == 0, capsys.readouterr().err


def test_reproduce_prints_no_progress_when_stderr_is_no_terminal(tmp_path):
    # "reproduce: N experiment(s) to run ..." and "reproduce: finished in ..." went to a
    # captured stderr; the summary is the JSON on stdout
    cmd = [sys.executable, "-m", "clap_unified", "reproduce", "--quick", "--only",
           "homography_homogr", "--out", str(tmp_path / "r")]
    run = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    assert run.stderr == ""
    assert '"ran": ["homography_homogr"]' in run.stdout


@pytest.mark.parametrize("value", [",", "", "homography_homogr,,homography_evd", " , "])
def test_reproduce_only_with_an_empty_name_is_bad_input(tmp_path, capsys, value):
    # an empty selection ran nothing (or, for "", everything) with exit 0
    status = main(["reproduce", "--quick", "--only", value, "--out", str(tmp_path / "r")])
    err = capsys.readouterr().err
    assert status == 2 and err.count("\n") == 1 and "--only" in err, err
    assert not (tmp_path / "r").exists()


def _run(argv, capsys):
    status = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return status, out, err


def _bad_input(argv, capsys):
    """The one line on stderr of a command that must exit 2 (nothing on stdout)."""
    status, out, err = _run(argv, capsys)
    assert status == 2 and out == "" and err.count("\n") == 1, (status, out, err)
    return err


def _obs2d(path, extra=()):
    """Every landmark within 6 m of a robot at (-1.2, 3.4, 0.1), in its frame, plus ``extra``."""
    import json
    import math

    from clap_unified.localization import load_field

    field, (x, y, theta) = load_field("adult"), (-1.2, 3.4, 0.1)
    c, s = math.cos(theta), math.sin(theta)
    obs = [{"type": str(t), "x": c * (px - x) + s * (py - y), "y": -s * (px - x) + c * (py - y)}
           for t, (px, py) in zip(field.types, field.positions, strict=True)
           if math.hypot(px - x, py - y) < 6]
    path.write_text(json.dumps(obs + list(extra)))
    return path


def test_an_unknown_option_names_the_command(tmp_path, capsys):
    csv = _line_csv(tmp_path / "p.csv")
    err = _bad_input(["fit", "line", csv, "--bogus"], capsys)
    assert err == "clap-unified fit line: error: unrecognized arguments: --bogus\n"
    err = _bad_input(["reproduce", "--only", "homography_homogr", "-x", "1"], capsys)
    assert err == "clap-unified reproduce: error: unrecognized arguments: -x 1\n"


def test_an_empty_path_is_said_to_be_empty(capsys):
    err = _bad_input(["fit", "line", ""], capsys)
    assert "empty path" in err and "folder" not in err


def test_json_entries_are_named_one_way_and_missing_keys_as_missing(tmp_path, capsys):
    f = tmp_path / "o.json"
    f.write_text('[{"type": "zz", "x": 1, "y": 2}]')
    assert ": entry 0: unknown type 'zz'" in _bad_input(["localize2d", f], capsys)
    f.write_text('[{"type": "L", "x": 1}]')
    err = _bad_input(["localize2d", f], capsys)
    assert ': entry 0: missing "y"' in err and "None" not in err
    world = tmp_path / "map.json"
    world.write_text('[{"type": "tree", "x": 0, "y": 0, "z": 0}, {"type": "post", "x": 1, '
                     '"y": 0, "z": 0}, {"type": "post", "x": 0, "y": 1, "z": 0}]')
    f.write_text('[{"type": "rock", "x": 1, "y": 2, "z": 0}]')
    err = _bad_input(["localize3d", f, "--map", world], capsys)
    assert ": entry 0: unknown type 'rock'; expected one of ['post', 'tree']" in err, err
    assert "np.str_" not in err


def test_library_observation_messages_say_entry():
    from clap_unified.spaces.landmarks2d import observations_array

    with pytest.raises(ValueError, match=r"^observations: entry 1: unknown type 'zz'"):
        observations_array([{"type": "L", "x": 0, "y": 0}, {"type": "zz", "x": 0, "y": 0}])


@pytest.mark.parametrize("prior", ["-1.2,3.4,0.1,", "-1.2,3.4", "-1.2,x,0"])
def test_a_malformed_negative_prior_says_three_numbers(tmp_path, capsys, prior):
    # "-1.2,3.4,0.1," was taken for an option: "argument --prior: expected one argument"
    err = _bad_input(["localize2d", _obs2d(tmp_path / "o.json"), "--prior", prior], capsys)
    assert "argument --prior: expected X,Y,THETA: three comma-separated numbers" in err


def test_huge_ranges_warn_of_no_overflow(tmp_path, capsys):
    # a detection at 1e149 m (within the readers' limit) overflowed the range-noise weight
    obs = _obs2d(tmp_path / "o.json", [{"type": "L", "x": 1e149, "y": -1e149}])
    for method in ("clap", "ransac", "randomized_hough"):
        status, _, err = _run(["localize2d", obs, "--method", method, "-q"], capsys)
        assert status in (0, 1) and err == "", err


def test_an_image_with_a_huge_header_is_one_clear_line(tmp_path, capsys):
    big = tmp_path / "big.pgm"
    big.write_bytes(b"P5\n100000000 100000000\n255\n" + bytes(16))
    right = tmp_path / "r.png"
    cv2.imwrite(str(right), np.zeros((20, 20, 3), np.uint8))
    err = _bad_input(["stitch", big, right, "-o", tmp_path / "p.png"], capsys)
    assert err == (f"clap-unified stitch: error: LEFT: {big}: more than 25,000,000 pixels "
                   "(100000000 x 100000000)\n")


def test_stitch_does_not_overwrite_an_input(tmp_path, capsys):
    g = np.random.default_rng(0)
    left, right = tmp_path / "L.png", tmp_path / "R.png"
    image = (g.random((120, 160, 3)) * 255).astype(np.uint8)
    cv2.imwrite(str(left), image)
    cv2.imwrite(str(right), image[:, 20:])
    before = left.read_bytes()
    for out, name in ((left, "LEFT"), (tmp_path / "." / "R.png", "RIGHT")):
        err = _bad_input(["stitch", left, right, "-o", out], capsys)
        assert "--output" in err and name in err
    assert left.read_bytes() == before
