"""Estimators of other libraries, registered as strategies of :func:`~clap_unified.fit`.

Importing this package registers them (the library's ``__init__`` does):

* :mod:`.opencv`: ``"cv2_ransac"``, ``"magsac"`` and ``"usac_ransac_fixed"``,
  OpenCV's robust homography estimators (OpenCV is imported only when one
  runs).
"""

from . import (
    open3d,  # noqa: F401  (registers the Open3D strategy)
    opencv,  # noqa: F401  (registers the OpenCV strategies)
)

__all__ = ["opencv"]
