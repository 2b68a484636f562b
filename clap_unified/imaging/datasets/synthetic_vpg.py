"""A VPG-layout stitching set generated from photographs bundled with scikit-image.

Every set views one planar "world" picture (photographs side by side, or a
tiled repetitive texture: brick, grass, gravel, checkerboard) from cameras
that only rotate about a common centre. Image ``i`` is the world picture
warped by ``G_i = K R_i A`` (``A`` puts the picture on the plane ``z = 1``),
so the homography from image ``i`` to image ``j`` is exactly
``H_ij = K R_j R_i^T K^-1`` and the ground-truth correspondences written to
``mNN-MM.txt`` are exact (before the JPEG compression of the images).

The files follow the VPG layout (:mod:`.vpg`): ``Sxx/NN.jpg``,
``mNN-MM.txt`` for every edge of the chain ``1-2, 2-3, ...``,
``camera-NN.txt`` (rotation, position ``0,0,0``) and
``Sxx-STITCH-GRAPH.txt``; ``synthetic.json`` adds ``K`` and the scene.

What is input and what is evaluation data: the generator writes no matches
for an estimator, only the images and the **exact** (noise-free, outlier-free)
ground-truth correspondences, the camera rotations and ``K``. All of these
but the images and the matching graph are evaluation data. The estimator's
matches come from the JPEG images (SIFT and the ratio test, with their
outliers: :func:`clap_unified.imaging.evaluation.vpg_pair_matches`).
:func:`load_synthetic_vpg` writes the sets and reads them back as
:class:`~clap_unified.imaging.datasets.vpg.VPGSet` objects, whose ``input``
holds the images and the graph and whose ``truth`` the correspondences and
cameras.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from ..._validation import as_generator, check_int
from ...geometry.homography_arithmetic import transfer

__all__ = ["SCENES", "load_synthetic_vpg", "make_synthetic_vpg", "scene_picture", "true_homography"]

#: Scene of each generated set, in order: photographs, then repetitive textures.
SCENES = ("astronaut", "coffee", "chelsea", "rocket", "hubble_deep_field", "motorcycle_left",
          "immunohistochemistry", "camera", "brick", "grass", "gravel", "checkerboard")

#: Repetitive textures (tiled) among :data:`SCENES`.
TEXTURES = ("brick", "grass", "gravel", "checkerboard")

#: World picture size (pixels) and its scale on the plane z = 1 (pixels per unit).
WORLD = (1800, 960)
WORLD_SCALE = 1000.0


def _rgb(img) -> np.ndarray:
    img = np.asarray(img)
    if img.ndim == 2:
        img = np.stack([img] * 3, axis=-1)
    img = img[..., :3]
    if img.dtype != np.uint8:
        img = (255 * (img.astype(float) / max(float(img.max()), 1e-12))).astype(np.uint8)
    return img


def scene_picture(name: str, rng=None) -> np.ndarray:
    """The world picture ``(960, 1800, 3)`` uint8 (RGB) of a scene.

    Photographs: the named photograph between two others, resized to the
    world height, side by side, centre crop. Textures: the texture
    tiled (the checkerboard is scikit-image's, 25 px squares).
    """
    import cv2
    from skimage import data

    if name not in SCENES:
        raise ValueError(f"scene: expected one of {list(SCENES)}, got {name!r}")
    w, h = WORLD
    if name in TEXTURES:
        tile = _rgb(data.checkerboard() if name == "checkerboard" else getattr(data, name)())
        reps = (h // tile.shape[0] + 1, w // tile.shape[1] + 1, 1)
        return np.ascontiguousarray(np.tile(tile, reps)[:h, :w])
    g = as_generator(rng)
    photos = [n for n in SCENES[:8] if n != name]
    left, right = g.choice(photos, 2, replace=False)
    names = [str(left), name, str(right)]  # the named photograph in the middle
    parts = []
    for n in names:
        img = _rgb(data.stereo_motorcycle()[0] if n == "motorcycle_left" else getattr(data, n)())
        s = h / img.shape[0]
        parts.append(cv2.resize(img, (int(round(img.shape[1] * s)), h),
                                interpolation=cv2.INTER_AREA))
    strip = np.concatenate(parts, axis=1)
    while strip.shape[1] < w:
        strip = np.concatenate([strip, strip], axis=1)
    start = (strip.shape[1] - w) // 2
    return np.ascontiguousarray(strip[:, start:start + w])


def _rotation(yaw, pitch, roll) -> np.ndarray:
    cy, sy, cp, sp, cr, sr = (np.cos(yaw), np.sin(yaw), np.cos(pitch), np.sin(pitch),
                              np.cos(roll), np.sin(roll))
    Ry = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    Rx = np.array([[1, 0, 0], [0, cp, -sp], [0, sp, cp]])
    Rz = np.array([[cr, -sr, 0], [sr, cr, 0], [0, 0, 1]])
    return Rz @ Rx @ Ry


def true_homography(K, R_i, R_j) -> np.ndarray:
    """``H_ij = K R_j R_i^T K^-1`` (pure rotation), ``H33 = 1``."""
    H = K @ R_j @ R_i.T @ np.linalg.inv(K)
    return H / H[2, 2]


def make_synthetic_vpg(root, *, scenes=SCENES, images_per_set: int = 3,
                       size=(640, 480), focal: float = 700.0, yaw_step_deg: float = 14.0,
                       n_correspondences: int = 120, jpeg_quality: int = 95,
                       rng=0) -> list[Path]:
    """Write one VPG-layout set per scene under ``root`` (``S01``, ``S02``, ...).

    Parameters
    ----------
    root : path
        Created if needed; existing set folders are overwritten.
    scenes : sequence of str
        Scenes from :data:`SCENES`, one set each.
    images_per_set : int
        Images per set (a chain of pairs with overlapping views).
    size : (width, height)
    focal : float
        Focal length in pixels (``K = [[f, 0, w/2], [0, f, h/2], [0, 0, 1]]``).
    yaw_step_deg : float
        Pan between neighbouring images (degrees); a few degrees of random
        pitch and roll are added.
    n_correspondences : int
        Ground-truth correspondences per pair (points of image ``i`` visible
        in image ``j``).
    jpeg_quality : int
    rng : None, int or numpy.random.Generator

    Returns
    -------
    list of Path
        The set folders.

    Examples
    --------
    >>> import tempfile
    >>> from clap_unified.imaging.datasets.vpg import load_vpg_set
    >>> with tempfile.TemporaryDirectory() as d:
    ...     [p] = make_synthetic_vpg(d, scenes=["brick"], images_per_set=2)
    ...     s = load_vpg_set(p)
    ...     print(s.name, sorted(s.input.images), s.pairs(),
    ...           s.truth.correspondences[(1, 2)].shape)
    S01 [1, 2] [(1, 2)] (120, 4)
    """
    import cv2

    g = as_generator(rng)
    n_img = check_int(images_per_set, "images_per_set", minimum=2)
    w, h = size
    K = np.array([[focal, 0.0, w / 2.0], [0.0, focal, h / 2.0], [0.0, 0.0, 1.0]])
    ww, wh = WORLD
    A = np.array([[1 / WORLD_SCALE, 0, -ww / 2 / WORLD_SCALE],
                  [0, 1 / WORLD_SCALE, -wh / 2 / WORLD_SCALE], [0, 0, 1.0]])
    root = Path(root)
    out = []
    for k, scene in enumerate(scenes, start=1):
        world = scene_picture(scene, g)
        folder = root / f"S{k:02d}"
        folder.mkdir(parents=True, exist_ok=True)
        # negative yaw pans right: image k + 1 lies to the right of image k
        yaws = -(np.arange(n_img) - (n_img - 1) / 2) * np.deg2rad(yaw_step_deg)
        Rs = [_rotation(y, *np.deg2rad(g.uniform(-2.0, 2.0, 2))) for y in yaws]
        for i, R in enumerate(Rs, start=1):
            G = K @ R @ A
            img = cv2.warpPerspective(world, G, (w, h), flags=cv2.INTER_LINEAR,
                                      borderMode=cv2.BORDER_REFLECT)
            cv2.imwrite(str(folder / f"{i:02d}.jpg"), img[..., ::-1],
                        [cv2.IMWRITE_JPEG_QUALITY, int(jpeg_quality)])
            rows = [",".join(f"{v:.7g}" for v in r) for r in R] + ["0,0,0"]
            (folder / f"camera-{i:02d}.txt").write_text("\n".join(rows) + "\n")
        lines = [f"{{center_image_index | {(n_img - 1) // 2} | center image index}}",
                 "{center_image_rotation_angle | 0 | center image rotation angle}",
                 f"{{images_count | {n_img} | images count}}"]
        for e in range(n_img - 1):
            lines.append(f"{{matching_graph_image_edges-{e} | {e + 1} | "
                         f"matching graph image edge {e}}}")
            H = true_homography(K, Rs[e], Rs[e + 1])
            pts = np.empty((0, 2))
            for _ in range(20):  # cap: enough points land in the overlap long before
                cand = g.uniform([0, 0], [w, h], (4 * n_correspondences, 2))
                q = transfer(H, cand)
                ok = (q[:, 0] >= 0) & (q[:, 0] < w) & (q[:, 1] >= 0) & (q[:, 1] < h)
                pts = np.concatenate([pts, cand[ok]])[:n_correspondences]
                if len(pts) == n_correspondences:
                    break
            m = np.c_[pts, transfer(H, pts)]
            (folder / f"m{e + 1:02d}-{e + 2:02d}.txt").write_text(
                "\n".join(",".join(f"{v:.6f}" for v in r) for r in m) + "\n")
        (folder / f"S{k:02d}-STITCH-GRAPH.txt").write_text("\n".join(lines) + "\n")
        meta = {"scene": scene, "repetitive": scene in TEXTURES, "K": K.tolist(),
                "size": [w, h], "generator": "clap_unified.imaging.datasets.synthetic_vpg"}
        (folder / "synthetic.json").write_text(json.dumps(meta, indent=1))
        out.append(folder)
    return out


def load_synthetic_vpg(root, **options) -> list:
    """Write the synthetic sets under ``root`` and read them back, split into input and truth.

    Parameters
    ----------
    root : path
        Where to write (see :func:`make_synthetic_vpg`).
    **options
        Passed to :func:`make_synthetic_vpg` (``scenes``, ``images_per_set``,
        ``rng``, ...).

    Returns
    -------
    list of VPGSet
        One per scene: ``input.images`` and ``input.graph`` for the
        estimator, ``truth.correspondences`` (exact), ``truth.cameras`` and
        ``truth.H(i, j)`` for scoring.

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     [s] = load_synthetic_vpg(d, scenes=["brick"], images_per_set=2)
    ...     print(s.name, sorted(s.input.images), s.truth.H(1, 2).shape)
    S01 [1, 2] (3, 3)
    """
    from .vpg import load_vpg_set

    return [load_vpg_set(f) for f in make_synthetic_vpg(root, **options)]
