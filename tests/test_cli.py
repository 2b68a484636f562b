import json
import subprocess
import sys

import numpy as np
import pytest
from scenes import line_scene

from clap_unified.cli import main


def run(args, capsys):
    code = main(args)
    out, err = capsys.readouterr()
    return code, out, err


@pytest.mark.parametrize("method", ["hough", "ransac", "clap"])
def test_fit_line_prints_json(tmp_path, capsys, method):
    pts = line_scene(n=200, outlier_ratio=0.5, seed=1).input.points
    f = tmp_path / "pts.csv"
    np.savetxt(f, pts, delimiter=",", header="x,y", comments="")
    code, out, err = run(["fit", "line", str(f), "--method", method, "--seed", "3",
                          "--threshold", "0.06"], capsys)
    assert code == 0 and err == ""
    d = json.loads(out)
    assert d["success"] is True and isinstance(d["seconds"], float)
    a, b = d["model"]["normal"]
    assert a * a + b * b == pytest.approx(1.0)
    assert abs(abs(np.dot([a, b], [-np.sin(0.3), np.cos(0.3)])) - 1) < 1e-3
    assert 95 <= d["inliers"] <= 110


def test_same_seed_same_output(tmp_path, capsys):
    pts = line_scene(seed=2).input.points
    f = tmp_path / "p.csv"
    np.savetxt(f, pts, delimiter=",")
    outs = [json.loads(run(["fit", "line", str(f), "--seed", "5"], capsys)[1]) for _ in range(2)]
    for o in outs:
        o.pop("seconds")
    assert outs[0] == outs[1]


@pytest.mark.parametrize("content, needle", [
    (None, "no such file"),
    ("", "no data"),
    ("x,y\n", "no data"),
    ("1,2\n3,abc\n", "line 2: non-numeric"),
    ("1,2\nnan,3\n", "non-finite"),
    ("1,2,3\n4,5,6\n", "expected 2 values"),
])
def test_bad_files_exit_2_with_one_line(tmp_path, capsys, content, needle):
    f = tmp_path / "bad.csv"
    if content is not None:
        f.write_text(content)
    code, out, err = run(["fit", "line", str(f)], capsys)
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and needle in err


def test_one_point_is_a_failed_estimate_not_bad_input(tmp_path, capsys):
    f = tmp_path / "one.csv"
    f.write_text("x,y\n1,2\n")
    code, out, err = run(["fit", "line", str(f)], capsys)
    d = json.loads(out)
    assert code == 1 and err == "" and d["success"] is False and d["model"] is None
    assert d["reason"] == "need at least 2 points, got 1" and d["data"] == 1


def test_degenerate_points_report_failure(tmp_path, capsys):
    f = tmp_path / "same.csv"
    f.write_text("1,1\n1,1\n1,1\n")
    code, out, _ = run(["fit", "line", str(f), "--method", "ransac"], capsys)
    d = json.loads(out)
    assert code == 1 and d["success"] is False and d["reason"]


def test_console_script_bad_method_exit_2(tmp_path):
    f = tmp_path / "p.csv"
    f.write_text("0,0\n1,1\n")
    proc = subprocess.run([sys.executable, "-m", "clap_unified.cli", "fit", "line", str(f),
                           "--method", "magic"], capture_output=True, text=True)
    assert proc.returncode == 2 and "invalid choice" in proc.stderr
