"""Adding a strategy is one new file and one registration line."""

from __future__ import annotations

import importlib
import json
import sys
import textwrap

import numpy as np
import pytest

from clap_unified import compare, fit, strategy_names
from clap_unified.cli import main
from clap_unified.registry import Strategy, get_strategy, register_strategy, unregister_strategy
from clap_unified.spaces import LineSpace

TOY = '''
"""A toy strategy: the hypothesis whose sample has the smallest indices."""
import numpy as np

from clap_unified.registry import Strategy, register_strategy
from clap_unified.result import Cluster, Consensus


def run_lowest(space, data, hypotheses, *, threshold, prior=None, radius=None, rng=None,
               n_hypotheses=0, offset=0):
    j = int(np.lexsort(hypotheses.samples.T[::-1])[offset])
    support = np.zeros(len(hypotheses), bool)
    support[j] = True
    return Consensus(hypotheses.models[j], (Cluster(hypotheses.models[j], 1, 0.0,
                                                    np.array([j])),), support, 1.0)


register_strategy(Strategy("lowest_sample", run_lowest, summary="toy"))
'''


@pytest.fixture
def toy(tmp_path, monkeypatch):
    (tmp_path / "toy_strategy.py").write_text(textwrap.dedent(TOY))
    monkeypatch.syspath_prepend(str(tmp_path))
    sys.modules.pop("toy_strategy", None)
    importlib.import_module("toy_strategy")
    yield "lowest_sample"
    unregister_strategy("lowest_sample")
    sys.modules.pop("toy_strategy", None)


def test_a_toy_strategy_runs_through_fit_compare_and_the_cli(toy, tmp_path, capsys):
    pts = np.c_[np.arange(20.0), 3.0 * np.arange(20.0) + 1.0]
    assert toy in strategy_names(LineSpace())
    res = fit(LineSpace.for_data(pts), pts, toy, threshold=0.1, rng=0)
    assert res.success and res.method == toy and res.n_inliers == 20
    assert fit(LineSpace.for_data(pts), pts, toy, threshold=0.1, rng=0, offset=1).success
    out = compare(LineSpace.for_data(pts), pts, methods=(toy, "clap"), threshold=0.1, rng=0)
    assert set(out) == {toy, "clap"}
    assert np.array_equal(out[toy].support, fit(LineSpace.for_data(pts), pts, toy,
                                                hypotheses=None, threshold=0.1, rng=0).support)
    csv = tmp_path / "points.csv"
    np.savetxt(csv, pts, delimiter=",")
    assert main(["fit", "line", str(csv), "--method", toy, "--threshold", "0.1"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["method"] == toy and doc["inliers"] == 20
    with pytest.raises(ValueError, match="offsett.*options: offset"):
        fit(LineSpace(), pts, toy, offsett=1, threshold=0.1)


def test_a_name_is_registered_once():
    strategy = get_strategy("clap")
    with pytest.raises(ValueError, match="already registered"):
        register_strategy(Strategy("clap", strategy.run))
    with pytest.raises(ValueError, match="name"):
        register_strategy(Strategy("two words", strategy.run))
    with pytest.raises(TypeError, match="Strategy"):
        register_strategy(strategy.run)
    assert get_strategy("clap") is strategy


def test_each_hough_variant_has_its_own_name():
    assert get_strategy("hough").applies_to == ("line",)
    assert not get_strategy("hough").uses_hypotheses
    assert get_strategy("randomized_hough").uses_hypotheses


def test_unknown_method_lists_only_the_strategies_of_the_space():
    # the registry also holds other spaces' strategies (OpenCV's homography estimators,
    # Open3D's 3D alignment); a line fit must not offer them
    from clap_unified import LineSpace, fit_line, strategy_names

    pts = np.c_[np.arange(10.0), np.arange(10.0)]
    with pytest.raises(ValueError) as info:
        fit_line(pts, "CLAP")
    msg = str(info.value)
    assert msg.startswith("method: expected one of ")
    assert str(sorted(strategy_names(LineSpace.for_data(pts)))) in msg
    for other in ("magsac", "poselib", "open3d", "cv2_ransac"):
        assert f"'{other}'" not in msg
    assert "(names are lower case: 'clap')" in msg


def test_unknown_method_without_a_space_lists_every_strategy():
    from clap_unified import get_strategy, strategy_names

    with pytest.raises(ValueError) as info:
        get_strategy("nope")
    assert str(sorted(strategy_names())) in str(info.value)
    assert "lower case" not in str(info.value)
