"""The misclassification error: hand-computed cases, a brute-force check, bad input."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from clap_unified.imaging.segmentation_metrics import contingency_table, misclassification_error


def _brute_force(predicted, truth):
    """Smallest error over every one-to-one map of predicted structures to true ones
    (or to nothing), outliers (-1 -> 0) fixed."""
    predicted, truth = np.asarray(predicted), np.asarray(truth)
    found = sorted(set(predicted[predicted >= 0].tolist()))
    true = sorted(set(truth[truth > 0].tolist()))
    slots = true + [None] * len(found)
    best = len(truth)
    for image in itertools.permutations(slots, len(found)):
        mapping = {-1: 0, **dict(zip(found, image, strict=True))}
        mapped = np.array([mapping[p] if mapping[p] is not None else -99 for p in predicted])
        best = min(best, int(np.sum(mapped != truth)))
    return best / len(truth)


def test_permuted_labels_score_zero():
    truth = [0, 0, 1, 1, 1, 2, 2, 3, 3, 3]
    for perm in itertools.permutations([0, 1, 2]):
        predicted = [-1 if t == 0 else perm[t - 1] for t in truth]
        assert misclassification_error(predicted, truth) == 0.0
    # indices need not be contiguous
    assert misclassification_error([-1, -1, 7, 7, 7, 4, 4, 0, 0, 0], truth) == 0.0


def test_all_outliers_costs_the_share_of_inliers():
    truth = np.array([0, 0, 0, 1, 1, 2, 2, 2])          # 5 inliers of 8
    assert misclassification_error(np.full(8, -1), truth) == 5 / 8
    # everything in one structure: it matches structure 2 (3 right), the other 5 are wrong
    assert misclassification_error(np.zeros(8, int), truth) == 5 / 8


def test_more_structures_found_than_exist():
    truth = [0, 0, 1, 1, 1, 1, 2, 2, 2, 2]
    # structure 1 split in two (0 and 3): one half matches, the other is wrong
    predicted = [-1, -1, 0, 0, 3, 3, 1, 1, 1, 1]
    assert misclassification_error(predicted, truth) == pytest.approx(0.2)
    # an extra structure made of outliers: both outliers wrong
    assert misclassification_error([5, 5, 0, 0, 0, 0, 1, 1, 1, 1], truth) == pytest.approx(0.2)


def test_fewer_structures_found_than_exist():
    truth = [1, 1, 1, 2, 2, 0]
    # one structure found for two: structure 2's data are wrong
    assert misclassification_error([0, 0, 0, 0, 0, -1], truth) == pytest.approx(2 / 6)


def test_outliers_match_only_outliers():
    # calling the outliers a structure and the inlier an outlier is all wrong, though a
    # relabelling that swapped the outlier class with the structure would make it right
    assert misclassification_error([0, 0, 0, -1], [0, 0, 0, 1]) == 1.0
    assert misclassification_error([-1, -1, -1, 0], [0, 0, 0, 1]) == 0.0


def test_agrees_with_brute_force():
    rng = np.random.default_rng(0)
    for _ in range(200):
        n = int(rng.integers(1, 15))
        truth = rng.integers(0, 4, n)
        predicted = rng.integers(-1, 4, n)
        assert misclassification_error(predicted, truth) == pytest.approx(
            _brute_force(predicted, truth))


def test_contingency_table():
    table = contingency_table([-1, 0, 2, 2, 2], [0, 1, 1, 3, 3])
    assert table.shape == (4, 4) and table.sum() == 5
    assert table[0, 0] == 1 and table[1, 1] == 1 and table[3, 1] == 1 and table[3, 3] == 2
    # integer-valued floats are accepted
    np.testing.assert_array_equal(contingency_table([-1.0, 0.0], [0.0, 1.0]), np.eye(2))


@pytest.mark.parametrize("predicted,truth,match", [
    ([0, 1], [1, 1, 0], "predicted: 2 labels for 3"),
    ([0, np.nan], [1, 1], "predicted: labels must be finite"),
    ([0, 1], [1, np.inf], "truth: labels must be finite"),
    ([0, 0.5], [1, 1], "predicted: labels must be integers"),
    ([-2, 0], [1, 1], "predicted: labels must be >= -1"),
    ([0, 0], [-1, 1], "truth: labels must be >= 0"),
    ([[0, 1]], [1, 1], "predicted: expected a 1-D"),
    ([0, 1], [[1, 1]], "truth: expected a 1-D"),
    (["a", "b"], [1, 1], "predicted: expected integer labels"),
    ([True, False], [1, 1], "predicted: expected integer labels"),
    ([], [], "empty"),
])
def test_bad_input_is_named(predicted, truth, match):
    with pytest.raises(ValueError, match=match):
        misclassification_error(predicted, truth)
