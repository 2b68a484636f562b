"""Lines in ``R^d`` (issue 27): the ``LineND`` manifold and ``LineNDSpace``.

scikit-image's ``LineModelND`` as a hypothesis space usable by RANSAC and CLAP.
"""

import numpy as np
import pytest

from clap_unified import LineNDSpace, fit
from clap_unified.geometry import LineND, canonical_lines_nd, line_residuals


def random_lines(d, n, seed):
    g = np.random.default_rng(seed)
    return canonical_lines_nd(np.stack([g.normal(0, 3, (n, d)), g.normal(0, 1, (n, d))], 1))


@pytest.mark.parametrize("d", [2, 3, 5])
def test_manifold_axioms(d):
    g = LineND(d, length_scale=2.0, origin=np.arange(d) * 0.5)
    a, b, c = (random_lines(d, 40, s) for s in (1, 2, 3))
    # the same line under another origin point and the other sign: distance 0
    other = np.stack([a[:, 0] + 3.7 * a[:, 1], -2.5 * a[:, 1]], axis=1)
    np.testing.assert_allclose(g.distance(a, other), 0, atol=1e-9)
    np.testing.assert_allclose(g.distance(a, b), g.distance(b, a), rtol=1e-12)
    assert np.all(g.distance(a, b) > 1e-6)
    assert np.all(g.distance(a, c) <= g.distance(a, b) + g.distance(b, c) + 1e-9)
    # exp and log round trip (canonical points)
    np.testing.assert_allclose(g.exp(g.log(b, a), a), g.projection(b), atol=1e-9)
    # the embedding bounds the distance (k-d tree pruning finds a superset)
    e = g.chordal_embedding(a) - g.chordal_embedding(b)
    assert np.all(np.linalg.norm(e, axis=-1) <= g.distance(a, b) + 1e-9)
    pair = g.pairwise_distance(a[:5], b[:4])
    np.testing.assert_allclose(pair, g.distance(a[:5, None], b[None, :4]), rtol=1e-12)
    # the mean of copies of one line (any representatives) is that line
    np.testing.assert_allclose(g.mean(np.stack([a[0], other[0], a[0]])),
                               g.projection(a[0]), atol=1e-9)


def test_bad_arguments_name_them():
    with pytest.raises(ValueError, match="dim"):
        LineND(1)
    with pytest.raises(ValueError, match="origin"):
        LineND(3, origin=[0.0, 0.0])
    with pytest.raises(ValueError, match="manifold"):
        LineNDSpace(manifold="x")
    with pytest.raises(ValueError, match="points"):
        fit(LineNDSpace(3), np.zeros((10, 2)), "ransac", threshold=1.0)
    with pytest.raises(ValueError, match="axis"):
        LineNDSpace.predict([[0.0, 0.0], [1.0, 0.0]], [1.0], axis=1)
    with pytest.raises(ValueError, match="axis"):
        LineNDSpace.predict([[0.0, 0.0], [1.0, 0.0]], [1.0], axis=2)


@pytest.mark.parametrize("method", ["ransac", "clap"])
@pytest.mark.parametrize("d", [2, 3, 6])
def test_fit_with_outliers(method, d):
    g = np.random.default_rng(d)
    direction = g.normal(size=d)
    direction /= np.linalg.norm(direction)
    origin = g.normal(0, 5, d)
    t = g.uniform(-10, 10, 120)
    pts = origin + t[:, None] * direction + g.normal(0, 0.01, (120, d))
    pts[:40] = g.uniform(-15, 15, (40, d))
    space = LineNDSpace.for_data(pts)
    res = fit(space, pts, method, threshold=0.05, rng=0)
    assert res.success, res.reason
    assert res.inliers[40:].all() and not res.inliers[:40].any()
    assert abs(abs(res.model[1] @ direction) - 1) < 1e-5
    assert line_residuals(res.model[None], origin[None])[0, 0] < 0.01


def test_degenerate_and_refit():
    space = LineNDSpace(3)
    pts = np.array([[1.0, 2, 3], [1.0, 2, 3], [1e5, 0, 0], [1e5 + 1e-3, 0, 0]])
    models, owner = space.solve_minimal(pts, np.array([[0, 1], [2, 3]]))
    assert owner.tolist() == [1]
    np.testing.assert_allclose(models[0], [[0, 0, 0], [1, 0, 0]], atol=1e-9)
    assert space.refit(np.ones((5, 3))) is None
    assert space.refit(pts[:1]) is None
    line = space.refit(np.array([[0.0, 0, 1], [0, 0, 2], [0, 0, 4]]))
    np.testing.assert_allclose(line, [[0, 0, 0], [0, 0, 1]], atol=1e-12)
    assert space.model_to_dict(line) == {"origin": [0.0, 0.0, 0.0],
                                         "direction": [0.0, 0.0, 1.0]}


def test_same_answer_in_every_unit():
    g = np.random.default_rng(0)
    pts = np.array([3.0, 1, 2]) + g.uniform(-1, 1, 30)[:, None] * np.array([1.0, 2, 2]) / 3
    ref = LineNDSpace(3).refit(pts)
    for scale in (1e-150, 1e-90, 1e90):
        line = LineNDSpace(3).refit(pts * scale)
        np.testing.assert_allclose(line[0] / scale, ref[0], rtol=1e-9, atol=1e-12)
        np.testing.assert_allclose(line[1], ref[1], rtol=1e-9)  # a unit direction


def test_predict_and_point_at():
    model = np.array([[0.0, 0.0], [0.2, 0.8]])
    x = np.arange(-10, 10.0)
    y = LineNDSpace.predict(model, x, axis=0)[:, 1]
    np.testing.assert_allclose(LineNDSpace.predict(model, y, axis=1)[:, 0], x)
    np.testing.assert_allclose(y, 4 * x)
    p = LineNDSpace.point_at([[1.0, 2, 3], [0, 0, 1]], [[0.0, 1.0]])
    assert p.shape == (1, 2, 3) and p[0, 1].tolist() == [1.0, 2.0, 4.0]
