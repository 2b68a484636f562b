"""Issue 27, "check once": each path from a user's call to ``fit`` checks its data once.

A spy replaces ``check_points`` (and ``check_array``, in the modules that call it directly)
in every module of the library that imported it, and counts the calls that check the
user's data: an array of the data's shape. The checks happen at the entry the user calls
(the command, ``estimate_homography``, ``fit``, ``fit_line``, ``segment``); what they pass
down is already checked. Each test runs its call once before the spy starts, so that the
modules the call imports lazily hold their ``check_points`` when the spy replaces it.
"""

import sys

import numpy as np
import pytest

import clap_unified
from clap_unified import _validation
from clap_unified.cli import main
from clap_unified.imaging.estimate import estimate_homography
from clap_unified.spaces import FundamentalSpace, HomographySpace

_ORIGINALS = {"check_points": _validation.check_points, "check_array": _validation.check_array}


@pytest.fixture
def spy_checks(monkeypatch):
    """``start()`` installs the spy and returns ``count(shape)``: how many times data of that
    shape was checked since."""
    calls = []

    def spy(fname):
        original = _ORIGINALS[fname]

        def checked(value, *args, **kwargs):
            calls.append((fname, np.shape(value)))
            return original(value, *args, **kwargs)
        checked.spy_of = fname
        return checked

    def start():
        calls.clear()
        for name, module in list(sys.modules.items()):
            if module is None or not (name == "clap_unified" or name.startswith("clap_unified.")):
                continue
            for fname, original in _ORIGINALS.items():
                if module is _validation and fname == "check_array":
                    continue  # check_points calls it: one check, not two
                held = getattr(module, fname, None)
                if held is original or getattr(held, "spy_of", None) == fname:
                    monkeypatch.setattr(module, fname, spy(fname))
        return lambda shape: sum(1 for _, s in calls if s == tuple(shape))
    return start


def _matches(n=120, seed=0):
    rng = np.random.default_rng(seed)
    src = rng.uniform(0, 640, (n, 2))
    dst = src @ np.array([[0.95, 0.05], [-0.05, 0.95]]).T + [20.0, -10.0]
    dst += rng.normal(0, 0.5, dst.shape)
    dst[: n // 4] = rng.uniform(0, 640, (n // 4, 2))
    return np.c_[src, dst]


def _once(spy_checks, call, shape):
    """The number of checks of data of ``shape`` in ``call()``, run after a warm-up call."""
    call()
    count = spy_checks()
    call()
    return count(shape)


def test_the_spy_counts_a_check(spy_checks):
    m = _matches()
    assert _once(spy_checks, lambda: HomographySpace().check_data(m), m.shape) == 1
    assert _once(spy_checks, lambda: [HomographySpace().check_data(m)] * 2, m.shape) == 1
    assert _once(spy_checks, lambda: [HomographySpace().check_data(m) for _ in range(2)],
                 m.shape) == 2


@pytest.mark.parametrize("method", ["clap", "ransac", "clap_paper", "randomized_hough"])
def test_estimate_homography_checks_the_matches_once(spy_checks, method):
    m = _matches()
    assert _once(spy_checks, lambda: estimate_homography(m, method, rng=0), m.shape) == 1


@pytest.mark.parametrize("method", ["clap", "ransac"])
def test_fit_homography_command_checks_the_matches_once(spy_checks, tmp_path, capsys, method):
    m = _matches()
    path = tmp_path / "m.csv"
    np.savetxt(path, m, delimiter=",")
    read = np.loadtxt(path, delimiter=",")
    assert _once(spy_checks, lambda: main(["fit", "homography", str(path), "-q",
                                           "--method", method]), read.shape) == 1
    capsys.readouterr()


@pytest.mark.parametrize("preset", [None, "paper", "own"])
def test_fit_checks_the_data_once(spy_checks, preset):
    m = _matches()
    assert _once(spy_checks, lambda: clap_unified.fit(HomographySpace(), m, "clap", rng=0,
                                                      preset=preset), m.shape) == 1


def test_fit_line_checks_the_points_once(spy_checks):
    rng = np.random.default_rng(0)
    x = rng.uniform(-5, 5, 80)
    pts = np.c_[x, 0.5 * x + 1]
    assert _once(spy_checks, lambda: clap_unified.fit_line(pts, "clap", threshold=0.05, rng=0),
                 pts.shape) == 1


def test_fit_fundamental_checks_the_matches_once(spy_checks):
    m = _matches()
    assert _once(spy_checks, lambda: clap_unified.fit(FundamentalSpace(), m, "ransac", rng=0,
                                                      threshold=1.0), m.shape) == 1


def test_segment_checks_the_data_once(spy_checks):
    rng = np.random.default_rng(0)
    x = rng.uniform(-5, 5, 60)
    pts = np.r_[np.c_[x[:30], 0.5 * x[:30] + 1], np.c_[x[30:], -x[30:]]]
    assert _once(spy_checks, lambda: clap_unified.segment(clap_unified.LineSpace(), pts, "ransac",
                                                          threshold=0.05, rng=0),
                 pts.shape) == 1


def test_segment_line_command_checks_the_points_once(spy_checks, tmp_path, capsys):
    rng = np.random.default_rng(0)
    x = rng.uniform(-5, 5, 60)
    pts = np.r_[np.c_[x[:30], 0.5 * x[:30] + 1], np.c_[x[30:], -x[30:]]]
    path = tmp_path / "p.csv"
    np.savetxt(path, pts, delimiter=",")
    read = np.loadtxt(path, delimiter=",")
    assert _once(spy_checks, lambda: main(["segment", "line", str(path), "-q", "--method",
                                           "ransac", "--threshold", "0.05"]), read.shape) == 1
    capsys.readouterr()


def test_the_checks_still_name_the_argument():
    """Bad data still fail at the entry, naming the user's argument."""
    with pytest.raises(ValueError, match="matches: need at least 4"):
        estimate_homography(_matches()[:3], "clap")
    with pytest.raises(ValueError, match="matches: contains 1 non-finite"):
        clap_unified.fit(HomographySpace(), np.r_[_matches()[:-1], [[np.nan, 0, 0, 0]]], "clap")
    with pytest.raises(ValueError, match="points: expected shape"):
        clap_unified.fit_line(np.zeros((5, 3)))
    with pytest.raises(ValueError, match="metric: expected one of"):
        clap_unified.fit_line(np.zeros((5, 2)), metric="nope")


@pytest.mark.parametrize("kind,method", [("homography", "clap"), ("homography", "ransac"),
                                         ("fundamental", "ransac")])
def test_segment_matches_checks_the_matches_once(spy_checks, kind, method):
    from clap_unified.imaging.segment_matches import segment_matches

    m = _matches()
    assert _once(spy_checks, lambda: segment_matches(m, kind, method, rng=0,
                                                     n_hypotheses=200), m.shape) == 1


@pytest.mark.parametrize("method", ["clap", "ransac"])
def test_localize2d_checks_the_observations_once(monkeypatch, method):
    """The 2D space checks its observations itself (type ids too): one call on the way."""
    from clap_unified.geometry import SE2
    from clap_unified.localization import localize2d
    from clap_unified.maps import LANDMARK_TYPES, load_field
    from clap_unified.spaces.landmarks2d import Landmark2DSpace

    field = load_field("adult")
    truth = SE2.from_xytheta(2.0, -1.0, 0.3)
    local = (np.linalg.inv(truth) @ np.c_[field.positions[:8], np.ones(8)].T).T[:, :2]
    obs = np.c_[[LANDMARK_TYPES.index(t) for t in field.types[:8]], local]
    calls = []
    original = Landmark2DSpace.check_data

    def counted(self, data):
        calls.append(np.shape(data))
        return original(self, data)
    monkeypatch.setattr(Landmark2DSpace, "check_data", counted)
    assert localize2d(obs, method=method, rng=0).success
    assert calls == [obs.shape]


@pytest.mark.parametrize("method", ["clap", "ransac"])
def test_align_correspondences_checks_them_once(spy_checks, method):
    from clap_unified.localization import align_correspondences

    rng = np.random.default_rng(0)
    src = rng.uniform(-3, 3, (30, 3))
    corr = np.c_[src, src + [0.5, -0.2, 0.1]]
    assert _once(spy_checks, lambda: align_correspondences(corr, method=method, rng=0),
                 corr.shape) == 1
