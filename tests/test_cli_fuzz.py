"""Property-based fuzzing of every command's input parsing.

Every command, on any input, ends with one of the three exit statuses and nothing else: 2 with
exactly one line on stderr naming the argument (nothing on stdout, no output file), or 0 / 1
with one strict JSON object on stdout whose ``success`` agrees with the status. No exception
escapes ``main`` (an escaping exception is the traceback a user would see), no warning is
emitted (pytest turns warnings into errors), nothing hangs.

Commands run in-process through ``main(argv)`` for speed; a few run as real processes at the
end. Derandomized with bounded examples: the same cases every run, a few seconds in all.
"""

from __future__ import annotations

import contextlib
import io
import json
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from clap_unified.cli import _leaves, build_parser, main
from clap_unified.maps.field import LANDMARK_TYPES

FUZZ = settings(derandomize=True, database=None, deadline=None, max_examples=100,
                suppress_health_check=[HealthCheck.too_slow])
FEW = settings(FUZZ, max_examples=30)


def run(argv):
    """``(status, stdout, stderr)`` of ``main(argv)`` in this process."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main([str(a) for a in argv])
    return code, out.getvalue(), err.getvalue()


def _reject_constant(name):
    raise ValueError(f"not strict JSON: {name}")


def check_clean(code, out, err, *, argument=None):
    """The one convention. Returns the JSON on success or failure, None on bad input."""
    assert code in (0, 1, 2), (code, out, err)
    assert "Traceback" not in err
    if code == 2:
        assert out == ""
        assert err.endswith("\n") and err.count("\n") == 1, err
        assert err.startswith("clap-unified") and ": error: " in err, err
        if argument is not None:
            assert argument in err, err
        return None
    assert err == "", err
    d = json.loads(out, parse_constant=_reject_constant)
    assert d["success"] is (code == 0)
    assert isinstance(d["reason"], str) and d["reason"]
    return d


def write(folder: Path, name: str, content) -> Path:
    p = folder / name
    if isinstance(content, bytes):
        p.write_bytes(content)
    else:
        p.write_text(content, encoding="utf-8", errors="surrogatepass")
    return p


# --- values a file may hold ------------------------------------------------------------

NUMBERS = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.floats(-1e3, 1e3),
    st.integers(-(10**400), 10**400),
    st.sampled_from([0.0, 1e308, -1e308, 1e-320, 1e150, 1e151]))
TOKENS = st.one_of(
    NUMBERS.map(repr),
    st.sampled_from(["", " ", "nan", "inf", "-inf", "1e999", "abc", "0x10", "1_0", "+", "-",
                     "'1'", '"2"', "1;2", "\t3 ", "NaN", "Infinity", "\x00", "1e5"]),
    st.text(max_size=6))


@st.composite
def csv_texts(draw, columns: int):
    """CSV files near the expected form: half of them well-formed (random, tiny, huge and
    duplicated values, a header, blank lines), the others with one thing broken (a bad
    token, a wrong column count, a stray quote)."""
    n = draw(st.integers(0, 40))
    value = st.one_of(st.floats(-1e3, 1e3), st.integers(-5, 5),
                      st.sampled_from([0.0, 1e-300, 1e12, -1e12, 1e150]))
    rows = [[repr(draw(value)) for _ in range(columns)] for _ in range(n)]
    if rows and draw(st.booleans()):  # duplicated points
        rows += [rows[draw(st.integers(0, len(rows) - 1))]] * draw(st.integers(1, 30))
    if rows and draw(st.booleans()):  # one thing broken
        i = draw(st.integers(0, len(rows) - 1))
        if draw(st.booleans()):
            rows[i][draw(st.integers(0, columns - 1))] = draw(TOKENS)
        else:
            rows[i] = [draw(TOKENS) for _ in range(draw(st.sampled_from([0, 1, columns + 1])))]
    lines = [",".join(r) for r in rows]
    if draw(st.booleans()):
        lines.insert(0, ",".join("xyzw"[:columns]))
    if draw(st.integers(0, 5)) == 0:
        lines.insert(draw(st.integers(0, len(lines))), draw(st.sampled_from(["", " ", '"'])))
    return "\n".join(lines) + draw(st.sampled_from(["", "\n", "\r\n"]))


JSON_SCALARS = st.one_of(st.none(), st.booleans(), st.integers(-(10**30), 10**30),
                         st.floats(allow_nan=True, allow_infinity=True), st.text(max_size=8))
JSON_VALUES = st.recursive(JSON_SCALARS, lambda c: st.lists(c, max_size=4)
                           | st.dictionaries(st.text(max_size=4), c, max_size=4), max_leaves=12)


@st.composite
def detections(draw, coords: str, types):
    """JSON lists of detections: half of them well-formed (duplicates included), the others
    with one entry broken (a wrong type, a missing key, NaN, a huge number, a string)."""
    entries = [{"type": draw(st.sampled_from(types)), **{c: draw(st.floats(-8, 8))
                                                          for c in coords}}
               for _ in range(draw(st.integers(0, 10)))]
    if entries and draw(st.booleans()):
        entries += [entries[0]] * draw(st.integers(1, 4))
    if entries and draw(st.booleans()):
        i = draw(st.integers(0, len(entries) - 1))
        key = draw(st.sampled_from(["type", *coords]))
        broken = draw(st.sampled_from(["value", "missing", "entry"]))
        if broken == "value":
            entries[i][key] = draw(st.one_of(NUMBERS, JSON_SCALARS))
        elif broken == "missing":
            entries[i].pop(key)
        else:
            entries[i] = draw(JSON_VALUES)
    return json.dumps(entries, allow_nan=True)


FILE_CONTENTS = st.one_of(st.text(max_size=200), st.binary(max_size=200),
                          JSON_VALUES.map(lambda v: json.dumps(v, allow_nan=True)))


# --- fit line and fit homography ---------------------------------------------------------

@FUZZ
@given(text=csv_texts(2), method=st.sampled_from(["clap", "ransac", "hough",
                                                  "randomized_hough"]))
def test_fit_line_any_csv(text, method):
    with tempfile.TemporaryDirectory() as d:
        f = write(Path(d), "p.csv", text)
        check_clean(*run(["fit", "line", f, "--method", method, "--hypotheses", "200"]))


@FUZZ
@given(text=csv_texts(4), method=st.sampled_from(["clap", "ransac", "cv2_ransac"]))
def test_fit_homography_any_csv(text, method):
    with tempfile.TemporaryDirectory() as d:
        f = write(Path(d), "m.csv", text)
        check_clean(*run(["fit", "homography", f, "--method", method]))


@FEW
@given(content=FILE_CONTENTS)
def test_every_file_argument_any_bytes(content):
    """Random text, bytes and JSON in place of every input file."""
    with tempfile.TemporaryDirectory() as d:
        f = write(Path(d), "in.dat", content)
        good_map = write(Path(d), "map.json", json.dumps(
            [{"type": t, "x": float(i), "y": float(i % 3), "z": 0.5 * i}
             for i, t in enumerate("abcab")]))
        out = Path(d) / "pano.png"
        for argv in (["fit", "line", f], ["fit", "homography", f], ["localize2d", f],
                     ["localize3d", f, "--map", good_map], ["localize3d", good_map, "--map", f],
                     ["stitch", f, f, "-o", out], ["segment", "line", f],
                     ["segment", "circle", f], ["segment", "homography", f]):
            check_clean(*run(argv))
        assert not out.exists()


def test_huge_coordinates_are_refused_or_fitted_without_overflow(tmp_path):
    for value in ("1e150", "1e151", "1e300", "-1e308"):
        f = write(tmp_path, "p.csv", f"0,0\n{value},1\n2,{value}\n3,3\n")
        d = check_clean(*run(["fit", "line", f, "--method", "ransac"]))
        if float(value) > 1e150 or float(value) < -1e150:
            assert d is None


# --- localization --------------------------------------------------------------------------

@FUZZ
@given(text=detections("xy", LANDMARK_TYPES), method=st.sampled_from(["clap", "ransac",
                                                                      "randomized_hough"]),
       prior=st.none() | st.tuples(st.floats(-8, 8), st.floats(-5, 5), st.floats(-4, 4)))
def test_localize2d_any_detections(text, method, prior):
    with tempfile.TemporaryDirectory() as d:
        f = write(Path(d), "o.json", text)
        argv = ["localize2d", f, "--method", method]
        if prior is not None:
            argv += ["--prior", ",".join(repr(v) for v in prior)]  # often negative
        check_clean(*run(argv))


@FUZZ
@given(obs=detections("xyz", ["a", "b", "c"]), themap=detections("xyz", ["a", "b", "c"]))
def test_localize3d_any_detections_and_map(obs, themap):
    with tempfile.TemporaryDirectory() as d:
        o, m = write(Path(d), "o.json", obs), write(Path(d), "m.json", themap)
        check_clean(*run(["localize3d", o, "--map", m]))


# --- images ----------------------------------------------------------------------------------

def _png(shape, dtype=np.uint8, ext=".png") -> bytes:
    import cv2

    ok, buf = cv2.imencode(ext, np.zeros(shape, dtype))
    assert ok
    return buf.tobytes()


@FEW
@given(kind=st.sampled_from(["empty", "junk", "truncated_png", "truncated_jpg", "header_only",
                             "tiny", "grey16", "alpha", "text"]),
       junk=st.binary(max_size=64))
def test_stitch_unreadable_or_odd_images_write_nothing(kind, junk):
    content = {
        "empty": b"",
        "junk": junk,
        "truncated_png": _png((64, 64, 3))[:40],
        "truncated_jpg": _png((64, 64, 3), ext=".jpg")[:200],
        "header_only": b"\x89PNG\r\n\x1a\n" + junk,
        "tiny": _png((1, 1, 3)),
        "grey16": _png((32, 32), np.uint16),
        "alpha": _png((16, 16, 4)),
        "text": "not an image ü".encode(),
    }[kind]
    with tempfile.TemporaryDirectory() as d:
        img = write(Path(d), "img.png", content)
        out = Path(d) / "pano.png"
        code, text, err = run(["stitch", img, img, "-o", out])
        check_clean(code, text, err)
        if code:
            assert not out.exists()
        assert sorted(os.listdir(d)) == sorted(["img.png"] + (["pano.png"] if code == 0 else []))


# --- options ---------------------------------------------------------------------------------

OPTION_VALUES = st.one_of(st.text(max_size=12), NUMBERS.map(repr),
                          st.sampled_from(["-1", "0", "-0", "1e9", "10000000", "nan", "-inf",
                                           "-1,2,3", "1,2", "--", "-q", "1,2,3,4"]))


@FUZZ
@given(option=st.sampled_from(["--seed", "--threshold", "--hypotheses"]), value=OPTION_VALUES)
def test_fit_line_any_option_value(tmp_path_factory, option, value):
    f = tmp_path_factory.getbasetemp() / "line.csv"
    f.write_text("".join(f"{i},{2 * i + 1}\n" for i in range(10)))
    t0 = time.perf_counter()
    code, out, err = run(["fit", "line", f, "--method", "ransac", option, value])
    check_clean(code, out, err)
    if code == 2:
        assert option in err or "unrecognized" in err or "expected one argument" in err
    assert time.perf_counter() - t0 < 10


@FUZZ
@given(option=st.sampled_from(["--prior", "--seed", "--field", "--method"]), value=OPTION_VALUES)
def test_localize2d_any_option_value(tmp_path_factory, option, value):
    f = tmp_path_factory.getbasetemp() / "obs2d.json"
    f.write_text(json.dumps([{"type": "L", "x": 1.0, "y": 2.0}, {"type": "T", "x": -3, "y": 1},
                             {"type": "goal_post", "x": 4.0, "y": -1.0}]))
    code, out, err = run(["localize2d", f, option, value])
    check_clean(code, out, err)
    if code == 2:
        assert option in err or "unrecognized" in err or "expected one argument" in err


@FEW
@given(option=st.sampled_from(["--ratio", "--seed", "--blend", "--method", "-o"]),
       value=OPTION_VALUES)
def test_stitch_any_option_value_writes_nothing_on_failure(option, value):
    with tempfile.TemporaryDirectory() as d:
        missing = Path(d) / "missing.png"  # the images are checked after the options
        code, out, err = run(["stitch", missing, missing, "-o", Path(d) / "p.png", option, value])
        check_clean(code, out, err)
        assert code == 2 and os.listdir(d) == []


@FEW
@given(value=OPTION_VALUES)
def test_reproduce_jobs_any_value(value):
    code, out, err = run(["reproduce", "--jobs", value, "--out", "/nonexistent/x", "--only",
                          "no_such_experiment"])
    check_clean(code, out, err)
    assert code == 2


# --- the cases of the issue, one by one ------------------------------------------------------

@pytest.fixture
def obs2d(tmp_path):
    """Every landmark within 6 m of a robot at (-1.2, 3.4, 0.1), in its frame."""
    from clap_unified.localization import load_field

    field, (x, y, theta) = load_field("adult"), (-1.2, 3.4, 0.1)
    c, s = math.cos(theta), math.sin(theta)
    obs = [{"type": str(t), "x": c * (px - x) + s * (py - y), "y": -s * (px - x) + c * (py - y)}
           for t, (px, py) in zip(field.types, field.positions, strict=True)
           if math.hypot(px - x, py - y) < 6]
    assert len(obs) >= 8
    return write(tmp_path, "obs.json", json.dumps(obs))


@pytest.mark.parametrize("form", [["--prior", "-1.2,3.4,0.1"], ["--prior=-1.2,3.4,0.1"],
                                  ["--prior", "-1.2,-3.4e0,-0.1"]])
def test_negative_prior_in_both_forms(obs2d, form):
    d = check_clean(*run(["localize2d", obs2d, *form]))
    assert d["success"] is True
    if form[-1] != "-1.2,-3.4e0,-0.1":
        assert d["model"]["x"] == pytest.approx(-1.2, abs=0.15)
        assert d["model"]["y"] == pytest.approx(3.4, abs=0.15)


def test_other_negative_values_name_their_option(tmp_path):
    f = write(tmp_path, "p.csv", "0,0\n1,1\n2,2\n")
    for option in ("--threshold", "--seed", "--hypotheses"):
        for value in ("-1", "-1e-3", "-inf", "-0.5"):
            code, _, err = run(["fit", "line", f, option, value])
            assert code == 2 and f"argument {option}:" in err and err.count("\n") == 1


@pytest.mark.parametrize("argv", [
    ["fit", "line", "P", "--hypotheses", "10000000"],
    ["fit", "line", "P", "--hypotheses", "1000001"],
    ["fit", "line", "P", "--hypotheses", "1000000", "--method", "ransac"],  # H x N
    ["reproduce", "--jobs", "100000"],
])
def test_absurd_sizes_are_refused_within_seconds(tmp_path, argv):
    f = write(tmp_path, "p.csv", "".join(f"{i},{i}\n" for i in range(2000)))
    t0 = time.perf_counter()
    code, _, err = run([f if a == "P" else a for a in argv])
    assert time.perf_counter() - t0 < 3
    assert code == 2 and ("--hypotheses" in err or "--jobs" in err)


def test_input_limits(tmp_path, monkeypatch):
    import clap_unified.cli as cli
    import clap_unified.imaging.cli as imaging_cli
    import clap_unified.io as cio
    import clap_unified.localization.cli as loc_cli

    monkeypatch.setattr(cli, "MAX_ROWS", 50)
    f = write(tmp_path, "p.csv", "".join(f"{i},{i}\n" for i in range(51)))
    code, _, err = run(["fit", "line", f])
    assert code == 2 and "more than 50 rows" in err
    monkeypatch.setattr(cio, "MAX_FILE_BYTES", 100)
    code, _, err = run(["fit", "line", f])
    assert code == 2 and "too large" in err
    monkeypatch.undo()
    monkeypatch.setattr(imaging_cli, "MAX_MATCHES", 20)
    f = write(tmp_path, "m.csv", "".join(f"{i},{i},{i},{i}\n" for i in range(21)))
    code, _, err = run(["fit", "homography", f])
    assert code == 2 and "more than 20 rows" in err and "m.csv" in err
    monkeypatch.undo()
    obs = [{"type": "L", "x": float(i), "y": 0.0} for i in range(loc_cli.MAX_DETECTIONS + 1)]
    code, _, err = run(["localize2d", write(tmp_path, "o.json", json.dumps(obs))])
    assert code == 2 and f"at most {loc_cli.MAX_DETECTIONS}" in err
    import clap_unified.localization.cli3d as cli3d

    marks = [{"type": "a", "x": float(i), "y": 0.0, "z": 0.0}
             for i in range(cli3d.MAX_LANDMARKS + 1)]
    m = write(tmp_path, "m.json", json.dumps(marks))
    code, _, err = run(["localize3d", m, "--map", m])
    assert code == 2 and f"at most {cli3d.MAX_LANDMARKS}" in err and "m.json" in err
    monkeypatch.setattr(imaging_cli, "MAX_IMAGE_PIXELS", 1000)
    img = write(tmp_path, "big.png", _png((40, 40, 3)))
    code, _, err = run(["stitch", img, img, "-o", tmp_path / "pano.png"])
    assert code == 2 and "LEFT" in err and "more than 1,000 pixels" in err
    assert not (tmp_path / "pano.png").exists()


def test_paths_that_are_folders_name_the_argument(tmp_path):
    good = write(tmp_path, "o.json", "[]")
    for argv, name in [(["fit", "line", tmp_path], str(tmp_path)),
                       (["fit", "homography", tmp_path], str(tmp_path)),
                       (["localize2d", tmp_path], str(tmp_path)),
                       (["localize3d", good, "--map", tmp_path], str(tmp_path)),
                       (["localize3d", tmp_path, "--map", good], str(tmp_path)),
                       (["stitch", good, good, "-o", tmp_path], "--output")]:
        code, _, err = run(argv)
        assert code == 2 and name in err and err.count("\n") == 1, (argv, err)
        assert "folder" in err or "is a folder" in err


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no named pipes")
def test_a_named_pipe_is_refused_not_read(tmp_path):
    """Reading a FIFO blocks until a writer comes: the readers refuse non-regular files."""
    fifo = tmp_path / "pipe.json"
    os.mkfifo(fifo)
    for argv in (["localize2d", fifo], ["fit", "line", fifo],
                 ["localize3d", fifo, "--map", fifo]):
        code, _, err = run(argv)
        assert code == 2 and "not a regular file" in err


def test_deeply_nested_json_and_long_lines_are_refused_quickly(tmp_path):
    nested = write(tmp_path, "deep.json", "[" * 100_000 + "]" * 100_000)
    code, _, err = run(["localize2d", nested])
    assert code == 2 and "nested too deeply" in err
    code, _, err = run(["localize3d", nested, "--map", nested])
    assert code == 2 and "nested too deeply" in err
    wide = write(tmp_path, "wide.csv", ",".join(["1"] * 200_000) + "\n")
    code, _, err = run(["fit", "line", wide])
    assert code == 2 and "line 1: expected 2 values, got 200000" in err


def test_one_point_one_detection_and_empty_inputs(tmp_path):
    """Too few data is a failed estimate (1); no data at all is bad input (2)."""
    assert run(["fit", "line", write(tmp_path, "one.csv", "1,2\n")])[0] == 1
    assert run(["fit", "line", write(tmp_path, "none.csv", "")])[0] == 2
    assert run(["localize2d", write(tmp_path, "one.json", '[{"type": "L", "x": 1, "y": 2}]')]
               )[0] == 1
    assert run(["localize2d", write(tmp_path, "none.json", "[]")])[0] == 2


# --- progress, version, help ----------------------------------------------------------------

class _Terminal(io.StringIO):
    def isatty(self):
        return True


def test_progress_bar_on_a_terminal_only_and_not_with_quiet(tmp_path, monkeypatch):
    f = write(tmp_path, "p.csv", "".join(f"{i},{i}\n" for i in range(20)))
    for quiet, shown in (([], True), (["--quiet"], False), (["-q"], False)):
        term = _Terminal()
        monkeypatch.setattr(sys, "stderr", term)
        out = io.StringIO()
        with contextlib.redirect_stdout(out):
            assert main(["fit", "line", str(f), *quiet]) == 0
        monkeypatch.undo()
        text = term.getvalue()
        assert ("fit line" in text and "fitting (clap" in text) is shown, text
        assert json.loads(out.getvalue())["success"] is True
    # not a terminal (a pipe, a file, the test's capture): no bar
    code, _, err = run(["fit", "line", f])
    assert code == 0 and err == ""


def test_version_and_help_exit_0(capsys):
    from clap_unified import __version__

    code, out, _ = run(["--version"])
    assert code == 0 and out.strip() == f"clap-unified {__version__}"
    for argv in (["--help"], ["fit", "line", "--help"], ["stitch", "--help"]):
        code, out, _ = run(argv)
        assert code == 0 and "exit status:" in out and "2    bad input" in out


def test_every_option_has_help_and_every_command_documents_output_and_exit_status():
    """The CLI reference is built from the parser: nothing may be left undocumented."""
    leaves = list(_leaves(build_parser()))
    assert len(leaves) == 10  # fit line, fit homography, localize2d, localize3d, stitch,
    # reproduce, segment line, segment circle, segment homography, segment fundamental
    for leaf in leaves:
        assert leaf.description, leaf.prog
        assert "exit status:" in leaf.epilog, leaf.prog
        assert "output:" in leaf.epilog or "JSON" in leaf.description, leaf.prog
        for action in leaf._actions:
            assert action.help, (leaf.prog, action.dest)


# --- real processes --------------------------------------------------------------------------

def _proc(*argv, cwd=None):
    env = {**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[1])}
    return subprocess.run([sys.executable, "-m", "clap_unified", *map(str, argv)],
                          capture_output=True, text=True, timeout=120, cwd=cwd, env=env)


def test_real_processes_one_line_no_traceback(tmp_path):
    junk = write(tmp_path, "junk.png", b"\x89PNG\r\n\x1a\n" + b"\x00" * 40)
    trunc = write(tmp_path, "trunc.jpg", _png((64, 64, 3), ext=".jpg")[:300])
    bad = write(tmp_path, "bad.csv", "1,2\nnan,3\n")
    cases = [(["fit", "line", bad], "non-finite"),
             (["stitch", junk, trunc, "-o", tmp_path / "p.png"], "not a readable image"),
             (["stitch", trunc, trunc, "-o", tmp_path / "p.png"], "not a readable image"),
             (["localize2d", tmp_path / "none.json"], "no such observations file"),
             (["fit", "line", bad, "--hypotheses", "10000000"], "--hypotheses")]
    for argv, needle in cases:
        p = _proc(*argv, cwd=tmp_path)
        assert p.returncode == 2 and p.stdout == "", (argv, p.stderr)
        assert p.stderr.count("\n") == 1 and needle in p.stderr, (argv, p.stderr)
    assert not (tmp_path / "p.png").exists()
    p = _proc("--version")
    assert p.returncode == 0 and p.stdout.startswith("clap-unified ")


def test_real_process_negative_prior(obs2d):
    p = _proc("localize2d", obs2d, "--prior", "-1.2,3.4,0.1")
    assert p.returncode == 0 and p.stderr == ""
    assert math.isclose(json.loads(p.stdout)["model"]["x"], -1.2, abs_tol=0.15)


@pytest.mark.skipif(sys.platform == "win32", reason="needs a pseudo-terminal")
def test_progress_bar_in_a_real_terminal_and_quiet(tmp_path):
    """A real process with stderr on a terminal (100 columns) shows the running stage and its
    time; with --quiet only the JSON comes out."""
    import fcntl
    import pty
    import struct
    import termios

    f = write(tmp_path, "p.csv", "".join(f"{i},{2 * i + i % 7}\n" for i in range(300)))
    texts = []
    for quiet in ([], ["--quiet"]):
        pid, fd = pty.fork()
        if pid == 0:  # the child: a terminal 100 columns wide, then the command
            fcntl.ioctl(1, termios.TIOCSWINSZ, struct.pack("HHHH", 24, 100, 0, 0))
            os.environ["PYTHONPATH"] = str(Path(__file__).resolve().parents[1])
            os.execv(sys.executable, [sys.executable, "-m", "clap_unified", "fit", "line",
                                      str(f), "--method", "ransac", *quiet])
        out = b""
        while True:
            try:
                chunk = os.read(fd, 4096)
            except OSError:
                break
            if not chunk:
                break
            out += chunk
        _, status = os.waitpid(pid, 0)
        os.close(fd)
        assert os.waitstatus_to_exitcode(status) == 0
        texts.append(out.decode())
    shown, quiet = texts
    assert "\rfit line: reading points [00:00]" in shown
    assert "fit line: fitting (ransac, 1000 hypotheses)" in shown
    assert quiet.startswith("{") and "fit line" not in quiet
    assert json.loads(quiet.strip())["success"] is True
