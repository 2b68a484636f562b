"""Estimators of other libraries, registered as strategies of :func:`~clap_unified.fit`.

Importing this package registers them (the library's ``__init__`` does);
each is a baseline (``Strategy.baseline``), and its library is imported only
when it runs:

* :mod:`.opencv`: ``"cv2_ransac"``, ``"magsac"``, ``"usac_accurate"`` and
  ``"usac_ransac_fixed"``, OpenCV's robust homography and fundamental-matrix
  estimators;
* :mod:`.poselib`: ``"poselib"``, PoseLib's homography and fundamental-matrix
  LO-RANSAC;
* :mod:`.colmap`: ``"colmap"``, COLMAP's homography and fundamental-matrix
  LO-RANSAC (pycolmap);
* :mod:`.open3d`: ``"open3d"``, Open3D's correspondence RANSAC for 3D poses;
* :mod:`.sequential`: the peers in a remove-inliers loop, as segmenters of
  :func:`~clap_unified.segment`.
"""

from . import (
    colmap,  # noqa: F401  (registers the COLMAP strategy)
    open3d,  # noqa: F401  (registers the Open3D strategy)
    opencv,  # noqa: F401  (registers the OpenCV strategies)
    poselib,  # noqa: F401  (registers the PoseLib strategy)
    sequential,  # noqa: F401,E402  (the peers in a remove-inliers loop, as segmenters)
)

__all__ = ["colmap", "open3d", "opencv", "poselib", "sequential"]
