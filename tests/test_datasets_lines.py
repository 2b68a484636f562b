"""Line scenes keep the estimator's input (noisy points) apart from the evaluation data."""

import dataclasses

import numpy as np
import pytest
import scenes
from split_checks import assert_rows_disjoint, assert_split

from clap_unified.geometry import Line2D
from clap_unified.spaces import LineSpace
from clap_unified.viz import LineInput, LineScene, LineTruth, line_scene


def noise_free_copies(scene):
    """Each inlier projected onto the line it was drawn from: its position before the noise."""
    pts, label = scene.input.points, scene.truth.label
    inl = label >= 0
    normal, rho = Line2D.normal_offset(scene.truth.lines[label[inl]])
    p = pts[inl]
    return p - (np.sum(p * normal, axis=1) - rho)[:, None] * normal


def two_line_scene(noise=0.05):
    return line_scene(240, 0.4, lines=[(1.9, 1.0), (np.radians(25.0), -1.5)],
                      share=[0.55, 0.45], noise=noise, rng=3)


@pytest.mark.parametrize("make", [lambda: line_scene(200, 0.6, rng=0), two_line_scene,
                                  lambda: scenes.line_scene(seed=1)])
def test_scene_is_split_and_frozen(make):
    scene = make()
    assert_split(scene)
    assert isinstance(scene.input, LineInput) and isinstance(scene.truth, LineTruth)
    # the input is the noisy points and nothing else
    assert [f.name for f in dataclasses.fields(scene.input)] == ["points"]
    assert scene.input.points.ndim == 2 and scene.input.points.shape[1] == 2
    assert len(scene.truth.label) == len(scene.input.points)
    with pytest.raises(ValueError):
        scene.input.points[0, 0] = 0.0
    with pytest.raises(dataclasses.FrozenInstanceError):
        scene.input.points = np.zeros((3, 2))
    # no shortcut from the scene to either part's fields
    assert not hasattr(scene, "points") and not hasattr(scene, "label")


@pytest.mark.parametrize("make", [lambda: line_scene(200, 0.6, rng=0), two_line_scene,
                                  lambda: scenes.line_scene(seed=1)])
def test_no_noise_free_copy_among_the_input(make):
    scene = make()
    clean = noise_free_copies(scene)
    assert len(clean) == scene.truth.is_inlier.sum() > 0
    assert_rows_disjoint(scene.input.points, clean, atol=1e-9)


def test_the_disjointness_check_catches_a_noise_free_scene():
    # with no noise the inputs are their own noise-free copies: the check must fail
    scene = line_scene(50, 0.2, noise=0.0, rng=0)
    with pytest.raises(AssertionError, match="evaluation rows"):
        assert_rows_disjoint(scene.input.points, noise_free_copies(scene), atol=1e-9)


def test_truth_labels_and_lines_describe_the_input():
    scene = two_line_scene(noise=0.05)
    truth = scene.truth
    assert np.bincount(truth.label[truth.is_inlier]).tolist() == [80, 64]
    assert np.count_nonzero(~truth.is_inlier) == 96
    for k, line in enumerate(truth.lines):
        res = LineSpace().residuals(line, scene.input.points[truth.label == k])
        assert res.max() < 5 * 0.05
    np.testing.assert_array_equal(truth.line, truth.lines[0])


def test_same_seed_same_scene_and_input_is_a_copy():
    a, b = line_scene(100, 0.5, rng=7), line_scene(100, 0.5, rng=7)
    np.testing.assert_array_equal(a.input.points, b.input.points)
    np.testing.assert_array_equal(a.truth.label, b.truth.label)
    pts = np.ones((4, 2))
    inp = LineInput(pts)
    pts[0, 0] = 5.0
    assert inp.points[0, 0] == 1.0


def test_scene_rejects_mismatched_or_swapped_parts():
    inp, truth = LineInput(np.zeros((3, 2))), LineTruth(np.zeros(4, int), np.zeros((1, 2)))
    with pytest.raises(ValueError, match="3 points but 4 labels"):
        LineScene(inp, truth)
    with pytest.raises(TypeError):
        LineScene(truth, inp)
