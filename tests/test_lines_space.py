import numpy as np
import pytest

from clap_unified.geometry import Line2D
from clap_unified.spaces import LineSpace, enumerate_hypotheses, generate_hypotheses, sample_subsets


def test_solver_returns_canonical_line_through_both_points():
    rng = np.random.default_rng(0)
    pts = rng.normal(size=(40, 2))
    space = LineSpace()
    idx = sample_subsets(40, 2, 100, rng=1)
    models, owner = space.solve_minimal(pts, idx)
    assert np.all((models[:, 0] >= 0) & (models[:, 0] < np.pi))
    r = space.residuals(models, pts)
    rows = np.arange(len(models))
    np.testing.assert_allclose(r[rows, idx[owner, 0]], 0, atol=1e-12)
    np.testing.assert_allclose(r[rows, idx[owner, 1]], 0, atol=1e-12)


def test_degenerate_sample_gives_no_model():
    pts = np.array([[1.0, 1.0], [1.0, 1.0], [2.0, 3.0]])
    models, owner = LineSpace().solve_minimal(pts, np.array([[0, 1], [0, 2]]))
    assert owner.tolist() == [1]


def test_refit_is_total_least_squares_and_detects_degenerate():
    space = LineSpace()
    pts = np.c_[np.arange(5.0), np.full(5, 2.0)]
    model = space.refit(pts)
    np.testing.assert_allclose(space.residuals(model, pts), 0, atol=1e-12)
    assert space.refit(np.ones((4, 2))) is None
    assert space.refit(pts[:1]) is None


def test_sample_subsets_distinct_uniform_and_seeded():
    s = sample_subsets(5, 2, 20000, rng=3)
    assert np.all(s[:, 0] != s[:, 1])
    pairs = np.sort(s, axis=1)
    _, counts = np.unique(pairs, axis=0, return_counts=True)
    assert len(counts) == 10
    assert counts.min() > 0.8 * 2000 and counts.max() < 1.2 * 2000
    np.testing.assert_array_equal(s, sample_subsets(5, 2, 20000, rng=3))
    with pytest.raises(ValueError, match="size"):
        sample_subsets(2, 3, 1)


def test_generate_is_exhaustive_when_small_and_capped_when_degenerate():
    pts = np.random.default_rng(0).normal(size=(10, 2))
    hs = generate_hypotheses(LineSpace(), pts, 100)
    assert hs.exhaustive and len(hs) == 45
    same = np.zeros((200, 2))
    same[0] = 1.0
    hs = generate_hypotheses(LineSpace(), same, 2000, rng=0, max_draws=500)
    assert hs.n_draws == 500 and len(hs) < 100 and hs.n_degenerate == 500 - len(hs)
    assert len(enumerate_hypotheses(LineSpace(), same[:3])) == 2


def test_generate_hypotheses_deterministic():
    pts = np.random.default_rng(0).normal(size=(100, 2))
    a = generate_hypotheses(LineSpace(), pts, 300, rng=7)
    b = generate_hypotheses(LineSpace(), pts, 300, rng=7)
    np.testing.assert_array_equal(a.models, b.models)
    np.testing.assert_array_equal(a.samples, b.samples)


@pytest.mark.parametrize("bad, match", [
    (np.zeros((5, 3)), "points: expected shape"),
    (np.array([[0.0, 1.0], [np.nan, 1.0]]), "points: contains 1 non-finite"),
    (np.zeros((1, 2)), "points: need at least 2"),
    ([["a", "b"], ["c", "d"]], "points: expected a numeric array"),
])
def test_bad_data_is_named(bad, match):
    with pytest.raises(ValueError, match=match):
        generate_hypotheses(LineSpace(), bad, 10)


def test_line_distance_identifies_antipodal_representations():
    m = Line2D(length_scale=3.0, origin=(1.0, 2.0))
    a = np.array([0.2, 1.5])
    b = np.array([0.2 + np.pi, -1.5])
    assert m.distance(a, b) == pytest.approx(0.0, abs=1e-12)
    c = np.array([0.25, 1.0])
    assert m.distance(a, c) == pytest.approx(m.distance(c, a))
    np.testing.assert_allclose(m.exp(m.log(c, a), a), c, atol=1e-12)
