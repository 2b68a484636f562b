"""``clap-unified stitch`` and ``clap-unified fit homography``."""

import json

import numpy as np
import pytest

from clap_unified.cli import main
from clap_unified.imaging.datasets import load_synthetic_vpg
from clap_unified.imaging.evaluation import vpg_pair_matches
from clap_unified.imaging.metrics import corner_error


@pytest.fixture(scope="module")
def synthetic_set(tmp_path_factory):
    root = tmp_path_factory.mktemp("vpg")
    [s] = load_synthetic_vpg(root, scenes=["astronaut"], images_per_set=2, rng=0)
    return s


@pytest.fixture(scope="module")
def sift_pair(synthetic_set):
    """The SIFT matches of images 1 and 2 (the input) with their ground truth."""
    [pm] = vpg_pair_matches(synthetic_set)
    return pm


def run(args, capsys):
    code = main(args)
    out, err = capsys.readouterr()
    return code, out, err


@pytest.mark.parametrize("method", ["clap", "ransac", "magsac"])
def test_stitch_writes_panorama_and_json(synthetic_set, tmp_path, capsys, method):
    out = tmp_path / f"pano_{method}.png"
    left, right = synthetic_set.input.images[1], synthetic_set.input.images[2]
    code, text, err = run(["stitch", str(left), str(right),
                           "-o", str(out), "--method", method, "--seed", "1"], capsys)
    assert code == 0 and err == ""
    d = json.loads(text)
    assert d["success"] is True and out.is_file()
    assert d["inliers"] >= 0.5 * d["matches"] and d["matches"] > 100
    assert d["method"] == method and d["data"] == d["matches"]
    H = np.array(d["model"]["H"])
    assert H.shape == (3, 3) and H[2, 2] == 1.0
    assert corner_error(H, synthetic_set.truth.H(1, 2), (640, 480)) < 3.0
    import cv2

    pano = cv2.imread(str(out))
    assert pano.shape[1] > 640 and pano.shape[0] >= 480
    import os

    umask = os.umask(0)
    os.umask(umask)
    assert out.stat().st_mode & 0o777 == 0o666 & ~umask  # not the temporary file's 0600
    assert sorted(p.name for p in tmp_path.iterdir()) == [out.name]  # no temporary file left


@pytest.mark.parametrize("blend", ["none", "overwrite", "feather"])
def test_every_blend(synthetic_set, tmp_path, capsys, blend):
    out = tmp_path / f"pano_{blend}.png"
    left, right = synthetic_set.input.images[1], synthetic_set.input.images[2]
    code, text, _ = run(["stitch", str(left), str(right),
                         "-o", str(out), "--blend", blend], capsys)
    assert code == 0 and json.loads(text)["blend"] == blend and out.is_file()


def test_stitch_bad_input_exits_2_and_writes_nothing(synthetic_set, tmp_path, capsys):
    out = tmp_path / "pano.png"
    left = str(synthetic_set.input.images[1])
    code, text, err = run(["stitch", left, str(tmp_path / "missing.jpg"), "-o", str(out)],
                          capsys)
    assert code == 2 and text == "" and "RIGHT" in err and "no such image file" in err
    assert len(err.splitlines()) == 1
    junk = tmp_path / "junk.jpg"
    junk.write_bytes(b"not an image")
    code, _, err = run(["stitch", left, str(junk), "-o", str(out)], capsys)
    assert code == 2 and "not a readable image" in err
    code, _, err = run(["stitch", str(tmp_path), left, "-o", str(out)], capsys)
    assert code == 2 and "LEFT" in err and "is a folder" in err
    code, _, err = run(["stitch", left, left, "-o", str(tmp_path / "pano.xyz")], capsys)
    assert code == 2 and "--output" in err and "extension" in err
    code, _, err = run(["stitch", left, left, "-o", str(tmp_path / "no" / "pano.png")], capsys)
    assert code == 2 and "does not exist" in err
    code, _, err = run(["stitch", left, left, "-o", str(tmp_path)], capsys)
    assert code == 2 and "--output" in err and "is a folder" in err
    assert not out.exists() and sorted(p.name for p in tmp_path.iterdir()) == ["junk.jpg"]


def test_stitch_too_few_matches_is_a_failed_estimate(synthetic_set, tmp_path, capsys):
    import cv2

    out = tmp_path / "pano.png"
    blank = tmp_path / "blank.png"
    cv2.imwrite(str(blank), np.full((480, 640, 3), 128, np.uint8))
    left = str(synthetic_set.input.images[1])
    code, text, err = run(["stitch", left, str(blank), "-o", str(out)], capsys)
    d = json.loads(text)
    assert code == 1 and err == "" and d["success"] is False and "too few matches" in d["reason"]
    assert d["output"] is None and d["matches"] < 8 and not out.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["blank.png"]


def test_stitch_unrelated_images_fail_cleanly(tmp_path, capsys):
    """Two unrelated photographs: whatever matches pass the ratio test, no broken output."""
    import cv2
    from skimage import data

    a, b = tmp_path / "a.png", tmp_path / "b.png"
    cv2.imwrite(str(a), data.astronaut()[..., ::-1])
    cv2.imwrite(str(b), np.ascontiguousarray(data.coffee()[..., ::-1]))
    out = tmp_path / "pano.png"
    code, text, err = run(["stitch", str(a), str(b), "-o", str(out)], capsys)
    d = json.loads(text)
    assert code == 1 and err == "" and not out.exists() and d["success"] is False
    assert d["reason"] and d["output"] is None
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.png", "b.png"]


def _matches_csv(tmp_path, sift_pair, outliers=0.4, n=None, seed=0):
    """SIFT matches (never the ground-truth correspondences), a fraction replaced by noise."""
    m = np.array(sift_pair.input.matches[:n])
    rng = np.random.default_rng(seed)
    k = int(outliers * len(m))
    m[:k, 2:] = rng.uniform([0, 0], [640, 480], (k, 2))
    f = tmp_path / "matches.csv"
    np.savetxt(f, m, delimiter=",", header="x1,y1,x2,y2", comments="")
    kept_inliers = int(np.count_nonzero(sift_pair.truth.inliers[:n][k:]))
    return f, kept_inliers


@pytest.mark.parametrize("method", ["clap", "ransac", "randomized_hough", "cv2_ransac"])
def test_fit_homography(synthetic_set, sift_pair, tmp_path, capsys, method):
    f, kept = _matches_csv(tmp_path, sift_pair)
    code, text, err = run(["fit", "homography", str(f), "--method", method, "--seed", "2"],
                          capsys)
    assert code == 0 and err == ""
    d = json.loads(text)
    assert set(d) >= {"model", "inliers", "success", "seconds", "matches", "threshold"}
    assert d["success"] is True and d["method"] == method and d["threshold"] == 3.0
    H = np.array(d["model"]["H"])
    # the ground-truth inliers left among the matches, give or take a few lucky outliers
    assert kept > 100 and H[2, 2] == 1.0 and 0.95 * kept <= d["inliers"] <= 1.05 * kept
    assert corner_error(H, synthetic_set.truth.H(1, 2), (640, 480)) < 2.0


def test_fit_homography_is_deterministic(sift_pair, tmp_path, capsys):
    f, _ = _matches_csv(tmp_path, sift_pair)
    outs = [json.loads(run(["fit", "homography", str(f), "--seed", "4"], capsys)[1])
            for _ in range(2)]
    for o in outs:
        o.pop("seconds")
    assert outs[0] == outs[1]


def test_fit_homography_bad_input_exits_2(sift_pair, tmp_path, capsys):
    f, _ = _matches_csv(tmp_path, sift_pair, outliers=0.0, n=5)
    code, text, err = run(["fit", "homography", str(f)], capsys)  # too few: a failed estimate
    d = json.loads(text)
    assert code == 1 and err == "" and d["success"] is False and d["model"] is None
    assert "too few matches" in d["reason"] and d["matches"] == 5
    g = tmp_path / "three.csv"
    g.write_text("1,2,3\n4,5,6\n")
    code, _, err = run(["fit", "homography", str(g)], capsys)
    assert code == 2 and "expected 4 values" in err
    code, _, err = run(["fit", "homography", str(tmp_path / "nope.csv")], capsys)
    assert code == 2 and "no such file" in err


@pytest.mark.parametrize("method", ["clap", "ransac"])
def test_fit_homography_failed_estimate_exits_1_like_fit_line(tmp_path, capsys, method):
    """One convention: a failed estimate is JSON with success false and exit 1, for every
    command (``fit line`` on degenerate points does the same).

    The matches are degenerate (every source point on one line: no 4-sample gives a
    homography). Random matches are no failure any more: the command reports the library's
    answer (issue 27: one success rule, fit's), and a homography through 4 or more of 60
    random matches passes it, in the library as in the command."""
    rng = np.random.default_rng(0)
    f = tmp_path / "degenerate.csv"
    x = rng.uniform(0, 640, 60)
    np.savetxt(f, np.c_[x, 0.5 * x + 10, rng.uniform(0, 640, (60, 2))], delimiter=",")
    code, text, err = run(["fit", "homography", str(f), "--method", method], capsys)
    d = json.loads(text)
    assert code == 1 and err == "" and d["success"] is False and d["reason"]
    assert d["matches"] == 60 and d["method"] == method
