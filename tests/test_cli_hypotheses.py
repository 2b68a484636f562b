"""``--hypotheses H`` on every command that estimates (issue 27): ``fit homography``,
``stitch``, ``localize2d``, ``localize3d`` as ``fit line`` and ``segment``."""

import json

import numpy as np
import pytest

from clap_unified.cli import build_parser, main
from clap_unified.imaging.estimate import PROTOCOLS, estimate_homography
from clap_unified.io import MAX_HYPOTHESES, MAX_WORK

#: The issue's case: 10 % inliers among 1500 matches in a 640 x 480 image.
N_INLIERS, N_OUTLIERS = 150, 1350
#: CLAP's budget that finds them: measured over data seeds 0-9 (rng 0), 50000 found all 150 in
#: 10 of 10, 30000 in 8, the default (1000, escalating to 10000) in 7; OpenCV's RANSAC (1000
#: iterations) in 10 (147 to 150).
ENOUGH = 50_000


def run(args, capsys):
    code = main([str(a) for a in args])
    out, err = capsys.readouterr()
    return code, out, err


def ten_percent_inliers(seed=0):
    """150 matches of a known homography with 0.5 px noise, then 1350 random matches."""
    rng = np.random.default_rng(seed)
    H = np.array([[0.95, 0.08, 40.0], [-0.06, 1.02, -25.0], [2e-5, -1e-5, 1.0]])
    src = rng.uniform([0, 0], [640, 480], (N_INLIERS, 2))
    p = np.c_[src, np.ones(N_INLIERS)] @ H.T
    dst = p[:, :2] / p[:, 2:] + rng.normal(0, 0.5, (N_INLIERS, 2))
    out = rng.uniform([0, 0, 0, 0], [640, 480, 640, 480], (N_OUTLIERS, 4))
    return np.r_[np.c_[src, dst], out], H


@pytest.fixture(scope="module")
def hard_matches(tmp_path_factory):
    m, _ = ten_percent_inliers(0)
    f = tmp_path_factory.mktemp("hyp") / "matches.csv"
    np.savetxt(f, m, delimiter=",", header="x1,y1,x2,y2", comments="")
    return f, m


def _option(argv):
    """The ``--hypotheses`` action of the command parser reached by ``argv``."""
    parser = build_parser()
    for word in argv:
        sub = next(a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction")
        parser = sub.choices[word]
    return parser._option_string_actions["--hypotheses"]


@pytest.mark.parametrize("argv", [["fit", "homography"], ["stitch"], ["localize2d"],
                                  ["localize3d"], ["fit", "line"], ["segment", "line"]])
def test_every_estimating_command_has_the_option(argv):
    action = _option(argv)
    assert action.dest == "hypotheses" and "at most" in action.help
    assert str(MAX_HYPOTHESES) in action.help
    if argv[0] != "segment":  # segment has its own, smaller work limit
        assert "hypotheses x " in action.help and f"{MAX_WORK:.0e}" in action.help
    assert action.metavar == "H"  # one spelling in every command's usage line
    if argv != ["fit", "line"]:  # fit line's default is its budget itself
        assert action.default is None


@pytest.mark.parametrize("value", ["0", "-3", "2.5", str(MAX_HYPOTHESES + 1)])
def test_out_of_range_exits_2(hard_matches, capsys, value):
    code, out, err = run(["fit", "homography", hard_matches[0], "--hypotheses", value], capsys)
    assert code == 2 and out == "" and "--hypotheses" in err


def test_work_limit_exits_2_naming_the_option(hard_matches, capsys):
    code, out, err = run(["fit", "homography", hard_matches[0], "--hypotheses", MAX_HYPOTHESES],
                         capsys)  # 1500 matches x 1e6 hypotheses > 2e8
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and "--hypotheses" in err and "1500 data" in err


def test_default_is_the_protocol_budget(hard_matches, capsys):
    """No ``--hypotheses``: today's output; the protocol's own budget given explicitly: the
    same output, bit for bit."""
    f = hard_matches[0]
    for method in ("clap", "ransac", "clap_paper", "cv2_ransac"):
        budget = PROTOCOLS[method]["n_hypotheses"]
        a = json.loads(run(["fit", "homography", f, "--method", method], capsys)[1])
        b = json.loads(run(["fit", "homography", f, "--method", method, "--hypotheses", budget],
                           capsys)[1])
        a.pop("seconds"), b.pop("seconds")
        assert a == b, method


def test_budget_reaches_the_external_peers(hard_matches, capsys):
    """OpenCV's iteration cap: 3 iterations at 10 % inliers find no homography worth it."""
    f = hard_matches[0]
    few = json.loads(run(["fit", "homography", f, "--method", "cv2_ransac", "--hypotheses", 3],
                         capsys)[1])
    full = json.loads(run(["fit", "homography", f, "--method", "cv2_ransac"], capsys)[1])
    assert full["inliers"] >= 0.95 * N_INLIERS and few["inliers"] < 0.5 * N_INLIERS


def test_ten_percent_inliers_clap_needs_a_larger_budget(hard_matches, capsys):
    """The issue's case: the default budget misses the 150 inliers where OpenCV's finds them;
    ``--hypotheses`` lets CLAP find all 150 inliers."""
    f, m = hard_matches
    code, out, _ = run(["fit", "homography", f, "--method", "clap"], capsys)
    default = json.loads(out)
    # a handful of matches agree, not 150 (the command reports the library's answer: fit's
    # one success rule passes a handful, see test_cli_and_library_agree)
    assert default["inliers"] < N_INLIERS // 10
    cv = json.loads(run(["fit", "homography", f, "--method", "cv2_ransac"], capsys)[1])
    assert cv["success"] is True and cv["inliers"] == N_INLIERS
    code, out, err = run(["fit", "homography", f, "--method", "clap", "--hypotheses", ENOUGH],
                         capsys)
    d = json.loads(out)
    assert code == 0 and err == "" and d["success"] is True
    assert N_INLIERS <= d["inliers"] <= N_INLIERS + 3  # all of them, give or take a lucky one
    _, H = ten_percent_inliers(0)
    corners = np.array([[0, 0, 1], [640, 0, 1], [640, 480, 1], [0, 480, 1]], float)

    def warp(M):
        q = corners @ np.asarray(M).T
        return q[:, :2] / q[:, 2:]

    assert np.abs(warp(d["model"]["H"]) - warp(H)).max() < 1.0


def test_cli_model_is_the_library_model(hard_matches, capsys):
    """The same data, seed and budget give the same homography in both."""
    f, m = hard_matches
    d = json.loads(run(["fit", "homography", f, "--seed", 3, "--hypotheses", ENOUGH],
                       capsys)[1])
    res = estimate_homography(m, "clap", rng=3, threshold=3.0, n_hypotheses=ENOUGH)
    lib = json.loads(json.dumps(res.to_dict()))
    assert d["success"] is True and d["model"] == lib["model"]
    assert d["inliers"] == lib["inliers"] == res.n_inliers


def test_stitch_takes_the_budget(tmp_path, capsys):
    from clap_unified.imaging.cli import read_image_checked
    from clap_unified.imaging.datasets import load_synthetic_vpg
    from clap_unified.imaging.features import sift_matches

    [s] = load_synthetic_vpg(tmp_path / "vpg", scenes=["astronaut"], images_per_set=2, rng=0)
    left, right = s.input.images[1], s.input.images[2]
    out = tmp_path / "pano.png"
    code, text, err = run(["stitch", left, right, "-o", out, "--seed", 1, "--hypotheses", 300,
                           "--method", "ransac"], capsys)
    d = json.loads(text)
    assert code == 0 and err == "" and d["success"] is True and out.is_file()
    matches, _ = sift_matches(read_image_checked(left, "LEFT"), read_image_checked(right, "RIGHT"))
    res = estimate_homography(matches, "ransac", rng=1, n_hypotheses=300)
    assert d["model"] == json.loads(json.dumps(res.to_dict()))["model"]
    code, text, err = run(["stitch", left, right, "-o", tmp_path / "big.png",
                           "--hypotheses", MAX_HYPOTHESES], capsys)
    assert len(matches) * MAX_HYPOTHESES > MAX_WORK  # checked once the matches are known
    assert code == 2 and text == "" and "--hypotheses" in err
    assert not (tmp_path / "big.png").exists()


def test_localize2d_takes_the_budget(tmp_path, capsys):
    from clap_unified.geometry import SE2
    from clap_unified.localization import load_field, localize2d, simulate_observations

    obs = simulate_observations(load_field("adult"), SE2.from_xytheta(3.0, 1.0, 0.2),
                                false_positive_rate=0.4, rng=1)
    f = tmp_path / "obs.json"
    f.write_text(json.dumps(obs.input.to_dicts()))
    full = json.loads(run(["localize2d", f], capsys)[1])
    few = json.loads(run(["localize2d", f, "--hypotheses", 5, "--seed", 2], capsys)[1])
    assert 0 < few["candidates"] < full["candidates"]
    res = localize2d(obs.input, "adult", n_hypotheses=5, rng=2)
    assert few["model"] == json.loads(json.dumps(res.to_dict()))["model"]
    assert few["candidates"] == res.diagnostics["hypotheses"]


@pytest.mark.parametrize("method", ["clap", "open3d"])
def test_localize3d_takes_the_budget(tmp_path, capsys, method):
    from clap_unified.localization.localize3d import localize3d
    from clap_unified.localization.map3d import lab_map
    from clap_unified.localization.scene3d import mocap_trajectory, simulate_detections

    if method == "open3d":
        pytest.importorskip("open3d")
    lab = lab_map()
    det = simulate_detections(lab, mocap_trajectory(10, rng=0)[4], outlier_ratio=0.5, rng=1)
    (tmp_path / "map.json").write_text(json.dumps(lab.to_json()))
    (tmp_path / "obs.json").write_text(json.dumps(det.input.to_json()))
    argv = ["localize3d", tmp_path / "obs.json", "--map", tmp_path / "map.json",
            "--method", method, "--seed", 3]
    d = json.loads(run([*argv, "--hypotheses", 200], capsys)[1])
    kw = {"open3d_iterations": 200} if method == "open3d" else {"n_hypotheses": 200}
    res = localize3d(det.input, lab, method=method, rng=3, **kw)
    assert d["model"] == json.loads(json.dumps(res.to_dict()))["model"]
    if method == "clap":
        full = json.loads(run(argv, capsys)[1])
        assert d["candidates"] < full["candidates"]


def test_localize3d_work_limit(tmp_path, capsys):
    from clap_unified.localization.map3d import lab_map

    lab = lab_map()
    (tmp_path / "map.json").write_text(json.dumps(lab.to_json()))
    kind = lab.to_json()[0]["type"]
    rng = np.random.default_rng(0)
    obs = [{"type": kind, "x": float(x), "y": float(y), "z": float(z)}
           for x, y, z in rng.uniform(-3, 3, (300, 3))]
    (tmp_path / "obs.json").write_text(json.dumps(obs))
    code, out, err = run(["localize3d", tmp_path / "obs.json", "--map", tmp_path / "map.json",
                          "--hypotheses", MAX_HYPOTHESES], capsys)
    assert code == 2 and out == "" and "--hypotheses" in err and "300 data" in err


@pytest.mark.parametrize("method,seed", [("clap", 0), ("clap", 1), ("ransac", 0),
                                         ("randomized_hough", 0)])
def test_cli_and_library_agree(hard_matches, capsys, method, seed):
    """Issue 27: ``fit homography`` and ``estimate_homography`` give the same answer on the
    same data: success, reason, inliers and model. Before, the command failed any estimate
    with fewer than 8 inliers (its own rule) where the library succeeded (clap, seed 0: 6
    inliers)."""
    f, m = hard_matches
    code, out, _ = run(["fit", "homography", f, "--method", method, "--seed", seed], capsys)
    d = json.loads(out)
    lib = json.loads(json.dumps(estimate_homography(m, method, rng=seed,
                                                    threshold=3.0).to_dict()))
    assert code == (0 if lib["success"] else 1)
    assert (d["success"], d["reason"], d["inliers"], d["model"]) == \
        (lib["success"], lib["reason"], lib["inliers"], lib["model"])


def _spy_budgets(monkeypatch, cls):
    """Record the ``n`` of every ``cls.hypotheses(data, n, ...)`` call (the budget that
    reached ``fit`` or ``segment``), the call itself unchanged."""
    calls, original = [], cls.hypotheses

    def hypotheses(self, data, n, *args, **kwargs):
        calls.append(int(n))
        return original(self, data, n, *args, **kwargs)

    monkeypatch.setattr(cls, "hypotheses", hypotheses)
    return calls


def _budget_data(kind, path):
    rng = np.random.default_rng(0)
    if kind in ("line", "circle"):
        t = rng.uniform(0, 2 * np.pi, 60)
        rows = (np.c_[t, 0.5 * t + 1] if kind == "line" else np.c_[np.cos(t), np.sin(t)] * 3)
        rows = np.r_[rows, rng.uniform(-3, 6, (20, 2))]
    elif kind == "homography":
        m = ten_percent_inliers(1)[0]
        rows = np.r_[m[:60], m[N_INLIERS:N_INLIERS + 15]]  # 60 inliers among 75
    else:
        from clap_unified.imaging.datasets import synthetic_two_view

        rows = synthetic_two_view(120, outliers=0.2, noise=0.3, rng=0).input.matches
    np.savetxt(path, rows, delimiter=",")
    return path


@pytest.mark.parametrize("argv,kind,space", [
    (["fit", "line"], "line", "LineSpace"),
    (["fit", "homography", "--method", "clap"], "homography", "HomographySpace"),
    (["fit", "homography", "--method", "clap_paper"], "homography", "HomographySpace"),
    (["fit", "homography", "--method", "randomized_hough"], "homography", "HomographySpace"),
    (["segment", "line"], "line", "LineSpace"),
    (["segment", "circle"], "circle", "CircleSpace"),
    (["segment", "homography"], "homography", "HomographySpace"),
    (["segment", "fundamental"], "fundamental", "FundamentalSpace")])
def test_the_budget_reaches_fit(tmp_path, capsys, monkeypatch, argv, kind, space):
    """``--hypotheses H`` is the number of hypotheses the command's fit (or segment) draws
    first, for every command that draws them; without it, the command's default (the
    preset's, for ``fit homography``) is drawn instead."""
    import clap_unified.spaces as spaces

    calls = _spy_budgets(monkeypatch, getattr(spaces, space))
    f = _budget_data(kind, tmp_path / "data.csv")
    code, out, err = run([*argv[:2], f, *argv[2:], "--seed", 1, "--hypotheses", 123], capsys)
    assert code in (0, 1) and err == "" and calls and calls[0] == 123
    calls.clear()
    run([*argv[:2], f, *argv[2:], "--seed", 1], capsys)
    assert calls and calls[0] != 123
    if argv[:2] == ["fit", "homography"]:
        method = argv[-1]
        assert calls[0] == PROTOCOLS[method]["n_hypotheses"]
