import numpy as np
import pytest

from clap_unified.clap import clap
from clap_unified.geometry import SE2
from clap_unified.localization import LANDMARK_TYPES, load_field
from clap_unified.ransac import ransac
from clap_unified.spaces import enumerate_hypotheses
from clap_unified.spaces.base import Capabilities, HypothesisSpace
from clap_unified.spaces.landmarks2d import Landmark2DSpace, observations_array

FIELD = load_field("adult")


def observe(truth, names_idx, noise=0.02, n_false=0, seed=0):
    """Observations (type_id, x, y) in the robot frame of chosen landmarks plus false ones."""
    rng = np.random.default_rng(seed)
    Tinv = np.linalg.inv(truth)
    marks = FIELD.positions[names_idx]
    local = (Tinv @ np.c_[marks, np.ones(len(marks))].T).T[:, :2]
    local += rng.normal(0, noise, local.shape)
    ids = [LANDMARK_TYPES.index(t) for t in FIELD.types[names_idx]]
    obs = np.c_[ids, local]
    false = np.c_[rng.integers(0, 3, n_false), rng.uniform(-4, 4, (n_false, 2))]
    return np.r_[obs, false]


def pose_error(T, truth):
    x, y, th = SE2.to_xytheta(np.linalg.inv(truth) @ T)
    return np.hypot(x, y), abs(np.degrees(th))


def test_clap_global_recovers_pose_with_40_percent_false_positives():
    truth = SE2.from_xytheta(3.0, 1.5, 0.4)
    mirror = SE2.from_xytheta(0.0, 0.0, np.pi) @ truth  # the field's 180 degree symmetry
    idx = np.flatnonzero((FIELD.positions[:, 0] > 1.0) & (FIELD.types != "goal_post"))[:6]
    data = observe(truth, idx, n_false=4, seed=1)  # 4 false of 10 = 40 %
    space = Landmark2DSpace(FIELD)
    hyps = enumerate_hypotheses(space, data)
    res = clap(space, data, hypotheses=hyps, bandwidth=0.2, threshold=0.2)
    assert res.success and res.n_inliers == 6
    # without a prior the symmetric field allows exactly two answers: both must be on top
    top = res.clusters[:2]
    rest = [c.support for c in res.clusters[2:]]
    assert top[0].support == top[1].support > 2 * max(rest, default=0)
    for target in (truth, mirror):
        dist, ang = min((pose_error(c.model, target) for c in top), key=lambda e: e[0])
        assert dist < 0.10 and ang < 2.0
    dist, ang = min(pose_error(res.model, t) for t in (truth, mirror))
    assert dist < 0.10 and ang < 2.0
    # RANSAC on the identical candidates, measured beside it
    r = ransac(space, data, hypotheses=hyps, n_hypotheses=len(hyps), threshold=0.2)
    assert r.success and min(pose_error(r.model, t)[0] for t in (truth, mirror)) < 0.10


def test_symmetric_scene_reports_both_mirror_poses():
    truth = SE2.from_xytheta(0.5, 0.0, 0.0)
    idx = np.flatnonzero(FIELD.types == "X")  # the two centre-circle crossings: symmetric
    data = observe(truth, idx, noise=0.0)
    space = Landmark2DSpace(FIELD)
    res = clap(space, data, hypotheses=enumerate_hypotheses(space, data), bandwidth=0.1,
               min_support=1, threshold=0.1)
    poses = [SE2.to_xytheta(c.model) for c in res.clusters]
    assert len(poses) == 2
    mirror = SE2.from_xytheta(-0.5, 0.0, np.pi)
    errs = sorted(min(pose_error(c.model, t)[0] for t in (truth, mirror)) for c in res.clusters)
    assert errs[-1] < 1e-9
    assert res.diagnostics["runner_up_ratio"] == pytest.approx(1.0)


def test_refit_uses_associations_and_bad_observations_are_named():
    truth = SE2.from_xytheta(-2.0, 1.0, -0.7)
    idx = np.flatnonzero(FIELD.positions[:, 0] < -3.0)[:5]
    data = observe(truth, idx, noise=0.0)
    space = Landmark2DSpace(FIELD)
    start = truth @ SE2.from_xytheta(0.05, -0.05, 0.02)
    np.testing.assert_allclose(space.refit(data, initial=start), truth, atol=1e-9)
    assert space.refit(data) is None
    with pytest.raises(ValueError, match="observations: column 0"):
        space.check_data(np.array([[9.0, 0, 0], [0.0, 1, 1]]))
    with pytest.raises(ValueError, match="unknown type"):
        observations_array([{"type": "corner", "x": 0, "y": 0}])


class _PlainRefit(Landmark2DSpace):
    """The base route: inliers_of, then refit(data[inliers]) searching the landmarks again."""

    declared = Capabilities(prior_hypotheses=True, grid=True)
    refit_steps = HypothesisSpace.refit_steps


@pytest.mark.parametrize("seed", range(6))
def test_shared_association_refit_equals_the_plain_refit(seed):
    from clap_unified.refine import refit_on_inliers

    rng = np.random.default_rng(seed)
    truth = SE2.from_xytheta(rng.uniform(-4, 4), rng.uniform(-3, 3), rng.uniform(-3, 3))
    data = observe(truth, rng.choice(len(FIELD.positions), 6, replace=False), n_false=3,
                   seed=seed)
    start = truth @ SE2.from_xytheta(0.2, -0.1, 0.08)
    fast, plain = Landmark2DSpace(FIELD), _PlainRefit(FIELD)
    for threshold in (0.1, 0.3, 1.0):
        model, inliers = refit_on_inliers(fast, start, data, threshold)
        model0, inliers0 = refit_on_inliers(plain, start, data, threshold)
        assert np.array_equal(model, model0) and np.array_equal(inliers, inliers0)
    with pytest.raises(ValueError, match="observations: contains"):
        fast.check_data(np.r_[data, [[0.0, np.nan, 1.0]]])
