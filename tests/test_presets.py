"""Presets, the one home of every default (issue 27): ``fit``, ``estimate_homography`` and
``clap-unified fit homography`` run the same preset and give the same answer, bit for bit."""

import dataclasses
import json
import pickle
import re

import numpy as np
import pytest

from clap_unified import fit
from clap_unified.cli import main
from clap_unified.imaging.estimate import PROTOCOLS, estimate_homography
from clap_unified.presets import (
    PRESETS,
    TASK_PRESETS,
    Preset,
    get_preset,
    preset_names,
    protocol_presets,
    resolve_preset,
    space_conflicts,
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
    # an explicit preset on the space it would build itself: its options and budget, the
    # space as given, the same answer as the preset building it from a plain space
    c = fit(space, m, "clap", rng=0, preset="paper")
    assert c.space is space and c.diagnostics["hypotheses"] == 400
    same(c, fit(HomographySpace(), m, "clap", rng=0, preset="paper"))


@pytest.mark.parametrize("build,method,preset,conflict", [
    (lambda m: HomographySpace.for_data(m, metric="lie_linear"), "clap", "paper",
     r"metric='lie_linear' \(the preset's 'lie'\)"),
    (lambda m: HomographySpace.for_data(m, metric="transfer", polish=True), "clap", "paper",
     r"metric='transfer' \(the preset's 'lie'\), polish=True \(the preset's False\)"),
    (lambda m: HomographySpace(polish=True), "ransac", "paper",
     r"polish=True \(the preset's False\)"),
    (lambda m: HomographySpace(polish=True), "clap", "default",
     r"frame=False \(the preset's True\), polish=True \(the preset's 2.0\)"),
    (lambda m: HomographySpace.for_data(m), "magsac", "peer",
     r"frame=True \(the preset's False\)"),
])
def test_a_named_preset_on_a_configured_space_is_never_half_applied(build, method, preset,
                                                                     conflict):
    """Issue 27: a named preset given with a space configured by hand used to skip the
    preset's space settings in silence (its budget and options ran on another space). Now
    the preset applies whole, when the space is the one it builds, or not at all: a
    ``ValueError`` naming ``preset`` and each conflicting setting, with the ways out."""
    m = matches(2)
    space = build(m)
    with pytest.raises(ValueError, match=rf"^preset: '\w+' of '{method}' builds its own "
                                         rf"homography space, .*differs: {conflict}\. Pass a "
                                         r"plain HomographySpace\(\).*preset='own'.*\.replace"):
        fit(space, m, method, preset=preset)
    # no preset on a configured space is still no preset (the strategy's own defaults)
    fit(space, m, method, rng=0, preset="own")


def test_a_preset_replaced_to_fit_the_configured_space_applies():
    """The way out the message gives: the preset changed to the space's settings runs its
    budget and options on that space, as the same preset builds it from a plain space."""
    m = matches(4)
    space = HomographySpace.for_data(m, metric="lie_linear")
    p = get_preset("homography", "clap", "paper").replace(metric="lie_linear")
    assert space_conflicts(p, space) == {}
    a = fit(space, m, "clap", rng=3, preset=p)
    assert a.space is space and a.diagnostics["hypotheses"] == 400
    same(a, fit(HomographySpace(), m, "clap", rng=3, preset=p))


def test_preset_is_hashable_and_equal_by_value():
    """Issue 27: a frozen preset holding dicts could not be hashed. Now two presets with the
    same settings are equal and hash alike, whatever mappings built them; a change makes
    another preset; presets key dicts and sets."""
    a = get_preset("homography", "clap", "paper")
    b = Preset("paper", "homography", "clap", space=dict(a.space), fit=dict(a.fit),
               options=dict(reversed(list(a.options.items()))), protocol="clap_paper",
               aliases=[], summary=a.summary, label=a.label)
    assert a == b and hash(a) == hash(b) and a is not b
    assert a.replace() == a and hash(a.replace()) == hash(a)
    c = a.replace(rounds=4)
    assert c != a and len({a, b, c}) == 2 and {a: 1}[b] == 1
    # every preset of every task hashes, and equal presets are the same key
    every = [p for presets in TASK_PRESETS.values() for p in presets.values()]
    assert len(set(every)) == len(every)
    assert {p: p.name for p in every}[pickle.loads(pickle.dumps(a))] == "paper"
    # a value the settings hold by reference (a tuple, an array) hashes by content
    hough = get_preset("pose2d", "randomized_hough", task="localize")
    assert hash(hough) == hash(hough.replace(cell_size=tuple(hough.options["cell_size"])))
    d = Preset("x", "line", "ransac", options={"w": np.array([1.0, 2.0])})
    assert hash(d) == hash(Preset("x", "line", "ransac", options={"w": np.array([1.0, 2.0])}))


def test_method_help_is_written_from_the_presets(capsys):
    """Issue 27: the ``--method`` help of ``fit homography`` and ``stitch`` listed the
    protocol names by hand. Now it is written from :func:`protocol_presets`: every protocol
    name in the presets' order, each with its label, the peers grouped."""
    from clap_unified.imaging.cli import method_help

    presets = protocol_presets()
    text = method_help()
    listed = re.findall(r"\b\w+\b", text.split(": ", 1)[1])
    names = [w for w in listed if w in presets]
    assert names == list(presets)
    for name, p in presets.items():
        assert (f"{name} ({p.label})" in text) == bool(p.label)
    peers = [n for n, p in presets.items() if "peer" in p.aliases]
    assert peers and text.endswith(f"or another library's estimator ({', '.join(peers)})")
    for command in (["fit", "homography"], ["stitch"]):
        assert main([*command, "--help"]) == 0
        out = " ".join(capsys.readouterr().out.split())
        assert " ".join(text.split()) in out


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


#: The segmentation defaults as ``imaging/segment_matches.py`` wrote them out before they
#: became presets (commit 8b40c51): the presets must reproduce them, key for key.
SEGMENT_DEFAULTS_BEFORE_PRESETS = {
    "homography": {"threshold": 5.0, "n_hypotheses": 1000, "neighbours": 20,
                   "coherence": 0.05, "coherence_neighbours": 8},
    "fundamental": {"threshold": 2.0, "n_hypotheses": 1000, "neighbours": 20,
                    "coherence": 0.05, "coherence_neighbours": 8},
}


def test_segmentation_defaults_are_presets():
    """Issue 27: ``SEGMENT_DEFAULTS`` was a second home of defaults beside the presets. Now
    the segmentation presets (task ``"segment"``, per space and segmenter) hold them; the
    old table is their read-only view, the same values as before."""
    from clap_unified.imaging.segment_matches import SEGMENT_DEFAULTS, segment_preset
    from clap_unified.registry import segmenter_names

    assert {k: dict(v) for k, v in SEGMENT_DEFAULTS.items()} == SEGMENT_DEFAULTS_BEFORE_PRESETS
    for kind, space in (("homography", HomographySpace()),):
        for method in segmenter_names(space):
            p = get_preset(kind, method, task="segment")
            assert p is segment_preset(kind, method) and p.fit == SEGMENT_DEFAULTS[kind]
            assert preset_names(kind, method, task="segment") == ("default", "own")
    assert get_preset("homography", "clap", "own", task="segment") is None
    assert get_preset("line", "clap", task="segment") is None  # segment's own defaults
    with pytest.raises(TypeError, match="Preset.replace"):
        SEGMENT_DEFAULTS["homography"]["threshold"] = 4.0
    with pytest.raises(ValueError, match="^kind: "):
        segment_preset("circle")
    with pytest.raises(ValueError, match="^task: "):
        get_preset("homography", "clap", task="segmnet")
    with pytest.raises(ValueError, match=r"^fit: 'rng' is not one of segment's arguments"):
        Preset("x", "homography", None, fit={"rng": 0}, task="segment")


@pytest.mark.parametrize("method", ["clap", "ransac"])
def test_segment_matches_runs_its_preset(method):
    """``segment_matches`` with no argument is ``segment_matches`` with every value of its
    preset written out: the same models and labels, bit for bit; another value changes the
    run (the preset is read, not shadowed by another default)."""
    from clap_unified.imaging.segment_matches import segment_matches, segment_preset

    rng = np.random.default_rng(0)
    src = rng.uniform(0, 640, (200, 2))
    dst = np.where(np.arange(200)[:, None] < 100, src + 20.0, 1.1 * src)
    dst += rng.normal(0, 0.3, dst.shape)
    m = np.c_[src, dst]
    p = segment_preset("homography", method).fit
    a = segment_matches(m, "homography", method, rng=1)
    b = segment_matches(m, "homography", method, rng=1, threshold=p["threshold"],
                        n_hypotheses=p["n_hypotheses"], neighbours=p["neighbours"],
                        coherence=p["coherence"],
                        coherence_neighbours=p["coherence_neighbours"])
    assert np.array_equal(a.models, b.models) and np.array_equal(a.labels, b.labels)
    assert a.threshold == p["threshold"] and a.diagnostics["coherence"] == p["coherence"]


def test_segment_command_reads_the_presets(capsys):
    """``clap-unified segment homography --help`` states the preset's threshold, budget and
    coherence; the point kinds state ``segment``'s own."""
    import inspect

    from clap_unified.segmenting import segment

    for kind in ("homography", "fundamental"):
        p = get_preset(kind, "clap", task="segment").fit
        assert main(["segment", kind, "--help"]) == 0
        out = " ".join(capsys.readouterr().out.split())
        assert f"default {p['threshold']:g})" in out
        assert f"(default {p['n_hypotheses']})" in out and f"default {p['coherence']:g})" in out
    own = inspect.signature(segment).parameters
    assert main(["segment", "line", "--help"]) == 0
    out = " ".join(capsys.readouterr().out.split())
    assert f"(default {own['n_hypotheses'].default})" in out
    assert f"default {own['coherence'].default:g})" in out


#: The localization defaults as the signatures of ``localize2d``, ``localize3d`` and
#: ``align_correspondences`` wrote them out before they became presets (commit 8b40c51).
LOCALIZE_BEFORE_PRESETS = {
    ("pose2d", "clap"): ({"n_hypotheses": 20000, "threshold": 0.3, "radius": 1.0},
                         {"bandwidth": 0.25, "max_clusters": 5, "min_support": 1}),
    ("pose2d", "ransac"): ({"n_hypotheses": 20000, "threshold": 0.3, "radius": 1.0}, {}),
    ("pose2d", "randomized_hough"): ({"n_hypotheses": 20000, "threshold": 0.3, "radius": 1.0},
                                     {"cell_size": (0.25, 0.25, np.radians(5.0)),
                                      "num_peaks": 5}),
    ("pose3d", "clap"): ({"n_hypotheses": 1000, "threshold": 0.15, "max_translation": 0.5,
                          "max_rotation": np.radians(10.0)},
                         {"bandwidth": 0.15, "centre": "medoid", "max_clusters": 5,
                          "min_support": 3, "prune": True, "select": "support"}),
    ("pose3d", "ransac"): ({"n_hypotheses": 1000, "threshold": 0.15, "max_translation": 0.5,
                            "max_rotation": np.radians(10.0)}, {}),
    ("pose3d", "open3d"): ({"n_hypotheses": 100000, "threshold": 0.15, "max_translation": 0.5,
                            "max_rotation": np.radians(10.0)}, {}),
    ("rigid3d", "clap"): ({"n_hypotheses": 1000, "threshold": 0.15},
                          {"bandwidth": 0.15, "centre": "medoid", "min_support": 3,
                           "prune": True}),
    ("rigid3d", "ransac"): ({"n_hypotheses": 1000, "threshold": 0.15}, {}),
}


@pytest.mark.parametrize("key", list(LOCALIZE_BEFORE_PRESETS))
def test_localization_defaults_are_presets(key):
    """Issue 27: the localization defaults were literals in three signatures (the 3D ones
    twice) and the commands read them back from the signatures. Now they are presets (task
    ``"localize"``) with the values the signatures had."""
    fit_part, options = LOCALIZE_BEFORE_PRESETS[key]
    p = get_preset(*key, task="localize")
    assert dict(p.fit) == fit_part and dict(p.options) == options


def test_localize_functions_run_their_presets():
    """Each localization function with no argument is the same call with its preset's
    values written out, bit for bit."""
    from clap_unified.geometry import SE2
    from clap_unified.localization import load_field, simulate_observations
    from clap_unified.localization.localize2d import localize2d
    from clap_unified.localization.localize3d import align_correspondences

    f = load_field("adult")
    truth = SE2.from_xytheta(3.0, 1.0, 0.2)
    obs = simulate_observations(f, truth, false_positive_rate=0.4, rng=1).input
    for method in ("clap", "randomized_hough"):
        p = get_preset("pose2d", method, task="localize")
        a = localize2d(obs, f, method=method, prior=(2.9, 1.1, 0.25), rng=0)
        o = p.options
        b = localize2d(obs, f, method=method, prior=(2.9, 1.1, 0.25), rng=0, **p.fit,
                       **({"max_clusters": o["num_peaks"], "cell_size": o["cell_size"]}
                          if method == "randomized_hough" else o))
        assert np.array_equal(a.model, b.model) and np.array_equal(a.inliers, b.inliers)
    rng = np.random.default_rng(0)
    pts = rng.uniform(-4, 4, (50, 3))
    q = pts + [0.5, -1.0, 2.0] + rng.normal(0, 0.01, (50, 3))
    q[:30] = rng.uniform(-4, 4, (30, 3))
    p = get_preset("rigid3d", "clap", task="localize")
    a = align_correspondences(np.c_[pts, q], rng=0)
    b = align_correspondences(np.c_[pts, q], rng=0, **p.fit, **p.options)
    assert np.array_equal(a.model, b.model) and np.array_equal(a.inliers, b.inliers)


def test_localize_commands_state_the_presets(capsys):
    for command, budget in ((["localize2d"], get_preset("pose2d", None, task="localize")),
                            (["localize3d"], get_preset("pose3d", None, task="localize"))):
        assert main([*command, "--help"]) == 0
        out = " ".join(capsys.readouterr().out.split())
        assert f"default {budget.fit['n_hypotheses']})" in out
    iterations = get_preset("pose3d", "open3d", task="localize").fit["n_hypotheses"]
    assert f"(open3d; default {iterations})" in out


def _documented_defaults(doc):
    """``name`` value pairs a docstring writes out ("``radius`` 1 m", "``centre``
    ``"medoid"``"), as {name: text of the value}."""
    import re

    doc = " ".join(doc.split())
    return dict(re.findall(r'``(\w+)`` (``"?[\w.]+"?``|\d+(?:\.\d+)?)', doc))


@pytest.mark.parametrize("function, space_name", [("localize2d", "pose2d"),
                                                  ("localize3d", "pose3d")])
def test_localization_docstrings_state_the_presets(function, space_name):
    """The localization functions' docstrings write their defaults out for the reader;
    each value written must be the preset's (the one home), so the two cannot drift."""
    import clap_unified.localization as loc

    doc = getattr(loc, function).__doc__
    written = _documented_defaults(doc)
    assert len(written) >= 4, written
    clap = get_preset(space_name, "clap", task="localize")
    values = {**clap.fit, **clap.options, "open3d_iterations":
              get_preset("pose3d", "open3d", task="localize").fit["n_hypotheses"]}
    for name, text in written.items():
        assert name in values, f"{function} documents ``{name}``, which no preset sets"
        want = values[name]
        got = text.strip('`"')
        if isinstance(want, str):
            assert got == want, (name, got, want)
        else:
            assert float(got) == pytest.approx(float(want)), (name, got, want)
    if function == "localize3d":
        gate = get_preset("pose3d", None, task="localize").fit
        assert (f"a gate of {gate['max_translation']:g} m and "
                f"{np.degrees(gate['max_rotation']):g} degrees") in " ".join(doc.split())


def test_align_correspondences_docstring_states_its_preset():
    from clap_unified.localization import align_correspondences

    p = get_preset("rigid3d", None, task="localize").fit
    doc = " ".join(align_correspondences.__doc__.split())
    assert f"{p['n_hypotheses']} triplets, {p['threshold']:g} m" in doc
