"""Lines compared by where they pass anchor points (LineTransfer) and its use by CLAP."""

import numpy as np
import pytest

from clap_unified import LineSpace, fit, fit_line
from clap_unified.clap.density import EmbeddedNeighbours
from clap_unified.geometry.line_transfer import LineTransfer
from clap_unified.geometry.lines import canonical_lines
from clap_unified.viz.scenes import line_scene

ANCHORS = np.array([[-3.0, -2.0], [4.0, -1.0], [3.0, 5.0], [-2.0, 3.0], [0.5, 1.0]])


def _random_lines(seed, n=40):
    g = np.random.default_rng(seed)
    return np.c_[g.uniform(-np.pi, 2 * np.pi, n), g.uniform(-6, 6, n)]


def _feet_loop(lines, anchors):
    """Feet of the perpendiculars, one anchor and one line at a time (the reference)."""
    out = []
    for theta, rho in lines:
        n = np.array([np.cos(theta), np.sin(theta)])
        out.append(np.concatenate([a - (n @ a - rho) * n for a in anchors]))
    return np.array(out) / np.sqrt(len(anchors))


@pytest.mark.parametrize("seed", range(3))
def test_embedding_is_the_feet_and_its_distance_the_distance(seed):
    g = LineTransfer(ANCHORS)
    lines = _random_lines(seed)
    np.testing.assert_allclose(g.chordal_embedding(lines), _feet_loop(lines, ANCHORS),
                               atol=1e-12)
    d = g.pairwise_distance(lines)
    feet = _feet_loop(lines, ANCHORS) * np.sqrt(len(ANCHORS))
    ref = np.array([[np.sqrt(np.mean(np.sum((fa.reshape(-1, 2) - fb.reshape(-1, 2)) ** 2, 1)))
                     for fb in feet] for fa in feet])
    np.testing.assert_allclose(d, ref, atol=1e-9)
    np.testing.assert_allclose(g.distance(lines[:, None], lines[None]), d, atol=1e-9)
    np.testing.assert_allclose(g.pairwise_distance(lines[:5], lines), d[:5], atol=1e-9)


def test_the_two_normals_of_a_line_are_one_line():
    g = LineTransfer(ANCHORS)
    lines = _random_lines(7)
    flipped = np.c_[lines[:, 0] + np.pi, -lines[:, 1]]
    np.testing.assert_allclose(g.distance(lines, flipped), 0.0, atol=1e-9)
    np.testing.assert_allclose(g.distance(lines, canonical_lines(lines)), 0.0, atol=1e-9)


def test_it_is_a_metric():
    g = LineTransfer(ANCHORS)
    d = g.pairwise_distance(_random_lines(11, 30))
    assert np.allclose(d, d.T) and np.all(np.diag(d) == 0)
    off = d[~np.eye(len(d), dtype=bool)]
    assert off.min() > 1e-6  # distinct lines are apart
    # triangle inequality on every triple (Line2D's chart distance violates it)
    assert np.all(d[:, None, :] <= d[:, :, None] + d[None, :, :] + 1e-9)


def test_distance_reads_in_data_units():
    g = LineTransfer(np.array([[0.0, 0.0], [10.0, 0.0]]))
    # y = 0 and y = 0.5: the feet move by 0.5 at every anchor
    assert float(g.distance([np.pi / 2, 0.0], [np.pi / 2, 0.5])) == pytest.approx(0.5)


def test_bad_anchors_are_refused():
    with pytest.raises(ValueError, match="anchors"):
        LineTransfer(np.zeros((3, 2)))
    with pytest.raises(ValueError, match="anchors"):
        LineTransfer(np.zeros((3, 3)))
    with pytest.raises(ValueError, match="metric"):
        LineSpace.for_data(np.eye(2), metric="angles")
    # all points at one place: a space all the same, and a failed fit rather than an error
    assert fit_line(np.ones((5, 2)), "clap", rng=0).reason
    assert not fit_line(np.ones((5, 2)), "clap", rng=0).success


def test_clap_uses_a_kd_tree_and_finds_the_same_line_as_the_chart():
    scene = line_scene(600, 0.6, noise=0.05, rng=3)
    pts = scene.input.points
    space = LineSpace.for_data(pts, metric="transfer")
    assert space.manifold.embedding_is_distance
    nb = EmbeddedNeighbours(space.manifold, np.array([[0.1, 0.2], [0.1, 0.25]]))
    assert nb.tree is not None
    res = fit(space, pts, "clap", threshold=0.15, rng=2)
    ref = fit(LineSpace.for_data(pts), pts, "clap", threshold=0.15, rng=2)
    assert res.success and ref.success
    truth = scene.truth.lines[0]
    for r in (res, ref):
        assert LineTransfer(ANCHORS).distance(r.model, truth) < 0.05
    assert abs(res.n_inliers - ref.n_inliers) <= 3


@pytest.mark.parametrize("method", ["clap", "ransac", "randomized_hough", "hough"])
def test_fit_line_with_either_metric(method):
    scene = line_scene(300, 0.5, noise=0.02, rng=5)
    pts = scene.input.points
    for metric in ("transfer", "chart"):
        res = fit_line(pts, method, threshold=0.06, rng=0, metric=metric)
        assert res.success, (method, metric, res.reason)
        assert abs(res.n_inliers - 150) <= 10
    a = fit_line(pts, method, rng=4)
    b = fit_line(pts, method, rng=4)
    assert np.array_equal(a.model, b.model) and np.array_equal(a.inliers, b.inliers)
