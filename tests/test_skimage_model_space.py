"""``SkimageModelSpace``: scikit-image's model classes as hypothesis spaces (issue 27)."""

import numpy as np
import pytest

pytest.importorskip("skimage", minversion="0.26")

from skimage.measure import CircleModel, EllipseModel, LineModelND  # noqa: E402
from skimage.transform import AffineTransform, EuclideanTransform  # noqa: E402

from clap_unified import SkimageModelSpace, compare, fit  # noqa: E402


def ellipse_scene(seed=0):
    g = np.random.default_rng(seed)
    truth = EllipseModel((3.0, -2.0), (6.0, 2.5), 0.4)
    pts = truth.predict_xy(g.uniform(0, 2 * np.pi, 120)) + g.normal(0, 0.01, (120, 2))
    pts[:40] = g.uniform(-6, 12, (40, 2))
    return truth, pts


@pytest.mark.parametrize("method", ["ransac", "clap"])
def test_ellipse_with_outliers(method):
    truth, pts = ellipse_scene()
    space = SkimageModelSpace(EllipseModel, 5)
    res = fit(space, pts, method, threshold=0.05, rng=0, n_hypotheses=150)
    assert res.success, res.reason
    assert res.inliers[40:].all() and res.inliers[:40].sum() <= 2
    est = space.to_model(res.model)
    np.testing.assert_allclose(est.center, truth.center, atol=0.01)
    np.testing.assert_allclose(sorted(est.axis_lengths), sorted(truth.axis_lengths), atol=0.01)


def test_compare_runs_the_strategies_on_one_hypothesis_set():
    _, pts = ellipse_scene(1)
    out = compare(SkimageModelSpace(EllipseModel, 5), pts, methods=("ransac", "clap"),
                  threshold=0.05, rng=1, n_hypotheses=150)
    assert all(r.success for r in out.values())
    assert np.array_equal(out["ransac"].inliers, out["clap"].inliers)


@pytest.mark.parametrize("method", ["ransac", "clap"])
def test_line_model_nd_in_3d(method):
    g = np.random.default_rng(2)
    t = g.uniform(-5, 5, 100)
    pts = np.array([1.0, 2, 3]) + t[:, None] * np.array([0.0, 0.6, 0.8])
    pts[:30] = g.uniform(-5, 5, (30, 3))
    space = SkimageModelSpace(LineModelND, 2, dim=3)
    res = fit(space, pts, method, threshold=0.01, rng=0, n_hypotheses=300)
    assert res.success and res.inliers[30:].all() and not res.inliers[:30].any()
    line = space.to_model(res.model)
    assert abs(abs(line.direction @ [0.0, 0.6, 0.8]) - 1) < 1e-9
    assert space.model_to_dict(res.model)["class"] == "LineModelND"


@pytest.mark.parametrize("method", ["ransac", "clap"])
def test_transform_from_two_arrays(method):
    g = np.random.default_rng(3)
    src = g.uniform(0, 100, (60, 2))
    truth = EuclideanTransform(rotation=0.3, translation=(5, -2))
    dst = truth(src)
    dst[:15] = g.uniform(0, 100, (15, 2))
    space = SkimageModelSpace(EuclideanTransform, 2, widths=(2, 2), n_params=9)
    res = fit(space, (src, dst), method, threshold=0.5, rng=0, n_hypotheses=200)
    assert res.success and res.inliers[15:].all() and not res.inliers[:15].any()
    np.testing.assert_allclose(space.to_model(res.model).params, truth.params, atol=1e-9)
    # the same data side by side is the same problem
    side = fit(space, np.c_[src, dst], method, threshold=0.5, rng=0, n_hypotheses=200)
    assert np.array_equal(side.model, res.model)


def test_same_seed_same_result():
    _, pts = ellipse_scene(4)
    space = SkimageModelSpace(EllipseModel, 5)
    a, b = (fit(space, pts, "clap", threshold=0.05, rng=9, n_hypotheses=200) for _ in "ab")
    assert np.array_equal(a.model, b.model) and np.array_equal(a.inliers, b.inliers)


def test_bad_arguments_name_them():
    with pytest.raises(ValueError, match="model_class"):
        SkimageModelSpace(CircleModel((0, 0), 1), 3)
    with pytest.raises(ValueError, match="min_samples"):
        SkimageModelSpace(CircleModel, 0)
    with pytest.raises(ValueError, match="n_params"):
        SkimageModelSpace(AffineTransform, 3)
    with pytest.raises(ValueError, match="n_params"):
        SkimageModelSpace(AffineTransform, 3, n_params=8)

    class NoMatrix:
        @classmethod
        def from_estimate(cls, data):
            return cls()

        def residuals(self, data):
            return np.zeros(len(data))

    with pytest.raises(ValueError, match="from_params"):
        SkimageModelSpace(NoMatrix, 3, n_params=2)
    for hook in ("is_data_valid", "is_model_valid", "to_params", "from_params"):
        with pytest.raises(ValueError, match=hook):
            SkimageModelSpace(CircleModel, 3, **{hook: 1})
    with pytest.raises(ValueError, match="model_kwargs"):
        SkimageModelSpace(CircleModel, 3, model_kwargs=[1])
    with pytest.raises(ValueError, match="widths"):
        SkimageModelSpace(AffineTransform, 3, n_params=9, widths=())
    space = SkimageModelSpace(AffineTransform, 3, n_params=9, widths=(2, 2))
    with pytest.raises(ValueError, match="data: expected 2 arrays"):
        space.check_data((np.zeros((5, 2)),))
    with pytest.raises(ValueError, match="data: the arrays differ in length"):
        space.check_data((np.zeros((5, 2)), np.zeros((4, 2))))
    with pytest.raises(ValueError, match="data: expected shape"):
        space.check_data(np.zeros((5, 3)))
    with pytest.raises(ValueError, match="data"):
        space.check_data(np.full((5, 4), np.nan))
