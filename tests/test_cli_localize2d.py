import json
import re

import numpy as np
import pytest

from clap_unified.cli import main
from clap_unified.geometry import SE2
from clap_unified.localization import load_field, simulate_observations

TRUTH = SE2.from_xytheta(3.0, 1.0, 0.2)


def run(args, capsys):
    code = main(args)
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture
def obs_file(tmp_path):
    obs = simulate_observations(load_field("adult"), TRUTH, false_positive_rate=0.4, rng=1)
    f = tmp_path / "obs.json"
    f.write_text(json.dumps(obs.input.to_dicts()))
    return f


def test_global_mode_prints_pose_and_both_mirror_clusters(obs_file, capsys):
    code, out, err = run(["localize2d", str(obs_file), "--field", "adult"], capsys)
    assert code == 0 and err == ""
    d = json.loads(out)
    assert d["success"] is True and set(d["model"]) == {"x", "y", "theta"}
    top = d["clusters"][:2]
    assert top[0]["support"] == top[1]["support"]
    xs = sorted(c["model"]["x"] for c in top)
    assert xs[0] == pytest.approx(-3.0, abs=0.1) and xs[1] == pytest.approx(3.0, abs=0.1)
    assert all(set(c) == {"model", "support", "spread"} for c in d["clusters"])
    # the one JSON form of a result, plus the command's context
    assert d["method"] == "clap" and d["field"] == "adult" and d["candidates"] > 0
    assert d["data"] == len(json.loads(obs_file.read_text()))
    assert d["threshold"] == pytest.approx(0.3)


@pytest.mark.parametrize("method", ["clap", "ransac", "randomized_hough"])
def test_prior_selects_the_true_pose(obs_file, capsys, method):
    code, out, _ = run(["localize2d", str(obs_file), "--method", method,
                        "--prior", "2.8,1.1,0.25", "--seed", "1"], capsys)
    d = json.loads(out)
    assert code == 0 and d["method"] == method
    assert d["model"]["x"] == pytest.approx(3.0, abs=0.1)
    assert d["model"]["y"] == pytest.approx(1.0, abs=0.1)
    assert d["model"]["theta"] == pytest.approx(0.2, abs=np.radians(2))


@pytest.mark.parametrize("content, match", [
    (None, "no such observations file"),
    ("", "not valid JSON"),
    ("[]", "no detections"),
    ("{not json", "not valid JSON"),
    ('{"type": "L"}', "JSON list"),
    ('[{"type": "Q", "x": 1, "y": 2}]', "unknown type"),
    ('[{"type": "L", "x": "a", "y": 2}]', 'entry 0: "x" must be a number'),
    ('[{"type": "L", "x": NaN, "y": 2}, {"type": "T", "x": 1, "y": 1}]', "finite"),
])
def test_bad_files_exit_2_with_one_line(tmp_path, capsys, content, match):
    f = tmp_path / "o.json"
    if content is not None:
        f.write_text(content)
    code, out, err = run(["localize2d", str(f)], capsys)
    assert code == 2 and out == ""
    assert len(err.strip().splitlines()) == 1
    assert re.search(match, err)


def test_bad_prior_and_field_exit_2(obs_file, capsys):
    code, _, err = run(["localize2d", str(obs_file), "--prior", "1,2"], capsys)
    assert code == 2 and "argument --prior" in err
    # the classical Hough transform is for lines only
    code, _, err = run(["localize2d", str(obs_file), "--method", "hough"], capsys)
    assert code == 2 and "argument --method" in err
    code, _, err = run(["localize2d", str(obs_file), "--field", "senior"], capsys)
    assert code == 2 and "argument --field" in err and err.count("\n") == 1


def test_one_observation_is_a_failed_fit_not_a_crash(tmp_path, capsys):
    f = tmp_path / "one.json"
    f.write_text('[{"type": "L", "x": 1.0, "y": 0.5}]')
    code, out, _ = run(["localize2d", str(f)], capsys)
    d = json.loads(out)
    assert code == 1 and d["success"] is False and d["model"] is None
    assert "at least 2" in d["reason"]
