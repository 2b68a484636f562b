"""``clap-unified localize3d``: output format, methods, bad input."""

import json

import numpy as np
import pytest

from clap_unified.cli import main
from clap_unified.localization.localize3d import pose_errors
from clap_unified.localization.map3d import lab_map
from clap_unified.localization.scene3d import mocap_trajectory, simulate_detections


@pytest.fixture(scope="module")
def frame():
    lab = lab_map()
    det = simulate_detections(lab, mocap_trajectory(10, rng=0)[4], outlier_ratio=0.5, rng=1)
    return lab, det


@pytest.fixture()
def files(tmp_path, frame):
    lab, det = frame
    (tmp_path / "map.json").write_text(json.dumps(lab.to_json()))
    (tmp_path / "obs.json").write_text(json.dumps(det.input.to_json()))
    return tmp_path


def run(argv, capsys):
    code = main(argv)
    out, err = capsys.readouterr()
    return code, out, err


@pytest.mark.parametrize("method", ["clap", "ransac", "open3d"])
def test_localize3d_prints_pose_json(files, frame, capsys, method):
    code, out, _ = run(["localize3d", str(files / "obs.json"), "--map", str(files / "map.json"),
                        "--method", method, "--seed", "3"], capsys)
    assert code == 0
    doc = json.loads(out)
    R, t = np.array(doc["model"]["rotation"]), np.array(doc["model"]["translation"])
    assert R.shape == (3, 3) and t.shape == (3,) and doc["success"] is True
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, t
    e_t, e_r = pose_errors(T, frame[1].truth.pose)
    assert e_t < 0.05 and e_r < 1.0
    assert doc["clusters"] and set(doc["clusters"][0]) == {"model", "support", "spread"}
    assert set(doc["clusters"][0]["model"]) == {"rotation", "translation"}
    assert doc["method"] == method and doc["candidates"] > 0
    supports = [c["support"] for c in doc["clusters"]]
    assert supports == sorted(supports, reverse=True)


def test_localize3d_is_seeded(files, capsys):
    argv = ["localize3d", str(files / "obs.json"), "--map", str(files / "map.json")]
    a = json.loads(run(argv, capsys)[1])
    b = json.loads(run(argv, capsys)[1])
    a.pop("seconds"), b.pop("seconds")
    assert a == b


def test_too_few_observations_is_a_failed_estimate(files, capsys):
    (files / "few.json").write_text('[{"type": "L", "x": 1, "y": 0, "z": 0}]')
    code, out, _ = run(["localize3d", str(files / "few.json"), "--map",
                        str(files / "map.json")], capsys)
    doc = json.loads(out)
    assert code == 1 and doc["success"] is False and "at least 3" in doc["reason"]


@pytest.mark.parametrize("content, message", [
    ("not json", "not valid JSON"),
    ('{"type": "L"}', "expected a JSON list"),
    ('[{"type": "L", "x": 1, "y": 2}]', "entry 0"),
    ('[{"type": "L", "x": "a", "y": 2, "z": 0}]', "entry 0"),
    ('[{"type": "L", "x": NaN, "y": 2, "z": 0}]', "finite"),
    ('[{"type": "unicorn", "x": 1, "y": 2, "z": 0}]', "unicorn"),
])
def test_bad_observation_files_exit_2_with_one_line(files, capsys, content, message):
    (files / "bad.json").write_text(content)
    code, out, err = run(["localize3d", str(files / "bad.json"), "--map",
                          str(files / "map.json")], capsys)
    assert code == 2 and out == ""
    assert message in err and err.count("\n") == 1 and "bad.json" in err


def test_bad_map_files_exit_2(files, capsys):
    (files / "small.json").write_text('[{"type": "L", "x": 1, "y": 2, "z": 0}]')
    for name in ("missing.json", "small.json"):
        code, _, err = run(["localize3d", str(files / "obs.json"), "--map",
                            str(files / name)], capsys)
        assert code == 2 and name in err and err.count("\n") == 1
    code, _, err = run(["localize3d", str(files / "obs.json")], capsys)
    assert code == 2 and "--map" in err
