"""Images: homography estimation from point matches and image stitching.

* :mod:`.estimate`: :func:`estimate_homography`, :func:`~clap_unified.fit`
  in a :class:`~clap_unified.spaces.HomographySpace` with each method's
  protocol (:data:`PROTOCOLS`, derived from the presets of
  :mod:`clap_unified.presets`): CLAP (the library's and the paper's), DLT +
  RANSAC, a randomized Hough on CLAP's candidates and OpenCV's estimators
  (:mod:`clap_unified.external.opencv`) on the same matches;
* the reweighted-DLT polish (the library's default CLAP, and ``"clap_densest"``)
  is the homography space's refinement with ``polish``
  (:mod:`clap_unified.spaces.homography_polish`); the paper's protocols refit
  on the inliers without it;
* :mod:`.metrics`: Lie distance to ground truth, corner error, symmetric
  reprojection error;
* :mod:`.features`: SIFT and the ratio test; :mod:`.stitching`: warping and
  blending into one panorama;
* :mod:`.segmentation_metrics`: the misclassification error of a multi-model
  labelling (the AdelaideRMF measure);
* :mod:`.datasets`: homogr / EVD, VPG (real layout), a synthetic VPG-layout
  generator and AdelaideRMF (multi-model fitting).
"""

from .estimate import (
    DEFAULT_PROTOCOL,
    MIN_MATCHES,
    PROTOCOLS,
    clap_homography,
    estimate_homography,
    ransac_homography,
)

__all__ = ["DEFAULT_PROTOCOL", "MIN_MATCHES", "PROTOCOLS", "clap_homography",
           "estimate_homography", "ransac_homography"]
