"""The 3D experiment of the paper: the symmetric field map, the outcome counts, the protocol."""

import importlib

import numpy as np
import pytest

from clap_unified.geometry import SE3, so3_exp
from clap_unified.localization.map3d import FIELD_MIRROR, GOAL_HEIGHT, field_map, lab_map
from clap_unified.localization.scene3d import (
    DetectionInput3D,
    mocap_trajectory,
    simulate_detections,
)
from clap_unified.reproduce import exp_localization as exp
from clap_unified.reproduce.exp_localization import (
    outcome_numbers,
    pose_outcome,
    run_localization3d,
    triplet_hypotheses,
)
from clap_unified.result import ConsensusResult

# the module (the package re-exports the function under the same name)
localize3d_module = importlib.import_module("clap_unified.localization.localize3d")

FIELD = field_map()
TRUTH = SE3.from_rt(so3_exp([0.02, 0.26, 0.3]), [3.0, 1.0, 1.25])


def test_field_map_has_both_halves_and_both_goals():
    assert len(FIELD) == 35 and FIELD.name == "field-adult"
    bars = FIELD.positions[FIELD.types == "crossbar"]
    assert sorted(map(tuple, bars.round(6).tolist())) == [
        (-7.0, -1.3, GOAL_HEIGHT["adult"]), (-7.0, 1.3, GOAL_HEIGHT["adult"]),
        (7.0, -1.3, GOAL_HEIGHT["adult"]), (7.0, 1.3, GOAL_HEIGHT["adult"])]
    assert np.all(FIELD.positions[FIELD.types != "crossbar", 2] == 0.0)
    assert "marker" not in set(FIELD.types.tolist())   # no symmetry-breaking wall markers
    assert len(field_map("kid")) == 35
    with pytest.raises(ValueError, match="size"):
        field_map("huge")


def test_field_map_is_symmetric_under_the_half_turn():
    turned = FIELD.positions @ FIELD_MIRROR[:3, :3].T
    for kind in set(FIELD.types.tolist()):
        a = np.sort(FIELD.positions[FIELD.types == kind].round(9), axis=0)
        b = np.sort(turned[FIELD.types == kind].round(9), axis=0)
        np.testing.assert_array_equal(a, b)
    # the lab map is not: it has no mirror image
    lab = lab_map()
    assert not np.allclose(np.sort(lab.positions @ FIELD_MIRROR[:3, :3].T, axis=0),
                           np.sort(lab.positions, axis=0))


def test_pose_and_mirror_explain_the_detections_equally_on_the_field():
    det = simulate_detections(FIELD, TRUTH, outlier_ratio=0.5, rng=3)
    space = FIELD.space()
    r = space.residuals(np.stack([TRUTH, FIELD_MIRROR @ TRUTH]), det.input.data)
    np.testing.assert_allclose(r[0], r[1], atol=1e-9)
    assert np.count_nonzero(r[0] < 0.15) >= np.count_nonzero(~det.truth.is_outlier) - 1


def test_a_failed_result_is_none_never_wrong():
    failed = ConsensusResult.failure("clap", "no cluster", 10, 0, FIELD.space())
    for mirror in (None, FIELD_MIRROR):
        out = pose_outcome(failed, TRUTH, mirror)
        assert out == {"e_t_m": None, "e_r_deg": None, "outcome": "none", "mirror": False}
    assert pose_outcome(None, TRUTH)["outcome"] == "none"


def test_outcomes_ok_coarse_wrong_and_mirror():
    def moved(t, deg=0.0):
        return TRUTH @ SE3.from_rt(so3_exp([0.0, 0.0, np.radians(deg)]), [t, 0.0, 0.0])

    assert pose_outcome(moved(0.02, 0.5), TRUTH, FIELD_MIRROR)["outcome"] == "ok"
    assert pose_outcome(moved(0.2), TRUTH, FIELD_MIRROR)["outcome"] == "coarse"
    assert pose_outcome(moved(0.02, 3.0), TRUTH, FIELD_MIRROR)["outcome"] == "coarse"
    far = pose_outcome(moved(2.0), TRUTH, FIELD_MIRROR)
    assert far["outcome"] == "wrong" and not far["mirror"]
    assert pose_outcome(moved(0.0, 8.0), TRUTH, FIELD_MIRROR)["outcome"] == "wrong"
    twin = pose_outcome(FIELD_MIRROR @ moved(0.1, 1.0), TRUTH, FIELD_MIRROR)
    assert twin["outcome"] == "wrong" and twin["mirror"]
    # without a symmetry there is no mirror to count
    assert not pose_outcome(FIELD_MIRROR @ TRUTH, TRUTH)["mirror"]


def test_outcome_numbers_count_no_pose_apart_from_wrong_pose():
    rows = ([{"outcome": "none", "mirror": False, "e_t_m": None}] * 3
            + [{"outcome": "wrong", "mirror": True, "e_t_m": 14.0}]
            + [{"outcome": "wrong", "mirror": False, "e_t_m": 3.0}]
            + [{"outcome": "ok", "mirror": False, "e_t_m": 0.01}] * 4
            + [{"outcome": "coarse", "mirror": False, "e_t_m": 0.2}])
    n = outcome_numbers(rows)
    assert set(n) == {"n", "ok", "wrong", "none", "mirror", "median_cm"}
    assert (n["n"], n["ok"], n["wrong"], n["none"], n["mirror"]) == (10, 0.4, 0.2, 0.3, 0.1)
    assert n["median_cm"] == pytest.approx(160.0)      # no pose counts as infinite
    assert outcome_numbers(rows[:3] * 2 + rows[5:7])["median_cm"] is None


def test_triplet_budget_enumerates_few_and_samples_many():
    space = FIELD.space()
    det = simulate_detections(FIELD, TRUTH, outlier_ratio=0.0, rng=1)
    few = triplet_hypotheses(space, det.input.data, 10_000, np.random.default_rng(0))
    assert few.exhaustive and few.n_draws == len(det) * (len(det) - 1) * (len(det) - 2) // 6
    assert triplet_hypotheses(space, det.input.data, None, None).exhaustive
    many = simulate_detections(FIELD, TRUTH, outlier_ratio=0.8, rng=1)
    a = triplet_hypotheses(space, many.input.data, 200, np.random.default_rng(5))
    b = triplet_hypotheses(space, many.input.data, 200, np.random.default_rng(5))
    assert not a.exhaustive and a.n_draws == 200
    np.testing.assert_array_equal(a.models, b.models)


PARAMS = {"ratios": [0.0, 0.6], "frames": 3, "mode": "local", "budget": 300,
          "budgets": [100], "correspondence_budgets": [100]}


def test_experiment_output_format_and_no_truth_reaches_an_estimator(monkeypatch):
    seen = []
    real = localize3d_module.localize3d

    def spy(observations, landmarks, **kw):
        seen.append((observations, kw.get("prior")))
        return real(observations, landmarks, **kw)

    monkeypatch.setattr(localize3d_module, "localize3d", spy)
    out = run_localization3d(PARAMS, 7)
    assert seen and all(isinstance(o, DetectionInput3D) for o, _ in seen)
    # the local gate is around the front end's guess, not the true pose
    priors = [p for o, p in seen if p is not None]
    assert priors and all(p is o.prior for o, p in seen if p is not None)
    assert {"data", "protocol", "deviations", "tables", "numbers", "variants"} <= set(out)
    assert out["data"].startswith("substitute")
    assert all(set(d) == {"paper", "here", "why"} for d in out["deviations"])
    rates = {"clap@0.00", "ransac@0.00", "clap@0.60", "ransac@0.60"}
    assert set(out["numbers"]) == rates | {"by_frame"}
    keys = {"n", "ok", "wrong", "none", "mirror", "median_cm"}
    assert all(set(out["numbers"][k]) == keys and out["numbers"][k]["n"] == 3 for k in rates)
    # each method's outcome per frame, in frame order (the paired test's input)
    frames = out["numbers"]["by_frame"]
    assert set(frames) == rates and all(len(f) == 3 and set(f) <= set("ocwn")
                                        for f in frames.values())
    kinds = {v["kind"] for v in out["variants"].values()}
    assert kinds == {"sensitivity", "extension", "control"}
    for v in out["variants"].values():
        assert set(v["numbers"]) == {"clap@0.60", "ransac@0.60", "by_frame"} and v["label"]
        assert all(set(x) == keys for k, x in v["numbers"].items() if k != "by_frame")
        assert set(v["numbers"]["by_frame"]) == {"clap@0.60", "ransac@0.60"}
    assert {"other_mode", "budget_100", "lab_map", "correspondences_100", "control_silent",
            "min_support_half", "min_support_double", "bandwidth_half", "bandwidth_double",
            "consensus", "control_ungated"} == set(out["variants"])
    assert out["variants"]["control_silent"]["numbers"]["clap@0.60"]["none"] == 1.0
    assert all(r["outcome"] in exp.OUTCOMES_3D for r in out["tables"]["errors"])
    # seeded: the same numbers again
    assert run_localization3d(PARAMS, 7)["variants"] == out["variants"]


def test_experiment_frames_do_not_depend_on_the_ratios_run():
    traj = mocap_trajectory(3, rng=np.random.default_rng([7, 0]))
    a = [d.input.data for o, f, _, d in exp._frames_3d(FIELD, traj, [0.0, 0.6], 3, 7, "t")
         if o == 0.6]
    b = [d.input.data for _, _, _, d in exp._frames_3d(FIELD, traj, [0.6], 3, 7, "t")]
    for x, y in zip(a, b, strict=True):
        np.testing.assert_array_equal(x, y)
