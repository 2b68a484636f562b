"""One axiom suite run over every group (manif / geomstats style)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from clap_unified.geometry import SE2, SE3, Homography, Line2D

GROUPS = {
    "SE2": SE2(),
    "SE2-lambda3": SE2(angle_weight=3.0),
    "SE3": SE3(),
    "SE3-lambda0.5": SE3(angle_weight=0.5),
    "H-h33": Homography("h33"),
    "H-det": Homography("det"),
}
LEFT_INVARIANT = {"SE2", "SE2-lambda3", "SE3", "SE3-lambda0.5", "H-det"}


def sample(g, n, seed, scale=0.5):
    out = g.random(n, rng=seed, scale=scale)
    return g.projection(out)


@pytest.fixture(params=list(GROUPS), ids=list(GROUPS))
def group(request):
    return request.param, GROUPS[request.param]


class TestGroupAxioms:
    def test_inverse_and_identity(self, group):
        _, g = group
        a = sample(g, 20, 0)
        I = g.identity((20,))
        np.testing.assert_allclose(g.compose(a, g.inverse(a)), I, atol=1e-10)
        np.testing.assert_allclose(g.compose(I, a), a, atol=1e-12)

    def test_associativity(self, group):
        _, g = group
        a, b, c = (sample(g, 10, s) for s in (1, 2, 3))
        np.testing.assert_allclose(g.compose(g.compose(a, b), c), g.compose(a, g.compose(b, c)),
                                   atol=1e-10)

    def test_exp_log_round_trips(self, group):
        _, g = group
        a = sample(g, 30, 4)
        base = sample(g, 30, 5)
        np.testing.assert_allclose(g.exp(g.log(a, base), base), a, atol=1e-8)
        rng = np.random.default_rng(6)
        xi = 0.3 * rng.standard_normal((30, g.dim))
        if g.name == "homographies":
            xi = g.logmap(g.projection(g.expmap(xi)))  # tangent of a normalised point
        np.testing.assert_allclose(g.logmap(g.expmap(xi)), xi, atol=1e-8)

    def test_distance_axioms(self, group):
        name, g = group
        a, b, h = (sample(g, 25, s) for s in (7, 8, 9))
        np.testing.assert_allclose(g.distance(a, a), 0, atol=1e-7)
        np.testing.assert_allclose(g.distance(a, b), g.distance(b, a), rtol=1e-8)
        assert np.all(g.distance(a, b) > 1e-6)
        if name in LEFT_INVARIANT:
            np.testing.assert_allclose(g.distance(g.compose(h, a), g.compose(h, b)),
                                       g.distance(a, b), rtol=1e-7)

    def test_means_of_copies_are_the_point(self, group):
        _, g = group
        p = sample(g, 1, 10)[0]
        copies = np.broadcast_to(p, (7, *p.shape))
        for centre in (g.mean(copies), g.log_euclidean_mean(copies), g.median(copies)):
            np.testing.assert_allclose(centre, p, atol=1e-8)
        if hasattr(g, "split_mean"):
            np.testing.assert_allclose(g.split_mean(copies), p, atol=1e-8)

    def test_karcher_mean_of_symmetric_set_is_its_centre(self, group):
        _, g = group
        c = sample(g, 1, 11)[0]
        xi = 0.2 * np.random.default_rng(12).standard_normal((5, g.dim))
        if g.name == "homographies":
            xi = g.logmap(g.projection(g.expmap(xi)))
        pts = g.exp(np.r_[xi, -xi], c)
        np.testing.assert_allclose(g.mean(pts, max_iter=100), c, atol=1e-7)

    def test_batching_matches_single_calls(self, group):
        _, g = group
        a, b = sample(g, 6, 13), sample(g, 6, 14)
        batched = g.distance(a, b)
        single = [float(g.distance(a[i], b[i])) for i in range(6)]
        np.testing.assert_allclose(batched, single, rtol=1e-10)
        D = g.pairwise_distance(a, b)
        np.testing.assert_allclose(D[np.arange(6), np.arange(6)], batched, rtol=1e-10)
        np.testing.assert_allclose(g.pairwise_distance(a), g.pairwise_distance(a, a), atol=1e-10)


@settings(max_examples=25, deadline=None)
@given(st.lists(st.floats(-2.0, 2.0), min_size=3, max_size=3),
       st.floats(-3.0, 3.0))
def test_se2_property_log_exp(xy_theta, angle):
    g = SE2()
    x, y, _ = xy_theta
    T = g.from_xytheta(x, y, angle)
    np.testing.assert_allclose(g.expmap(g.logmap(T)), T, atol=1e-9)
    np.testing.assert_allclose(g.to_xytheta(T)[:2], [x, y], atol=1e-12)


@settings(max_examples=25, deadline=None)
@given(st.lists(st.floats(-1.0, 1.0), min_size=6, max_size=6))
def test_se3_property_log_exp(v):
    g = SE3()
    xi = np.array(v)
    np.testing.assert_allclose(g.logmap(g.expmap(xi)), xi, atol=1e-9)


@settings(max_examples=25, deadline=None)
@given(st.floats(0.0, np.pi - 1e-3), st.floats(-5, 5), st.floats(0.0, np.pi - 1e-3),
       st.floats(-5, 5))
def test_line_distance_symmetric_and_zero_on_equal(t1, r1, t2, r2):
    m = Line2D(length_scale=2.0, origin=(0.5, -1.0))
    a, b = np.array([t1, r1]), np.array([t2, r2])
    assert m.distance(a, a) == pytest.approx(0.0, abs=1e-9)
    assert m.distance(a, b) == pytest.approx(float(m.distance(b, a)), abs=1e-9)
    np.testing.assert_allclose(m.distance(m.exp(m.log(b, a), a), b), 0, atol=1e-9)
