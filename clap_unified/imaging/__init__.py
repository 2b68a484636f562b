"""Images: homography estimation from point matches and image stitching.

* :mod:`.estimate`: CLAP (the paper's protocol), the library's DLT + RANSAC
  and a randomized Hough on the same candidates; :mod:`.baselines`: OpenCV's
  ``cv2.RANSAC`` and ``cv2.USAC_MAGSAC`` on the same matches;
* :mod:`.metrics`: Lie distance to ground truth, corner error, symmetric
  reprojection error;
* :mod:`.features`: SIFT and the ratio test; :mod:`.stitching`: warping and
  blending into one panorama;
* :mod:`.datasets`: homogr / EVD, VPG (real layout) and a synthetic VPG-layout
  generator.
"""

from .baselines import OPENCV_METHODS, opencv_homography
from .estimate import (
    CLAP_PROTOCOL,
    METHODS,
    clap_homography,
    estimate_homography,
    homography_hypotheses,
    hough_homography,
    ransac_homography,
)

__all__ = ["CLAP_PROTOCOL", "METHODS", "OPENCV_METHODS", "clap_homography",
           "estimate_homography", "homography_hypotheses", "hough_homography",
           "opencv_homography", "ransac_homography"]
