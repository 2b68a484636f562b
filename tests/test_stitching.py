"""Warping and blending, and the refusal of homographies that cannot give a panorama."""

import numpy as np
import pytest

from clap_unified.imaging.features import read_image, sift_matches
from clap_unified.imaging.stitching import StitchError, panorama_canvas, stitch

LEFT = np.full((40, 60, 3), 100, np.uint8)
RIGHT = np.full((40, 60, 3), 200, np.uint8)
SHIFT = np.array([[1.0, 0, -30], [0, 1, 0], [0, 0, 1]])  # right image starts at x = 30


def test_canvas_holds_both_images():
    (w, h), T = panorama_canvas(SHIFT, LEFT.shape, RIGHT.shape)
    assert (w, h) == (90, 40) and np.allclose(T, np.eye(3))
    (w, h), T = panorama_canvas(np.linalg.inv(SHIFT), LEFT.shape, RIGHT.shape)
    assert (w, h) == (90, 40) and T[0, 2] == 30


@pytest.mark.parametrize("blend,overlap", [("none", 150), ("overwrite", 200)])
def test_overlay_and_overwrite(blend, overlap):
    pano = stitch(LEFT, RIGHT, SHIFT, blend=blend)
    assert pano.shape == (40, 90, 3)
    assert pano[20, 10, 0] == 100 and pano[20, 80, 0] == 200 and pano[20, 45, 0] == overlap


def test_feather_ramps_across_the_overlap():
    row = stitch(LEFT, RIGHT, SHIFT, blend="feather")[20, 30:60, 0].astype(int)
    assert np.all(np.diff(row) >= 0) and row[0] < 130 and row[-1] > 170


def test_degenerate_homographies_are_refused():
    with pytest.raises(StitchError, match="singular"):
        stitch(LEFT, RIGHT, np.zeros((3, 3)))
    behind = np.array([[1.0, 0, 0], [0, 1, 0], [0.05, 0, -1]])  # horizon inside the image
    with pytest.raises(StitchError, match="in front"):
        stitch(LEFT, RIGHT, behind)
    huge = np.diag([1e-4, 1e-4, 1.0])
    with pytest.raises(StitchError, match="plausible"):
        stitch(LEFT, RIGHT, huge)
    with pytest.raises(ValueError, match="blend"):
        stitch(LEFT, RIGHT, SHIFT, blend="multiband")


def test_read_image_and_matching_edge_cases(tmp_path):
    with pytest.raises(ValueError, match="no such image"):
        read_image(tmp_path / "none.png")
    bad = tmp_path / "bad.png"
    bad.write_bytes(b"\x89PNG broken")
    with pytest.raises(ValueError, match="not a readable image"):
        read_image(bad)
    m, q = sift_matches(np.zeros((50, 50), np.uint8), np.zeros((50, 50), np.uint8))
    assert m.shape == (0, 4) and q.shape == (0,)
