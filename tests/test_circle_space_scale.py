"""``CircleSpace`` does not depend on where the circle is or on its unit (issue 27).

Before the fix, a unit circle centred at ``(1e5, 1e5)`` gave "every minimal sample was
degenerate" (the degeneracy tolerance grew with the distance from the origin, not with the
spread of the sample), and the refit at scikit-image's ``1e-90`` scale returned garbage
(uncentred algebraic fit: ``r^2 = c + cx^2 + cy^2`` cancels catastrophically).
"""

import numpy as np
import pytest

from clap_unified import CircleSpace, fit

ANGLES = np.array([0.107, 0.407, 1.108, 1.489, 2.216, 2.768, 3.183, 3.969, 4.840, 5.387,
                   5.792, 6.139])


def circle(cx, cy, r, angles=ANGLES):
    return CircleSpace.predict([cx, cy, r], angles)


@pytest.mark.parametrize("method", ["ransac", "clap"])
@pytest.mark.parametrize("offset", [0.0, 1e3, 1e5, 1e7, -3e6])
def test_unit_circle_anywhere(method, offset):
    pts = circle(offset, offset, 1.0, np.linspace(0, 2 * np.pi, 40, endpoint=False))
    res = fit(CircleSpace(), pts, method, threshold=1e-6, rng=0, n_hypotheses=200)
    assert res.success, res.reason
    np.testing.assert_allclose(res.model, [offset, offset, 1.0], rtol=0, atol=1e-6)
    assert res.n_inliers == 40


@pytest.mark.parametrize("scale", [1e-90, 1e-30, 1.0, 1e30, 1e150])
def test_same_answer_in_every_unit(scale):
    """The same scene in another unit: the same model, in that unit."""
    pts = circle(1.23, 2.34, 0.345)
    space = CircleSpace()
    ref = space.refit(pts)
    np.testing.assert_allclose(space.refit(pts * scale) / scale, ref, rtol=1e-9)
    samples = np.array([[0, 4, 8], [1, 5, 9]])
    models, owner = space.solve_minimal(pts * scale, samples)
    assert owner.tolist() == [0, 1]
    np.testing.assert_allclose(models / scale, [ref, ref], rtol=1e-9)


def test_skimage_small_scale_refit():
    """scikit-image's ``test_circle_model_estimate_from_small_scale_data`` scene."""
    params = np.array([1.23e-90, 2.34e-90, 3.45e-100])
    model = CircleSpace().refit(circle(*params))
    # the data hold the radius to ~1e-6 of itself (coordinates ~1e-90 round at ~1e-106)
    np.testing.assert_allclose(model, params, rtol=1e-5)


def test_degenerate_samples_by_their_own_spread():
    space = CircleSpace()
    far = np.array([[1e5, 1e5], [1e5 + 1, 1e5 + 1], [1e5 + 2, 1e5 + 2],   # collinear
                    [1e5 + 1, 1e5], [1e5, 1e5], [1e5, 1e5]])               # coincident pair
    models, owner = space.solve_minimal(far, np.array([[0, 1, 2], [0, 1, 3], [3, 4, 5]]))
    assert owner.tolist() == [1]
    np.testing.assert_allclose(models[0], [1e5 + 0.5, 1e5 + 0.5, np.sqrt(0.5)], atol=1e-9)
    assert space.refit(np.ones((6, 2))) is None
    assert space.refit(far[:3]) is None  # collinear: no circle


def test_predict():
    pts = CircleSpace.predict([0.0, 0.0, 5.0], np.arange(0, 2 * np.pi, np.pi / 2))
    np.testing.assert_allclose(pts, [[5, 0], [0, 5], [-5, 0], [0, -5]], atol=1e-12)
    assert CircleSpace.predict([1.0, 2.0, 3.0], np.zeros((2, 3))).shape == (2, 3, 2)
