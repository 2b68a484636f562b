"""Synthetic two-view scenes: the truth is exact, the input holds nothing of it."""

import dataclasses

import numpy as np
import pytest

from clap_unified.geometry import sampson_error
from clap_unified.imaging.datasets import MultiModelInput, synthetic_two_view


@pytest.mark.parametrize("motions", [1, 3])
def test_each_motion_s_matches_satisfy_its_F_exactly_without_noise(motions):
    pair = synthetic_two_view(240, outliers=0.2, noise=0.0, motions=motions, rng=1)
    m, lab = pair.input.matches, pair.truth.labels
    for k in range(1, motions + 1):
        err = sampson_error(pair.truth.F[k - 1], m[lab == k, :2], m[lab == k, 2:])
        assert np.max(err) < 1e-6
    # outliers agree with no motion (a few may by chance; most are far)
    far = [np.median(sampson_error(F, m[lab == 0, :2], m[lab == 0, 2:])) for F in pair.truth.F]
    assert min(far) > 5.0


def test_counts_determinism_and_the_input_holds_no_truth():
    a = synthetic_two_view(101, outliers=0.3, motions=2, rng=5)
    b = synthetic_two_view(101, outliers=0.3, motions=2, rng=5)
    np.testing.assert_array_equal(a.input.matches, b.input.matches)
    assert np.bincount(a.truth.labels).tolist() == [30, 36, 35]
    assert {f.name for f in dataclasses.fields(a.input)} == \
        {f.name for f in dataclasses.fields(MultiModelInput)}
    assert not a.input.matches.flags.writeable and not a.truth.F.flags.writeable
    assert np.all(a.input.score == 0)


@pytest.mark.parametrize("kwargs, name", [
    ({"n": 6}, "n"), ({"outliers": 1.0}, "outliers"), ({"outliers": -0.1}, "outliers"),
    ({"noise": -1.0}, "noise"), ({"motions": 0}, "motions"), ({"n": 20, "motions": 3}, "n"),
])
def test_bad_arguments_name_themselves(kwargs, name):
    with pytest.raises(ValueError, match=name):
        synthetic_two_view(**kwargs)
