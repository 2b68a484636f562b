"""Commands ``clap-unified stitch`` and ``clap-unified fit homography``.

Bad input (a missing or unreadable image or CSV, a folder, an image over
:data:`MAX_IMAGE_PIXELS`, an unwritable output, ``--hypotheses`` times the matches over
:data:`~clap_unified.io.MAX_WORK`) raises ``ValueError``: the command prints
one line and exits with status 2. A failed estimate (fewer than 8 matches, no consensus,
fewer matches agreeing with it than a minimal sample, a homography that gives no plausible
panorama) is a result with ``success: false`` and a ``reason``: status 1.

``fit homography`` reports what :func:`~clap_unified.imaging.estimate.estimate_homography`
returns on the same matches, seed and options: the same success, reason, model and inliers
(one success rule, :func:`~clap_unified.fitting.fit`'s; the command adds none of its own).
Only fewer than 8 matches differ in form: the library raises ``ValueError``, the command
reports a failed estimate.
Either way no panorama file is written: it is written to a temporary file next to the
target and renamed only on success.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import numpy as np

from ..io import MAX_HYPOTHESES, MAX_WORK, check_budget, float_option, int_option, read_points_csv
from ..presets import protocol_presets
from ..result import ConsensusResult
from ..spaces.homography import DEFAULT_THRESHOLD, HomographySpace
from .estimate import MIN_MATCHES, PROTOCOLS, estimate_homography, method_names

__all__ = ["DEFAULT_METHOD", "MAX_IMAGE_PIXELS", "MAX_MATCHES", "add_fit_homography",
           "fit_homography_command", "method_help", "register", "stitch_command"]

#: ``--method`` choices: the protocols and every registered homography strategy.
METHODS = method_names()

#: Images with more pixels are refused: SIFT and the panorama canvas grow with the pixels, in
#: time and in memory.
MAX_IMAGE_PIXELS = 25_000_000

#: ``fit homography`` reads at most this many matches (images give thousands): every method
#: should answer within a few seconds there; ``bench/bench_cli_limits.py`` runs the command
#: at this limit and prints the time and memory it takes.
MAX_MATCHES = 100_000

#: ``--method``'s default.
DEFAULT_METHOD = "clap"


def method_help() -> str:
    """``--method``'s help, written from the presets (their protocol names, in their order,
    with their labels; the peers' presets grouped), so that it cannot drift from them.

    Examples
    --------
    >>> method_help()[:70]
    "homography estimator (default clap): clap (the library's CLAP), clap_p"
    """
    presets = protocol_presets(HomographySpace.name)
    ours = [f"{name} ({p.label})" if p.label else name
            for name, p in presets.items() if "peer" not in p.aliases]
    peers = [name for name, p in presets.items() if "peer" in p.aliases]
    others = [name for name in METHODS if name not in presets]
    text = f"homography estimator (default {DEFAULT_METHOD}): {', '.join(ours)}"
    if peers:
        text += f", or another library's estimator ({', '.join(peers)})"
    if others:
        text += f"; also registered: {', '.join(others)}"
    return text


def _budgets() -> str:
    """The protocols' budgets, e.g. ``"1000 (clap, ransac), 400 (clap_paper)"``."""
    by = {}
    for name, protocol in PROTOCOLS.items():
        by.setdefault(protocol.get("n_hypotheses", 1000), []).append(name)
    return ", ".join(f"{n} ({', '.join(names)})" for n, names in by.items())


def _add_hypotheses(p) -> None:
    """``--hypotheses H``: override the protocol's ``n_hypotheses`` (default: keep it)."""
    cap = PROTOCOLS["clap"]["max_hypotheses"]
    p.add_argument("--hypotheses", type=int_option(1, MAX_HYPOTHESES), default=None, metavar="H",
                   help=f"hypotheses (CLAP, randomized Hough), trials (RANSAC) or the iteration "
                        f"cap (the other libraries' estimators); default the method's protocol: "
                        f"{_budgets()}; clap draws up to {cap} (or H if more) when few "
                        f"matches agree; at most {MAX_HYPOTHESES}, and hypotheses x matches at "
                        f"most {MAX_WORK:.0e}")


def _budget(args, n: int) -> dict:
    """``{"n_hypotheses": H}`` when ``--hypotheses`` is given (checked against ``n`` data),
    else nothing: the protocol's budget."""
    if args.hypotheses is None:
        return {}
    check_budget(args.method, args.hypotheses, n)
    return {"n_hypotheses": args.hypotheses}


def register(sub) -> None:
    """Add ``stitch``."""
    p = sub.add_parser(
        "stitch", help="stitch RIGHT into LEFT's frame (SIFT + homography)",
        description="Match SIFT features of LEFT and RIGHT (Lowe's ratio test), estimate the "
                    "homography H from LEFT to RIGHT, warp RIGHT into LEFT's frame on a "
                    "canvas holding both, blend, and write the panorama to OUT. The JSON's "
                    "model is {\"H\": 3 x 3 row-major, H33 = 1}, plus matches, blend, output "
                    "and size [width, height]. Fewer than "
                    f"{MIN_MATCHES} matches, or a homography that gives no plausible "
                    "panorama, is a failed estimate (exit 1) and OUT is not written.")
    p.add_argument("left", metavar="LEFT",
                   help=f"left image file (any format OpenCV reads: PNG, JPEG, ...; at most "
                        f"{MAX_IMAGE_PIXELS // 10**6} megapixels)")
    p.add_argument("right", metavar="RIGHT", help="right image file (as LEFT)")
    p.add_argument("-o", "--output", required=True, metavar="OUT",
                   help="panorama file to write (.png or .jpg); its folder must exist; "
                        "written only on success")
    p.add_argument("--method", choices=METHODS, default=DEFAULT_METHOD,
                   help=method_help())
    p.add_argument("--blend", choices=["none", "overwrite", "feather"], default="feather",
                   help="how the overlap is blended: none (overlay), overwrite, feather "
                        "(distance-transform weights; default)")
    p.add_argument("--seed", type=int_option(), default=0, help="random seed (default 0)")
    p.add_argument("--ratio", type=float_option(0.0, 1.0), default=0.75,
                   help="Lowe's ratio test for SIFT matches, in (0, 1] (default 0.75)")
    _add_hypotheses(p)
    p.set_defaults(run=stitch_command)


def add_fit_homography(kinds) -> None:
    """Add ``fit homography`` to the ``fit`` command's sub-parsers."""
    p = kinds.add_parser(
        "homography", help="fit a homography to MATCHES.csv (rows x1,y1,x2,y2)",
        description="Fit the homography H mapping point 1 to point 2 of the matches in "
                    "MATCHES.csv. The JSON's model is {\"H\": 3 x 3 row-major, H33 = 1}, plus "
                    f"matches. Fewer than {MIN_MATCHES} matches, or an estimate that fit's "
                    "success rule fails (fewer inliers than a minimal sample of 4, no "
                    "consensus), is a failed estimate (exit 1); otherwise the answer is "
                    "estimate_homography's on the same matches and seed.")
    p.add_argument("matches", metavar="MATCHES.csv",
                   help=f"CSV file, one match per row: x1,y1,x2,y2 in pixels (the VPG "
                        f"correspondence format; header line optional; at most {MAX_MATCHES} "
                        "rows)")
    p.add_argument("--method", choices=METHODS, default=DEFAULT_METHOD,
                   help=method_help())
    p.add_argument("--seed", type=int_option(), default=0, help="random seed (default 0)")
    p.add_argument("--threshold", type=float_option(), default=DEFAULT_THRESHOLD,
                   help=f"inlier reprojection error in pixels (default {DEFAULT_THRESHOLD:g})")
    _add_hypotheses(p)
    p.set_defaults(run=fit_homography_command)


def _failure(method: str, reason: str, n: int, threshold=None) -> ConsensusResult:
    return ConsensusResult.failure(method, reason, n_data=n, space=HomographySpace(),
                                   threshold=threshold)


def _estimate(matches: np.ndarray, method: str, where: str, **options) -> ConsensusResult:
    """The homography of ``matches`` (:func:`estimate_homography`'s answer, unchanged), or a
    failed result when there are too few matches to ask it."""
    n = len(matches)
    if n < MIN_MATCHES:
        return _failure(method, f"too few matches {where} ({n}; at least {MIN_MATCHES} are "
                                "needed)", n, options.get("threshold"))
    return estimate_homography(matches, method, **options)


def _hypotheses_text(budget: dict) -> str:
    """``", H hypotheses"`` for the progress bar when ``--hypotheses`` is given, else ``""``."""
    return f", {budget['n_hypotheses']} hypotheses" if budget else ""


def fit_homography_command(args) -> dict:
    args.progress.stage("reading matches")
    matches = read_points_csv(args.matches, columns=4, min_rows=1, max_rows=MAX_MATCHES)
    budget = _budget(args, len(matches))
    args.progress.stage(f"fitting ({args.method}{_hypotheses_text(budget)})")
    res = _estimate(matches, args.method, f"in {args.matches}", rng=args.seed,
                    threshold=args.threshold, **budget)
    return {**res.to_dict(), "matches": len(matches)}


def read_image_checked(path, name: str) -> np.ndarray:
    """The image at ``path`` (BGR ``uint8``), or a ``ValueError`` naming ``name`` and the file:
    missing, a folder, unreadable, over :data:`MAX_IMAGE_PIXELS`."""
    import cv2

    from ..io import check_input_file

    try:
        p = check_input_file(path, "image")
    except ValueError as exc:
        raise ValueError(f"{name}: {exc}") from None
    size = _header_size(p)
    if size is not None and size[0] * size[1] > MAX_IMAGE_PIXELS:
        raise ValueError(f"{name}: {p}: more than {MAX_IMAGE_PIXELS:,} pixels "
                         f"({size[0]} x {size[1]})")
    buf = np.fromfile(p, dtype=np.uint8)
    level = cv2.utils.logging.getLogLevel()
    cv2.utils.logging.setLogLevel(cv2.utils.logging.LOG_LEVEL_SILENT)  # our one line says it
    try:
        img = cv2.imdecode(buf, cv2.IMREAD_COLOR) if buf.size else None
    except cv2.error:
        img = None
    finally:
        cv2.utils.logging.setLogLevel(level)
    if img is None or img.size == 0:
        raise ValueError(f"{name}: {p}: not a readable image")
    if img.shape[0] * img.shape[1] > MAX_IMAGE_PIXELS:
        raise ValueError(f"{name}: {p}: more than {MAX_IMAGE_PIXELS:,} pixels "
                         f"({img.shape[1]} x {img.shape[0]})")
    return img


def _header_size(path: Path):
    """``(width, height)`` from the image header without decoding it, or None."""
    import warnings

    try:
        from PIL import Image
    except ImportError:  # pragma: no cover - Pillow comes with matplotlib
        return None
    bomb, Image.MAX_IMAGE_PIXELS = Image.MAX_IMAGE_PIXELS, None  # the size, whatever it is:
    try:  # the header alone is read, and the caller compares it with its own limit
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            with Image.open(path) as im:
                return im.size
    except Exception:  # not an image Pillow knows: OpenCV decides
        return None
    finally:
        Image.MAX_IMAGE_PIXELS = bomb


def stitch_command(args) -> dict:
    import cv2

    from .features import sift_matches
    from .stitching import StitchError, stitch

    out = Path(args.output)
    if out.is_dir():
        raise ValueError(f"--output: {out} is a folder; give a file name such as pano.png")
    if not out.parent.is_dir():
        raise ValueError(f"--output: the folder {out.parent} of {out} does not exist")
    if not cv2.haveImageWriter(str(out)):
        raise ValueError(f"--output: {out}: OpenCV cannot write images with this extension "
                         "(use .png or .jpg)")
    for name, image in (("LEFT", args.left), ("RIGHT", args.right)):
        if out.exists() and Path(image).exists() and os.path.samefile(out, image):
            raise ValueError(f"--output: {out} is the {name} image; give another file for the "
                             "panorama")
    args.progress.stage("reading images")
    left = read_image_checked(args.left, "LEFT")
    right = read_image_checked(args.right, "RIGHT")
    args.progress.stage("matching SIFT features")
    matches, _ = sift_matches(left, right, ratio=args.ratio)
    budget = _budget(args, len(matches))
    args.progress.stage(f"estimating the homography ({args.method}{_hypotheses_text(budget)})")
    res = _estimate(matches, args.method,
                    f"between {args.left} and {args.right} (passing the ratio test)",
                    rng=args.seed, **budget)
    extra = {"matches": len(matches), "blend": args.blend, "output": None, "size": None}
    if not res.success:
        return {**res.to_dict(), **extra}
    args.progress.stage("warping and blending")
    try:
        pano = stitch(left, right, np.asarray(res.model), blend=args.blend)
    except StitchError as exc:
        res = res.replace(success=False, reason=f"no plausible panorama ({exc})")
        return {**res.to_dict(), **extra}
    args.progress.stage("writing the panorama")
    _write_atomic(out, pano)
    return {**res.to_dict(), **extra, "output": str(out),
            "size": [int(pano.shape[1]), int(pano.shape[0])]}


def _write_atomic(out: Path, image: np.ndarray) -> None:
    """Write ``image`` to a temporary file next to ``out``, then rename: never a half-written
    panorama."""
    import cv2

    try:
        fd, tmp = tempfile.mkstemp(suffix=out.suffix or ".png", prefix=f".{out.stem}.",
                                   dir=out.parent)
    except OSError as exc:
        raise OSError(f"--output: {out}: cannot write in {out.parent} ({exc.strerror})") \
            from None
    umask = os.umask(0)
    os.umask(umask)
    os.fchmod(fd, 0o666 & ~umask)  # as open() would, not mkstemp's owner-only 0600
    os.close(fd)
    try:
        try:
            written = cv2.imwrite(tmp, image)
        except cv2.error as exc:
            raise OSError(f"--output: {out}: cannot write the panorama ({exc})") from None
        if not written:
            raise OSError(f"--output: {out}: cannot write the panorama")
        os.replace(tmp, out)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)
