"""Review of the fit redesign: defects a reviewer found, each kept as a test of its fix."""

from __future__ import annotations

import dataclasses
import json
import pickle

import numpy as np
import pytest

from clap_unified import fit
from clap_unified.cli import main
from clap_unified.geometry import SE2
from clap_unified.localization import load_field, simulate_observations
from clap_unified.registry import Strategy, register_strategy, unregister_strategy
from clap_unified.result import Cluster, Consensus
from clap_unified.spaces import LineSpace
from clap_unified.viz import line_scene


@pytest.fixture(scope="module")
def line_problem():
    pts = line_scene(150, 0.4, rng=0).input.points
    space = LineSpace.for_data(pts)
    hyps = space.hypotheses(pts, 300, rng=np.random.default_rng(2))
    prior = fit(space, pts, "clap", threshold=0.06, rng=0).model
    radius = float(np.quantile(space.manifold.distance(prior, hyps.models), 0.3))
    return space, pts, hyps, prior, radius


def test_ransac_best_hypothesis_indexes_the_full_hypothesis_set(line_problem):
    space, pts, hyps, prior, radius = line_problem
    res = fit(space, pts, "ransac", threshold=0.06, rng=3, hypotheses=hyps, prior=prior,
              radius=radius)
    assert res.success
    best = res.diagnostics["best_hypothesis"]
    assert res.support[best]
    assert np.array_equal(res.clusters[0].members, [best])


def test_radius_of_wrong_shape_is_a_value_error_naming_radius(line_problem):
    space, pts, hyps, prior, _ = line_problem
    with pytest.raises(ValueError, match="radius"):
        fit(space, pts, "ransac", threshold=0.06, rng=0, prior=prior, radius=(0.1, 0.2))


def test_failed_result_still_counts_the_hypotheses(line_problem):
    space, pts, hyps, prior, radius = line_problem
    res = fit(space, pts, "clap", threshold=0.06, hypotheses=hyps, min_support=10_000)
    assert not res.success
    assert res.diagnostics.get("hypotheses") == len(hyps)


def test_a_strategy_may_be_an_unhashable_callable(line_problem):
    space, pts, *_ = line_problem

    @dataclasses.dataclass
    class First:
        k: int = 0

        def __call__(self, space, data, hypotheses, *, threshold, prior=None, radius=None,
                     rng=None, n_hypotheses=0):
            support = np.zeros(len(hypotheses), bool)
            support[self.k] = True
            m = hypotheses.models[self.k]
            return Consensus(m, (Cluster(m, 1, 0.0, np.array([self.k])),), support, 1.0)

    register_strategy(Strategy("review_unhashable", First()))
    try:
        res = fit(space, pts, "review_unhashable", threshold=0.06, rng=0)
    finally:
        unregister_strategy("review_unhashable")
    assert res.success


def test_a_pickled_result_stays_frozen(line_problem):
    space, pts, *_ = line_problem
    res = pickle.loads(pickle.dumps(fit(space, pts, "clap", threshold=0.06, rng=0)))
    assert not res.model.flags.writeable
    assert not res.inliers.flags.writeable
    assert not res.clusters[0].model.flags.writeable


def test_cli_prior_with_negative_x(tmp_path, capsys):
    truth = SE2.from_xytheta(-3.0, -1.0, 0.2)
    obs = simulate_observations(load_field("adult"), truth, false_positive_rate=0.0, rng=1)
    f = tmp_path / "obs.json"
    f.write_text(json.dumps(obs.input.to_dicts()))
    try:
        code = main(["localize2d", str(f), "--prior", "-2.9,-1.1,0.25"])
    except SystemExit as exc:  # argparse's error exit
        code = exc.code
    out = capsys.readouterr().out
    assert code == 0
    assert json.loads(out)["model"]["x"] == pytest.approx(-3.0, abs=0.1)
