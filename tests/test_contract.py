"""One contract, run against every registered strategy in every space.

The way the geometry axioms run against every group: each (space, strategy)
pair the registry allows must give results of the right shapes, the same
result for the same seed, a failed result (not an exception) on degenerate
data, a ValueError naming the argument on bad input, frozen results, and
fields that describe the returned model.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from clap_unified import fit, strategy_names
from clap_unified.registry import get_strategy
from clap_unified.spaces import CircleSpace, LineSpace
from clap_unified.spaces.homography import HomographySpace
from clap_unified.spaces.rigid3d import Correspondence3DSpace
from clap_unified.viz import line_scene

N_HYPOTHESES = 300


def _line():
    pts = line_scene(150, 0.4, rng=0).input.points
    return LineSpace.for_data(pts), pts, np.zeros((30, 2)), 0.06, "points"


def _line_transfer():
    pts = line_scene(150, 0.4, rng=0).input.points
    return (LineSpace.for_data(pts, metric="transfer"), pts, np.zeros((30, 2)), 0.06,
            "points")


def _circle():
    g = np.random.default_rng(4)
    t = g.uniform(0, 2 * np.pi, 150)
    pts = np.c_[2.0 + 3.0 * np.cos(t), -1.0 + 3.0 * np.sin(t)] + g.normal(0, 0.01, (150, 2))
    pts[:60] = g.uniform(-3, 7, (60, 2))
    return CircleSpace(), pts, np.zeros((30, 2)), 0.05, "points"


def _homography():
    rng = np.random.default_rng(3)
    src = rng.uniform(0, 640, (150, 2))
    H = np.array([[0.95, 0.05, 20.0], [-0.04, 1.02, -10.0], [1e-5, 2e-5, 1.0]])
    p = np.c_[src, np.ones(150)] @ H.T
    dst = p[:, :2] / p[:, 2:] + rng.normal(0, 0.5, (150, 2))
    dst[:45] = rng.uniform(0, 640, (45, 2))
    matches = np.c_[src, dst]
    degenerate = np.tile([[10.0, 20.0, 30.0, 40.0]], (20, 1))
    return HomographySpace.for_data(matches), matches, degenerate, 3.0, "matches"


def _fundamental():
    from clap_unified.spaces import FundamentalSpace

    rng = np.random.default_rng(5)
    X = np.c_[rng.uniform(-2, 2, (150, 2)), rng.uniform(4, 8, 150)]
    x1 = 800 * X[:, :2] / X[:, 2:] + 320
    Y = X + [1.0, 0.2, 0.1]  # the second camera translated
    x2 = 800 * Y[:, :2] / Y[:, 2:] + 320 + rng.normal(0, 0.3, (150, 2))
    x2[:30] = rng.uniform(0, 640, (30, 2))  # 20 % outliers
    matches = np.c_[x1, x2]
    degenerate = np.tile([[10.0, 20.0, 30.0, 40.0]], (20, 1))
    return FundamentalSpace.for_data(matches), matches, degenerate, 1.0, "matches"


def _pose2d():
    from clap_unified.geometry import SE2
    from clap_unified.localization import load_field, simulate_observations
    from clap_unified.spaces.landmarks2d import Landmark2DSpace

    field = load_field("adult")
    obs = simulate_observations(field, SE2.from_xytheta(2.0, 1.0, 0.3),
                                false_positive_rate=0.3, rng=1).input.data
    t = obs[0, 0]
    degenerate = np.array([[t, 1.0, 0.0], [t, 1.0, 0.0], [t, 1.0, 0.0]])
    return Landmark2DSpace(field), obs, degenerate, 0.3, "observations"


def _pose3d():
    from clap_unified.localization.map3d import lab_map
    from clap_unified.localization.scene3d import mocap_trajectory, simulate_detections

    lab = lab_map()
    det = simulate_detections(lab, mocap_trajectory(20, rng=0)[4], outlier_ratio=0.4, rng=2)
    data = det.input.data
    degenerate = np.tile(data[:1], (5, 1))
    return lab.space(), data, degenerate, 0.15, "observations"


def _rigid3d():
    from clap_unified.geometry import so3_exp

    rng = np.random.default_rng(0)
    p = rng.uniform(-4, 4, (60, 3))
    q = p @ so3_exp([0.1, -0.2, 0.3]).T + [0.5, -1.0, 2.0] + rng.normal(0, 0.01, (60, 3))
    q[:25] = rng.uniform(-4, 4, (25, 3))
    degenerate = np.tile([[1.0, 2.0, 3.0, 1.0, 2.0, 3.0]], (10, 1))
    return Correspondence3DSpace(), np.c_[p, q], degenerate, 0.15, "correspondences"


def _observations():
    from clap_unified.spaces import ObservationSpace

    rng = np.random.default_rng(4)
    where = rng.uniform(-5, 5, (6, 2))
    seen = [np.c_[np.full(8, k % 3), where[k] + rng.normal(0, 0.03, (8, 2))] for k in range(6)]
    lone = np.c_[rng.integers(0, 3, 10), rng.uniform(-5, 5, (10, 2))]
    data = np.concatenate([*seen, lone])
    # every observation is a valid hypothesis: no sample can be degenerate
    return ObservationSpace(2), data, None, 0.15, "observations"


def _line_nd():
    from clap_unified.spaces import LineNDSpace

    g = np.random.default_rng(5)
    t = g.uniform(-5, 5, 150)
    pts = np.array([1.0, -2.0, 0.5]) + t[:, None] * np.array([0.6, 0.0, 0.8])
    pts += g.normal(0, 0.01, pts.shape)
    pts[:50] = g.uniform(-5, 5, (50, 3))
    return LineNDSpace.for_data(pts), pts, np.zeros((30, 3)), 0.05, "points"


def _skimage_circle():
    from skimage.measure import CircleModel

    from clap_unified.spaces import SkimageModelSpace

    _, pts, degenerate, threshold, _ = _circle()
    return SkimageModelSpace(CircleModel, 3), pts, degenerate, threshold, "data"


SPACES = {"line": _line, "line_nd": _line_nd, "line_transfer": _line_transfer,
          "homography": _homography,
          "fundamental": _fundamental,
          "pose2d": _pose2d, "pose3d": _pose3d, "rigid3d": _rigid3d,
          "observations": _observations, "circle": _circle, "skimage_circle": _skimage_circle}
#: Options a space needs that have no default there.
OPTIONS = {"observations": {"randomized_hough": {"cell_size": 0.2}},
           "skimage_circle": {"randomized_hough": {"cell_size": 0.1}}}
_CACHE: dict = {}


def problem(name):
    if name not in _CACHE:
        _CACHE[name] = SPACES[name]()
    return _CACHE[name]


def _pairs():
    out = []
    for name in SPACES:
        space = problem(name)[0]
        out += [(name, m) for m in strategy_names(space)]
    return out


PAIRS = _pairs()
IDS = [f"{s}-{m}" for s, m in PAIRS]


def run(name, method, data=None, **kw):
    space, good, _, threshold, _ = problem(name)
    kw.setdefault("threshold", threshold)
    kw.setdefault("n_hypotheses", N_HYPOTHESES)
    kw = {**OPTIONS.get(name, {}).get(method, {}), **kw}
    return fit(space, good if data is None else data, method, rng=kw.pop("rng", 7), **kw)


def test_every_space_has_the_three_strategies():
    for name in SPACES:
        names = strategy_names(problem(name)[0])
        assert {"clap", "ransac", "randomized_hough"} <= set(names), name


@pytest.mark.parametrize(("name", "method"), PAIRS, ids=IDS)
def test_shapes(name, method):
    space, data, *_ = problem(name)
    res = run(name, method)
    assert res.success, res.reason
    assert res.method == method and res.space is space
    assert res.model.shape == tuple(space.model_shape)
    assert res.inliers.shape == (len(data),) and res.inliers.dtype == bool
    assert res.support.dtype == bool and res.support.shape == (res.diagnostics["hypotheses"],)
    assert isinstance(res.clusters, tuple)
    assert np.isfinite(res.score) and res.diagnostics["seconds"] >= 0


@pytest.mark.parametrize(("name", "method"), PAIRS, ids=IDS)
def test_same_seed_same_result(name, method):
    a, b = run(name, method, rng=11), run(name, method, rng=11)
    assert np.array_equal(a.model, b.model)
    assert np.array_equal(a.inliers, b.inliers) and np.array_equal(a.support, b.support)
    assert a.score == b.score and len(a.clusters) == len(b.clusters)


@pytest.mark.parametrize(("name", "method"), PAIRS, ids=IDS)
def test_degenerate_data_is_a_failed_result(name, method):
    _, _, degenerate, *_ = problem(name)
    if degenerate is None:
        pytest.skip(f"no sample of the {name} space is degenerate")
    res = run(name, method, data=degenerate)
    assert not res.success and not res and res.model is None
    assert isinstance(res.reason, str) and res.reason and res.reason != "ok"
    assert res.inliers.shape == (len(degenerate),) and not res.inliers.any()


@pytest.mark.parametrize(("name", "method"), PAIRS, ids=IDS)
def test_bad_input_names_the_argument(name, method):
    _, data, _, _, data_name = problem(name)
    nan = np.array(data, dtype=float)
    nan[1, -1] = np.nan
    with pytest.raises(ValueError, match=data_name):
        run(name, method, data=nan)
    with pytest.raises(ValueError, match=data_name):
        run(name, method, data=np.asarray(data)[:, :-1])
    with pytest.raises(ValueError, match="threshold"):
        run(name, method, threshold=-1.0)
    with pytest.raises(ValueError, match="n_hypotheses"):
        run(name, method, n_hypotheses=0)
    with pytest.raises(ValueError, match="no_such_option"):
        run(name, method, no_such_option=1)


@pytest.mark.parametrize("name", list(SPACES))
def test_unknown_or_foreign_method_names_method(name):
    with pytest.raises(ValueError, match="method"):
        run(name, "no_such_method")
    space = problem(name)[0]
    for other in strategy_names():
        if other not in strategy_names(space):
            with pytest.raises(ValueError, match="method"):
                run(name, other)


@pytest.mark.parametrize(("name", "method"), PAIRS, ids=IDS)
def test_results_are_frozen(name, method):
    res = run(name, method)
    with pytest.raises(dataclasses.FrozenInstanceError):
        res.model = None
    for array in (res.model, res.inliers, res.support):
        with pytest.raises(ValueError, match="read-only"):
            array[(0,) * array.ndim] = 0
    with pytest.raises(TypeError, match="read-only"):
        res.diagnostics["seconds"] = 0.0
    for c in res.clusters:
        with pytest.raises(dataclasses.FrozenInstanceError):
            c.support = 0
        assert not c.model.flags.writeable and not c.members.flags.writeable
    changed = res.replace(diagnostics={"note": 1})
    assert changed.diagnostics["note"] == 1 and "note" not in res.diagnostics


@pytest.mark.parametrize(("name", "method"), PAIRS, ids=IDS)
@pytest.mark.parametrize("refine", [True, False])
def test_fields_describe_the_returned_model(name, method, refine):
    space, data, *_ = problem(name)
    res = run(name, method, refine=refine)
    data = space.check_data(data)
    residuals = space.residuals(res.model[None], data)[0]
    assert np.array_equal(res.inliers, residuals < res.threshold)
    if res.clusters and not refine:
        assert np.array_equal(res.model, res.clusters[0].model)
    strategy = get_strategy(method)
    if strategy.uses_hypotheses and res.diagnostics["hypotheses"]:  # RANSAC may draw its own
        assert res.support.any()
        assert set(np.flatnonzero(res.support)) <= set(range(res.diagnostics["hypotheses"]))
    if method == "ransac":  # scored again after refinement
        assert res.score == res.n_inliers
    elif method in ("clap", "randomized_hough"):
        assert res.score == res.clusters[0].support
        assert np.array_equal(np.flatnonzero(res.support), np.sort(res.clusters[0].members))
