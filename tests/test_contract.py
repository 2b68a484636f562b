"""One contract, run against every registered strategy in every space.

As geomstats does for its manifolds: :class:`SpaceContract` holds the contract's
tests, and each space has one small subclass giving its fixtures (the space, good
data, degenerate data, a threshold, the name of its data argument). Each (space,
strategy) pair the registry allows must give results of the right shapes, the
same result for the same seed, a failed result (not an exception) on degenerate
data, a ValueError naming the argument on bad input, frozen results, and fields
that describe the returned model. A new space adds one subclass;
``test_every_public_space_has_a_contract`` fails for a public space without one.
"""

from __future__ import annotations

import dataclasses
import importlib
import inspect
import pkgutil

import numpy as np
import pytest

import clap_unified.spaces
from clap_unified import fit, strategy_names
from clap_unified.registry import get_strategy
from clap_unified.spaces import (
    CircleSpace,
    Correspondence3DSpace,
    FundamentalSpace,
    HomographySpace,
    Landmark3DSpace,
    LineNDSpace,
    LineSpace,
    ObservationSpace,
    SkimageModelSpace,
)
from clap_unified.spaces.base import HypothesisSpace
from clap_unified.spaces.landmarks2d import Landmark2DSpace
from clap_unified.viz import line_scene

N_HYPOTHESES = 300
_PROBLEMS: dict = {}  # contract class -> its problem, built once


class SpaceContract:
    """The contract's tests; a subclass per space gives :meth:`problem` and ``space_class``.

    Not collected itself (pytest collects classes named ``Test*``); every subclass
    is, with each test run once per strategy the registry allows in its space.
    """

    #: The hypothesis space class the subclass holds to the contract.
    space_class: type | None = None
    #: The name the data argument has in error messages.
    data_name = "data"
    #: Options a strategy needs in this space that have no default there.
    options: dict = {}
    #: The space is plain and ``fit``'s preset builds the one it runs in (same class).
    builds_space = False

    @staticmethod
    def problem():
        """``(space, good data, degenerate data or None, threshold)``."""
        raise NotImplementedError

    @classmethod
    def fixtures(cls):
        if cls not in _PROBLEMS:
            _PROBLEMS[cls] = cls.problem()
        return _PROBLEMS[cls]

    def pytest_generate_tests(self, metafunc):
        if "method" in metafunc.fixturenames:
            metafunc.parametrize("method", strategy_names(self.fixtures()[0]))

    def run(self, method, data=None, **kw):
        space, good, _, threshold = self.fixtures()
        kw.setdefault("threshold", threshold)
        kw.setdefault("n_hypotheses", N_HYPOTHESES)
        kw = {**self.options.get(method, {}), **kw}
        return fit(space, good if data is None else data, method, rng=kw.pop("rng", 7), **kw)

    def test_space_is_the_declared_class(self):
        assert type(self.fixtures()[0]) is self.space_class

    def test_the_space_has_the_three_strategies(self):
        names = strategy_names(self.fixtures()[0])
        assert {"clap", "ransac", "randomized_hough"} <= set(names)

    def test_shapes(self, method):
        space, data, *_ = self.fixtures()
        res = self.run(method)
        assert res.success, res.reason
        assert res.method == method
        assert res.space is space or (self.builds_space and type(res.space) is type(space))
        assert res.model.shape == tuple(space.model_shape)
        assert res.inliers.shape == (len(data),) and res.inliers.dtype == bool
        assert res.support.dtype == bool and res.support.shape == (res.diagnostics["hypotheses"],)
        assert isinstance(res.clusters, tuple)
        assert np.isfinite(res.score) and res.diagnostics["seconds"] >= 0

    def test_same_seed_same_result(self, method):
        a, b = self.run(method, rng=11), self.run(method, rng=11)
        assert np.array_equal(a.model, b.model)
        assert np.array_equal(a.inliers, b.inliers) and np.array_equal(a.support, b.support)
        assert a.score == b.score and len(a.clusters) == len(b.clusters)

    def test_degenerate_data_is_a_failed_result(self, method):
        _, _, degenerate, _ = self.fixtures()
        if degenerate is None:
            pytest.skip(f"no sample of the {self.space_class.__name__} space is degenerate")
        res = self.run(method, data=degenerate)
        assert not res.success and not res and res.model is None
        assert isinstance(res.reason, str) and res.reason and res.reason != "ok"
        assert res.inliers.shape == (len(degenerate),) and not res.inliers.any()

    def test_bad_input_names_the_argument(self, method):
        _, data, _, _ = self.fixtures()
        nan = np.array(data, dtype=float)
        nan[1, -1] = np.nan
        with pytest.raises(ValueError, match=self.data_name):
            self.run(method, data=nan)
        with pytest.raises(ValueError, match=self.data_name):
            self.run(method, data=np.asarray(data)[:, :-1])
        with pytest.raises(ValueError, match="threshold"):
            self.run(method, threshold=-1.0)
        with pytest.raises(ValueError, match="n_hypotheses"):
            self.run(method, n_hypotheses=0)
        with pytest.raises(ValueError, match="no_such_option"):
            self.run(method, no_such_option=1)

    def test_unknown_or_foreign_method_names_method(self):
        with pytest.raises(ValueError, match="method"):
            self.run("no_such_method")
        space = self.fixtures()[0]
        for other in strategy_names():
            if other not in strategy_names(space):
                with pytest.raises(ValueError, match="method"):
                    self.run(other)

    def test_results_are_frozen(self, method):
        res = self.run(method)
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

    @pytest.mark.parametrize("refine", [True, False])
    def test_fields_describe_the_returned_model(self, method, refine):
        space, data, *_ = self.fixtures()
        res = self.run(method, refine=refine)
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


# ------------------------------------------------------------ one subclass per space
class TestLine(SpaceContract):
    space_class = LineSpace
    data_name = "points"

    @staticmethod
    def problem():
        pts = line_scene(150, 0.4, rng=0).input.points
        return LineSpace.for_data(pts), pts, np.zeros((30, 2)), 0.06


class TestLineTransfer(SpaceContract):
    space_class = LineSpace
    data_name = "points"

    @staticmethod
    def problem():
        pts = line_scene(150, 0.4, rng=0).input.points
        return LineSpace.for_data(pts, metric="transfer"), pts, np.zeros((30, 2)), 0.06


class TestLineND(SpaceContract):
    space_class = LineNDSpace

    data_name = "points"

    @staticmethod
    def problem():
        g = np.random.default_rng(5)
        t = g.uniform(-5, 5, 150)
        pts = np.array([1.0, -2.0, 0.5]) + t[:, None] * np.array([0.6, 0.0, 0.8])
        pts += g.normal(0, 0.01, pts.shape)
        pts[:50] = g.uniform(-5, 5, (50, 3))
        return LineNDSpace.for_data(pts), pts, np.zeros((30, 3)), 0.05


def _circle_points():
    g = np.random.default_rng(4)
    t = g.uniform(0, 2 * np.pi, 150)
    pts = np.c_[2.0 + 3.0 * np.cos(t), -1.0 + 3.0 * np.sin(t)] + g.normal(0, 0.01, (150, 2))
    pts[:60] = g.uniform(-3, 7, (60, 2))
    return pts


class TestCircle(SpaceContract):
    space_class = CircleSpace
    data_name = "points"

    @staticmethod
    def problem():
        return CircleSpace(), _circle_points(), np.zeros((30, 2)), 0.05


class TestSkimageCircle(SpaceContract):
    space_class = SkimageModelSpace

    options = {"randomized_hough": {"cell_size": 0.1}}

    @staticmethod
    def problem():
        from skimage.measure import CircleModel

        return SkimageModelSpace(CircleModel, 3), _circle_points(), np.zeros((30, 2)), 0.05


class TestHomography(SpaceContract):
    space_class = HomographySpace
    data_name = "matches"

    @staticmethod
    def problem():
        rng = np.random.default_rng(3)
        src = rng.uniform(0, 640, (150, 2))
        H = np.array([[0.95, 0.05, 20.0], [-0.04, 1.02, -10.0], [1e-5, 2e-5, 1.0]])
        p = np.c_[src, np.ones(150)] @ H.T
        dst = p[:, :2] / p[:, 2:] + rng.normal(0, 0.5, (150, 2))
        dst[:45] = rng.uniform(0, 640, (45, 2))
        matches = np.c_[src, dst]
        degenerate = np.tile([[10.0, 20.0, 30.0, 40.0]], (20, 1))
        return HomographySpace.for_data(matches), matches, degenerate, 3.0


class TestPlainHomography(TestHomography):
    """``fit(HomographySpace(), ...)``: each strategy's preset builds the space it runs in."""

    builds_space = True

    @staticmethod
    def problem():
        space, matches, degenerate, threshold = TestHomography.problem()
        return HomographySpace(), matches, degenerate, threshold


class TestFundamental(SpaceContract):
    space_class = FundamentalSpace

    data_name = "matches"

    @staticmethod
    def problem():
        rng = np.random.default_rng(5)
        X = np.c_[rng.uniform(-2, 2, (150, 2)), rng.uniform(4, 8, 150)]
        x1 = 800 * X[:, :2] / X[:, 2:] + 320
        Y = X + [1.0, 0.2, 0.1]  # the second camera translated
        x2 = 800 * Y[:, :2] / Y[:, 2:] + 320 + rng.normal(0, 0.3, (150, 2))
        x2[:30] = rng.uniform(0, 640, (30, 2))  # 20 % outliers
        matches = np.c_[x1, x2]
        degenerate = np.tile([[10.0, 20.0, 30.0, 40.0]], (20, 1))
        return FundamentalSpace.for_data(matches), matches, degenerate, 1.0


class TestPose2D(SpaceContract):
    space_class = Landmark2DSpace

    data_name = "observations"

    @staticmethod
    def problem():
        from clap_unified.geometry import SE2
        from clap_unified.localization import load_field, simulate_observations

        field = load_field("adult")
        obs = simulate_observations(field, SE2.from_xytheta(2.0, 1.0, 0.3),
                                    false_positive_rate=0.3, rng=1).input.data
        t = obs[0, 0]
        degenerate = np.array([[t, 1.0, 0.0], [t, 1.0, 0.0], [t, 1.0, 0.0]])
        return Landmark2DSpace(field), obs, degenerate, 0.3


class TestPose3D(SpaceContract):
    space_class = Landmark3DSpace

    data_name = "observations"

    @staticmethod
    def problem():
        from clap_unified.localization.map3d import lab_map
        from clap_unified.localization.scene3d import mocap_trajectory, simulate_detections

        lab = lab_map()
        det = simulate_detections(lab, mocap_trajectory(20, rng=0)[4], outlier_ratio=0.4, rng=2)
        data = det.input.data
        degenerate = np.tile(data[:1], (5, 1))
        return lab.space(), data, degenerate, 0.15


class TestRigid3D(SpaceContract):
    space_class = Correspondence3DSpace
    data_name = "correspondences"

    @staticmethod
    def problem():
        from clap_unified.geometry import so3_exp

        rng = np.random.default_rng(0)
        p = rng.uniform(-4, 4, (60, 3))
        q = p @ so3_exp([0.1, -0.2, 0.3]).T + [0.5, -1.0, 2.0] + rng.normal(0, 0.01, (60, 3))
        q[:25] = rng.uniform(-4, 4, (25, 3))
        degenerate = np.tile([[1.0, 2.0, 3.0, 1.0, 2.0, 3.0]], (10, 1))
        return Correspondence3DSpace(), np.c_[p, q], degenerate, 0.15


class TestObservations(SpaceContract):
    space_class = ObservationSpace

    data_name = "observations"
    options = {"randomized_hough": {"cell_size": 0.2}}

    @staticmethod
    def problem():
        rng = np.random.default_rng(4)
        where = rng.uniform(-5, 5, (6, 2))
        seen = [np.c_[np.full(8, k % 3), where[k] + rng.normal(0, 0.03, (8, 2))]
                for k in range(6)]
        lone = np.c_[rng.integers(0, 3, 10), rng.uniform(-5, 5, (10, 2))]
        data = np.concatenate([*seen, lone])
        # every observation is a valid hypothesis: no sample can be degenerate
        return ObservationSpace(2), data, None, 0.15


# ----------------------------------------------------------- the list cannot go stale
def public_spaces() -> set:
    """Every concrete hypothesis space a module of ``clap_unified.spaces`` defines."""
    found = set()
    for info in pkgutil.iter_modules(clap_unified.spaces.__path__, "clap_unified.spaces."):
        module = importlib.import_module(info.name)
        for name, obj in vars(module).items():
            if (inspect.isclass(obj) and issubclass(obj, HypothesisSpace)
                    and obj.__module__ == module.__name__ and not name.startswith("_")
                    and not inspect.isabstract(obj)):
                found.add(obj)
    return found


def contracts(base=SpaceContract) -> list:
    """Every subclass of ``base``, at any depth."""
    return [c for sub in base.__subclasses__() for c in (sub, *contracts(sub))]


def spaces_without_contract(spaces, contract_classes) -> list[str]:
    covered = {c.space_class for c in contract_classes}
    return sorted(s.__name__ for s in spaces if s not in covered)


def test_every_public_space_has_a_contract():
    missing = spaces_without_contract(public_spaces(), contracts())
    assert not missing, (f"spaces with no subclass of SpaceContract in {__file__}: {missing}; "
                         "add one giving its fixtures")


def test_a_space_without_a_contract_is_reported():
    class Unheld(CircleSpace):
        pass

    assert spaces_without_contract(public_spaces() | {Unheld}, contracts()) == ["Unheld"]
    assert CircleSpace in public_spaces() and HypothesisSpace not in public_spaces()
