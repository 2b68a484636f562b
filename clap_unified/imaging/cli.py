"""Commands ``clap-unified stitch`` and ``clap-unified fit homography``.

Bad input (unreadable image or CSV, too few matches) and a failed estimate
raise ``ValueError``: the command prints one line and exits with status 2,
and no panorama file is written.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import numpy as np

from ..io import read_points_csv
from .estimate import MIN_MATCHES, estimate_homography, method_names

__all__ = ["fit_homography_command", "register", "stitch_command"]

#: ``--method`` choices: the protocols and every registered homography strategy.
METHODS = method_names()


def register(sub) -> None:
    """Add ``stitch``."""
    p = sub.add_parser("stitch", help="stitch RIGHT into LEFT's frame (SIFT + homography)")
    p.add_argument("left", help="left image file")
    p.add_argument("right", help="right image file")
    p.add_argument("-o", "--output", required=True, help="panorama file to write (e.g. .png)")
    p.add_argument("--method", choices=METHODS, default="clap",
                   help="consensus strategy (default clap)")
    p.add_argument("--blend", choices=["none", "overwrite", "feather"], default="feather")
    p.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    p.add_argument("--ratio", type=float, default=0.75, help="SIFT ratio test (default 0.75)")
    p.set_defaults(run=stitch_command)


def add_fit_homography(kinds) -> None:
    """Add ``fit homography`` to the ``fit`` command's sub-parsers."""
    p = kinds.add_parser("homography",
                         help="fit a homography to MATCHES.csv (rows x1,y1,x2,y2)")
    p.add_argument("matches", help="CSV file, one match per row: x1,y1,x2,y2 (header optional)")
    p.add_argument("--method", choices=METHODS, default="clap",
                   help="consensus strategy (default clap)")
    p.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    p.add_argument("--threshold", type=float, default=3.0,
                   help="inlier reprojection error in pixels (default 3)")
    p.set_defaults(run=fit_homography_command)


def _checked(res, n_matches: int):
    """``res`` when it is a usable estimate; ``ValueError`` saying why otherwise."""
    if not res.success:
        raise ValueError(f"homography estimate failed ({res.reason})")
    if res.n_inliers < MIN_MATCHES:
        raise ValueError(f"homography estimate failed (only {res.n_inliers} of {n_matches} "
                         f"matches agree with it, fewer than {MIN_MATCHES})")
    return res


def _too_few(n: int, where: str) -> None:
    if n < MIN_MATCHES:
        raise ValueError(f"too few matches {where} ({n}; at least {MIN_MATCHES} are needed)")


def fit_homography_command(args) -> dict:
    matches = read_points_csv(args.matches, columns=4, min_rows=1)
    _too_few(len(matches), f"in {args.matches}")
    res = _checked(estimate_homography(matches, args.method, rng=args.seed,
                                       threshold=args.threshold), len(matches))
    return {**res.to_dict(), "matches": len(matches)}


def stitch_command(args) -> dict:
    import cv2

    from .features import match_images
    from .stitching import stitch

    out = Path(args.output)
    if not out.parent.is_dir():
        raise ValueError(f"{out}: the output folder {out.parent} does not exist")
    if not cv2.haveImageWriter(str(out)):
        raise ValueError(f"{out}: OpenCV cannot write images with this extension "
                         "(use .png or .jpg)")
    left, right, matches, quality = match_images(args.left, args.right, ratio=args.ratio)
    _too_few(len(matches), f"between {args.left} and {args.right} (passing the ratio test)")
    res = _checked(estimate_homography(matches, args.method, rng=args.seed), len(matches))
    pano = stitch(left, right, np.asarray(res.model), blend=args.blend)
    # write next to the target, then rename: never a half-written panorama
    fd, tmp = tempfile.mkstemp(suffix=out.suffix or ".png", dir=out.parent)
    os.close(fd)
    try:
        try:
            written = cv2.imwrite(tmp, pano)
        except cv2.error as exc:
            raise OSError(f"{out}: cannot write the panorama ({exc})") from None
        if not written:
            raise OSError(f"{out}: cannot write the panorama")
        os.replace(tmp, out)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)
    return {**res.to_dict(), "matches": len(matches), "blend": args.blend,
            "output": str(out), "size": [int(pano.shape[1]), int(pano.shape[0])]}
