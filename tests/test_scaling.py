"""The scaling measurements behind the performance chapter and bench/bench_scaling.py."""

import numpy as np
import pytest

from clap_unified.reproduce.scaling import loglog_slope, scaling_problem, scaling_runs


def test_rows_have_every_key_and_positive_figures():
    rows = scaling_runs("homography", [60, 120], repeat=1)
    assert {r["method"] for r in rows} == {"clap", "clap_densest"}
    for r in rows:
        assert set(r) == {"kind", "vary", "method", "size", "seconds", "peak_mb", "success"}
        assert r["seconds"] > 0 and r["peak_mb"] > 0 and r["success"]


def test_the_matrix_path_needs_more_memory_with_more_hypotheses():
    rows = scaling_runs("homography", [200, 1600], methods=["clap_densest"], repeat=1)
    assert rows[1]["peak_mb"] > 4 * rows[0]["peak_mb"]


def test_loglog_slope_recovers_a_power_law():
    x = np.array([10.0, 30.0, 100.0, 1000.0])
    assert loglog_slope(x, 5 * x**1.5) == pytest.approx(1.5)
    with pytest.raises(ValueError, match="sizes"):
        loglog_slope([1.0], [2.0])


def test_problems_are_seeded_and_bad_kinds_named():
    assert np.array_equal(scaling_problem("line", 20, seed=3), scaling_problem("line", 20, seed=3))
    with pytest.raises(ValueError, match="kind"):
        scaling_runs("circle", [10])
