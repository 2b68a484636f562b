"""Presets, the one home of every default (issue 27): ``fit``, ``estimate_homography`` and
``clap-unified fit homography`` run the same preset and give the same answer, bit for bit."""

import dataclasses
import json
import pickle

import numpy as np
import pytest

from clap_unified import fit
from clap_unified.cli import main
from clap_unified.imaging.estimate import PROTOCOLS, estimate_homography
from clap_unified.presets import (
    PRESETS,
    Preset,
    get_preset,
    preset_names,
    protocol_presets,
    resolve_preset,
)
from clap_unified.spaces import HomographySpace, LineSpace
from clap_unified.spaces.homography import DEFAULT_THRESHOLD


def matches(seed=0, n=200, outliers=0.4):
    """Matches of a known homography, 0.5 px noise, then a fraction replaced by random ones."""
    rng = np.random.default_rng(seed)
    H = np.array([[0.95, 0.08, 40.0], [-0.06, 1.02, -25.0], [2e-5, -1e-5, 1.0]])
    src = rng.uniform([0, 0], [640, 480], (n, 2))
    p = np.c_[src, np.ones(n)] @ H.T
    dst = p[:, :2] / p[:, 2:] + rng.normal(0, 0.5, (n, 2))
    k = int(outliers * n)
    dst[:k] = rng.uniform([0, 0], [640, 480], (k, 2))
    return np.c_[src, dst]


def same(a, b):
    """The same estimate: success, reason, model, inliers, support, score and clusters."""
    assert (a.success, a.reason, a.n_inliers) == (b.success, b.reason, b.n_inliers)
    assert np.array_equal(a.model, b.model) and np.array_equal(a.inliers, b.inliers)
    assert np.array_equal(a.support, b.support) and a.score == b.score
    for c, d in zip(a.clusters, b.clusters, strict=True):
        assert (c.support, c.spread) == (d.support, d.spread)
        assert np.array_equal(c.model, d.model) and np.array_equal(c.members, d.members)
    assert repr(a.space) == repr(b.space) and a.threshold == b.threshold


def run_cli(args, capsys):
    code = main([str(a) for a in args])
    out, err = capsys.readouterr()
    return code, json.loads(out) if out else None, err


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_fit_without_a_preset_is_the_library_clap(seed):
    """``fit(HomographySpace(), m, "clap")`` is ``estimate_homography(m, "clap")``: before,
    fit ran CLAP's generic defaults in the pixel space (another model, other inliers)."""
    m = matches(seed, outliers=0.6)
    a = fit(HomographySpace(), m, "clap", rng=seed)
    b = estimate_homography(m, "clap", rng=seed)
    same(a, b)
    assert a.space.polish == 2.0 and a.diagnostics["hypotheses"] == 1000
    assert type(a.space.manifold).__name__ == "HomographyTransfer"


@pytest.mark.parametrize("preset,protocol", [("paper", "clap_paper"),
                                             ("clap_paper", "clap_paper"),
                                             ("densest", "clap_densest"),
                                             ("default", "clap")])
def test_named_preset_is_the_protocol(preset, protocol):
    m = matches(3)
    a = fit(HomographySpace(), m, "clap", rng=4, preset=preset)
    b = estimate_homography(m, protocol, rng=4)
    same(a, b.replace(method="clap"))
    assert b.method == protocol


@pytest.mark.parametrize("method,preset", [("clap", None), ("clap_paper", "paper"),
                                           ("ransac", None), ("randomized_hough", None),
                                           ("cv2_ransac", None)])
def test_fit_estimate_and_command_line_agree(tmp_path, capsys, method, preset):
    """The three entry points, one preset, one answer: model and inliers bit for bit."""
    if method == "cv2_ransac":
        pytest.importorskip("cv2")
    m = matches(5, outliers=0.5)
    f = tmp_path / "m.csv"
    np.savetxt(f, m, delimiter=",", header="x1,y1,x2,y2", comments="", fmt="%.17g")
    strategy = PROTOCOLS[method].get("strategy", method)
    a = fit(HomographySpace(), m, strategy, rng=7, preset=preset)
    b = estimate_homography(m, method, rng=7)
    same(a, b.replace(method=strategy))
    code, d, err = run_cli(["fit", "homography", f, "--method", method, "--seed", 7], capsys)
    lib = json.loads(json.dumps(b.to_dict()))
    assert code == (0 if b.success else 1) and err == ""
    assert (d["success"], d["inliers"], d["model"], d["clusters"]) == \
        (lib["success"], lib["inliers"], lib["model"], lib["clusters"])


def test_unknown_preset_names_the_argument_and_the_choices():
    m = matches(0)
    with pytest.raises(ValueError, match=r"^preset: unknown preset 'papr' of 'clap' in the "
                                         r"homography space; choices: 'default', 'paper', "
                                         r"'densest', 'clap', 'clap_paper', 'clap_densest', "
                                         r"'own'$"):
        fit(HomographySpace(), m, "clap", preset="papr")
    with pytest.raises(ValueError, match=r"^preset: .*'ransac'.*choices: 'default', 'paper', "
                                         r"'ransac', 'own'$"):
        fit(HomographySpace(), m, "ransac", preset="densest")
    pts = np.c_[np.arange(10.0), np.arange(10.0)]
    with pytest.raises(ValueError, match=r"^preset: .*line space; choices: 'default', 'own'$"):
        fit(LineSpace(), pts, "clap", preset="paper")
    with pytest.raises(ValueError, match="^preset: expected a name or a Preset"):
        fit(HomographySpace(), m, "clap", preset=3)
    with pytest.raises(ValueError, match=r"^preset: a preset of 'ransac'"):
        fit(HomographySpace(), m, "clap", preset=get_preset("homography", "ransac"))


def test_override_by_keyword_and_by_replace():
    """An argument or option overrides the preset, as it overrides the protocol of
    ``estimate_homography``; ``Preset.replace`` gives the same fit."""
    m = matches(6)
    paper = get_preset("homography", "clap", "paper")
    a = fit(HomographySpace(), m, "clap", rng=1, preset="paper", n_hypotheses=150, rounds=2,
            polish=True)
    b = estimate_homography(m, "clap_paper", rng=1, n_hypotheses=150, rounds=2, polish=True)
    c = fit(HomographySpace(), m, "clap", rng=1,
            preset=paper.replace(n_hypotheses=150, rounds=2, polish=True))
    same(a, b.replace(method="clap"))
    same(a, c)
    assert a.diagnostics["hypotheses"] == 150 and a.space.polish == 1.0
    base = fit(HomographySpace(), m, "clap", rng=1, preset="paper")
    assert base.diagnostics["hypotheses"] == 400 and base.space.polish is False
    # the preset itself is untouched and frozen
    assert paper.fit["n_hypotheses"] == 400 and paper.options["rounds"] == 5
    with pytest.raises(dataclasses.FrozenInstanceError):
        paper.name = "mine"
    with pytest.raises(TypeError, match="Preset.replace"):
        paper.options["rounds"] = 1
    # and it pickles (a process pool can take it), as the protocols do
    assert pickle.loads(pickle.dumps(paper)) == paper
    assert pickle.loads(pickle.dumps(PROTOCOLS)) == PROTOCOLS


def test_explicit_budget_raises_the_adaptive_cap_and_hypotheses_drop_it():
    m = matches(0)
    _, args, _ = resolve_preset(HomographySpace(), m, "clap", None, {}, {})
    assert (args["n_hypotheses"], args["max_hypotheses"]) == (1000, 10_000)
    _, args, _ = resolve_preset(HomographySpace(), m, "clap", None, {"n_hypotheses": 30000}, {})
    assert args["max_hypotheses"] == 30000
    _, args, _ = resolve_preset(HomographySpace(), m, "clap", None,
                                {"n_hypotheses": 30000, "max_hypotheses": 12000}, {})
    assert args["max_hypotheses"] == 12000
    _, args, _ = resolve_preset(HomographySpace(), m, "clap", None, {}, {},
                                hypotheses_given=True)
    assert "max_hypotheses" not in args
    hyps = HomographySpace().hypotheses(m, 300, rng=0)
    res = fit(HomographySpace(), m, "clap", hypotheses=hyps, rng=0)
    assert res.success and res.diagnostics["hypotheses"] == 300
    assert "adaptive_hypotheses" not in res.diagnostics


def test_a_configured_space_is_used_as_given():
    """No preset behind the user's back: a space built by hand runs the strategy's own
    defaults (as before presets), the same as ``preset="own"``; a space setting of a
    preset cannot be applied to it."""
    m = matches(2)
    space = HomographySpace.for_data(m, metric="lie")
    a = fit(space, m, "clap", rng=0)
    b = fit(space, m, "clap", rng=0, preset="own")
    same(a, b)
    # the strategy's own defaults, not the preset's: 1000 hypotheses, no adaptive second budget
    assert a.space is space and a.diagnostics["hypotheses"] == 1000
    assert "adaptive_hypotheses" not in a.diagnostics
    plain = fit(HomographySpace(), m, "clap", rng=0, preset="own", n_hypotheses=50)
    assert plain.space.is_plain and plain.diagnostics["hypotheses"] == 50
    with pytest.raises(ValueError, match="^polish: a setting of the space a preset builds"):
        fit(space, m, "clap", preset="paper", polish=True)
    # an explicit preset on a configured space: its options and budget, the space as given
    c = fit(space, m, "clap", rng=0, preset="paper")
    assert c.space is space and c.diagnostics["hypotheses"] == 400


def test_protocols_derive_from_the_presets():
    """One home: every protocol is its preset, every homography preset has the one
    threshold, and the protocol table cannot be edited around the presets."""
    presets = protocol_presets()
    assert list(PROTOCOLS) == list(presets)
    for name, p in presets.items():
        assert dict(PROTOCOLS[name]) == p.as_protocol()
        assert p.fit["threshold"] == DEFAULT_THRESHOLD
        assert get_preset("homography", p.strategy, name) is p
    assert all(p.fit.get("threshold") == DEFAULT_THRESHOLD for p in PRESETS.values())
    assert HomographySpace().default_threshold(None) == DEFAULT_THRESHOLD
    with pytest.raises(TypeError):
        PROTOCOLS["clap"]["threshold"] = 2.0
    assert preset_names(HomographySpace(), "magsac") == ("default", "peer", "magsac", "own")


def test_preset_rejects_unknown_keys():
    with pytest.raises(ValueError, match=r"^space: 'metrik' is not a setting"):
        Preset("x", "homography", "clap", space={"metrik": "lie"})
    with pytest.raises(ValueError, match=r"^fit: 'rng' is not one of fit's arguments"):
        Preset("x", "homography", "clap", fit={"rng": 0})


#: The protocols as ``imaging.estimate`` wrote them out before the presets existed (commit
#: 5b852aa): the presets must reproduce them, key for key.
PROTOCOLS_BEFORE_PRESETS = {
    "clap": {"frame": True, "metric": "transfer", "polish": 2.0, "n_hypotheses": 1000,
             "threshold": 3.0, "density": "knn", "k": 2, "bandwidth": 3.0, "suppress": 3.0,
             "rounds": 0, "max_clusters": 16, "min_support": 1, "select": "consensus",
             "n_refine": 3, "max_hypotheses": 10_000},
    "clap_paper": {"strategy": "clap", "frame": True, "metric": "lie", "polish": False,
                   "n_hypotheses": 400, "threshold": 3.0, "neighbourhood": "all",
                   "rounds": 5, "discard_fraction": 0.2, "bandwidth_quantile": 0.02},
    "clap_densest": {"strategy": "clap", "frame": True, "metric": "lie_linear", "polish": True,
                     "n_hypotheses": 400, "threshold": 3.0, "bandwidth_quantile": 0.02,
                     "rounds": 5, "discard_fraction": 0.2},
    "ransac": {"frame": False, "polish": False, "n_hypotheses": 1000, "threshold": 3.0},
    "randomized_hough": {"frame": True, "metric": "lie_linear", "polish": False,
                         "n_hypotheses": 400, "threshold": 3.0, "cell_size": 0.05},
    "cv2_ransac": {"frame": False, "refine": False, "n_hypotheses": 1000, "threshold": 3.0},
    "magsac": {"frame": False, "refine": False, "n_hypotheses": 1000, "threshold": 3.0},
    "usac_accurate": {"frame": False, "refine": False, "n_hypotheses": 1000, "threshold": 3.0},
    "usac_ransac_fixed": {"frame": False, "refine": False, "n_hypotheses": 1000,
                          "threshold": 3.0},
    "poselib": {"frame": False, "refine": False, "n_hypotheses": 100_000, "threshold": 3.0,
                "confidence": 0.9999, "min_iterations": 1000},
    "colmap": {"frame": False, "refine": False, "n_hypotheses": 100_000, "threshold": 3.0,
               "confidence": 0.9999, "min_iterations": 1000},
}


def test_presets_reproduce_the_protocols_written_before_them():
    from clap_unified.imaging.estimate import PROTOCOLS

    assert {k: dict(v) for k, v in PROTOCOLS.items()} == PROTOCOLS_BEFORE_PRESETS


@pytest.mark.parametrize("bad", ["abc", float("nan"), float("inf"), [5], 0])
def test_a_bad_budget_names_the_argument_before_any_preset(bad):
    m = matches(0)
    with pytest.raises(ValueError, match="^n_hypotheses"):
        fit(HomographySpace(), m, "clap", n_hypotheses=bad)
    with pytest.raises(ValueError, match="^max_hypotheses"):
        fit(HomographySpace(), m, "clap", max_hypotheses=bad)
