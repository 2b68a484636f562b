"""Open3D baselines for 6-DoF registration, and a generated point-cloud scene.

Thin wrappers that put numpy arrays into Open3D and take 4 x 4 poses out, so
the chapter, the benchmark and the command line run exactly the same calls:

* :func:`open3d_correspondence_ransac` (defined with the ``"open3d"`` strategy
  in :mod:`clap_unified.external.open3d`, re-exported here):
  ``registration_ransac_based_on_correspondence`` on given correspondences,
  with Open3D's edge-length and distance checkers (the counterpart of the
  triplet distance check of :mod:`clap_unified.spaces.rigid3d`);
* point clouds: :func:`scene_point_clouds` (two seeded scans of one scene
  built from Open3D primitives), :func:`fpfh_features`,
  :func:`feature_correspondences` (mutual nearest neighbours in FPFH space),
  :func:`open3d_feature_ransac` (RANSAC on feature matching) and
  :func:`open3d_fgr` (fast global registration).

Open3D is imported on first use. Its RANSAC does not promise reproducible
results: the seed goes to Open3D's global generator (the only way its API
offers) and its loops run in parallel; repeated runs on the same input have
returned different poses here (an earlier measurement saw it even with
``OMP_NUM_THREADS=1``). On one thread, with the scans below, the book's runs have
agreed across processes and OpenBLAS kernels. The point clouds themselves are
sampled with numpy from a seeded generator and computed without BLAS, so they
(and Open3D's FPFH features of them) are the same bit for bit under any OpenBLAS
kernel and thread count.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from .._validation import as_generator, check_int, check_positive
from ..datatypes import freeze_arrays
from ..external.open3d import _cloud, _o3d, open3d_correspondence_ransac
from ..geometry.se3 import SE3

__all__ = ["open3d_correspondence_ransac", "scene_point_clouds", "fpfh_features",
           "feature_correspondences", "open3d_feature_ransac", "open3d_fgr", "PointCloudScene",
           "PointCloudInput", "PointCloudTruth"]


# ---------------------------------------------------------------- point clouds
@dataclass(frozen=True)
class PointCloudInput:
    """What a registration method may see: the two noisy scans.

    Attributes
    ----------
    source : ndarray of shape (N, 3)
        Second scan, in its own sensor frame.
    target : ndarray of shape (M, 3)
        First scan, in the world frame.
    """

    source: np.ndarray
    target: np.ndarray

    def __post_init__(self):
        freeze_arrays(self)


@dataclass(frozen=True)
class PointCloudTruth:
    """Evaluation data of a scan pair: for scoring only.

    Attributes
    ----------
    pose : ndarray of shape (4, 4)
        True motion ``T_target_source``: ``target ~ pose @ source`` on the overlap.
    source_clean, target_clean : ndarray of shape (N, 3), (M, 3)
        The scans before noise (row for row).
    """

    pose: np.ndarray
    source_clean: np.ndarray
    target_clean: np.ndarray

    def __post_init__(self):
        freeze_arrays(self)


@dataclass(frozen=True)
class PointCloudScene:
    """Two scans of one scene (``input``) and the true motion between them (``truth``).

    Attributes
    ----------
    input : PointCloudInput
    truth : PointCloudTruth
    """

    input: PointCloudInput
    truth: PointCloudTruth


def _rotation(phi) -> np.ndarray:
    """Rodrigues' rotation of a rotation vector with elementwise operations only.

    No matrix product (hence no BLAS call): the scene's points are then the same
    bit for bit whatever OpenBLAS kernel or thread count a machine uses, and so
    are the features Open3D computes from them. (``so3_exp`` multiplies
    matrices, whose last bits depend on the kernel.)
    """
    phi = np.asarray(phi, dtype=float)
    theta = np.sqrt(np.sum(phi * phi))
    if theta == 0.0:
        return np.eye(3)
    x, y, z = phi / theta
    c, s = np.cos(theta), np.sin(theta)
    C = 1.0 - c
    return np.array([[c + x * x * C, x * y * C - z * s, x * z * C + y * s],
                     [y * x * C + z * s, c + y * y * C, y * z * C - x * s],
                     [z * x * C - y * s, z * y * C + x * s, c + z * z * C]])


def _rotate_rows(points, R) -> np.ndarray:
    """``points @ R.T`` by elementwise products and sums in a fixed order (no BLAS)."""
    p = np.asarray(points, dtype=float)
    return (p[:, 0:1] * R[:, 0] + p[:, 1:2] * R[:, 1]) + p[:, 2:3] * R[:, 2]


def _scene_meshes(o3d):
    """A room corner with furniture-like primitives (metres)."""
    parts = []

    def add(mesh, xyz, rot=(0.0, 0.0, 0.0)):
        mesh.rotate(_rotation(np.asarray(rot, dtype=float)), center=(0, 0, 0))
        mesh.translate(xyz)
        parts.append(mesh)

    g = o3d.geometry.TriangleMesh
    add(g.create_box(4.0, 3.0, 0.02), (-2.0, -1.5, -0.02))                  # floor
    add(g.create_box(4.0, 0.02, 2.0), (-2.0, 1.5, 0.0))                     # back wall
    add(g.create_box(0.02, 3.0, 2.0), (-2.0, -1.5, 0.0))                    # side wall
    add(g.create_box(0.8, 0.5, 0.7), (-1.5, 0.6, 0.0), (0, 0, 0.3))         # cabinet
    add(g.create_sphere(0.35), (0.6, 0.2, 0.35))
    add(g.create_cylinder(0.2, 1.2), (-0.4, -0.6, 0.6))
    add(g.create_cone(0.3, 0.8), (1.2, -0.8, 0.0))
    add(g.create_torus(0.4, 0.12), (0.9, 0.9, 0.8), (1.2, 0.0, 0.4))
    add(g.create_box(0.3, 0.3, 1.4), (-1.2, -1.2, 0.0), (0, 0, 0.7))        # column
    return parts


def scene_point_clouds(*, n_points: int = 20000, noise: float = 0.005,
                       rotation_deg: float = 30.0, translation: float = 0.5,
                       rng=None) -> PointCloudScene:
    """Two noisy scans of a generated scene, related by a random rigid motion.

    Each scan samples the scene's surfaces (Open3D primitives: a floor, two
    walls, a cabinet, a sphere, a cylinder, a cone, a torus, a column)
    independently, keeps the part seen from its own side (partial overlap),
    and adds Gaussian noise. The second scan is expressed in a frame moved
    by a random rotation of ``rotation_deg`` degrees and a translation of
    ``translation`` metres.

    The points are computed without matrix products, so a seed gives the
    same scans bit for bit under any OpenBLAS kernel and thread count (the
    FPFH features Open3D computes from them, and their matches, then agree
    too; with ``@`` the last bits, and with them a few feature matches,
    changed between kernels).

    Parameters
    ----------
    n_points : int
        Points sampled per scan before cropping.
    noise : float
        Per-axis noise, metres.
    rotation_deg, translation : float
        Size of the true motion.
    rng : None, int or numpy.random.Generator

    Returns
    -------
    PointCloudScene
        ``input``: the two noisy scans; ``truth``: the motion and the scans
        before noise.
    """
    o3d = _o3d()
    g = as_generator(rng)
    n_points = check_int(n_points, "n_points", minimum=100)
    meshes = _scene_meshes(o3d)

    tris = [np.asarray(m.vertices)[np.asarray(m.triangles)] for m in meshes]  # (T, 3, 3) each
    tris = np.concatenate(tris)
    tri_area = 0.5 * np.linalg.norm(np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]),
                                    axis=1)

    def scan(keep_side):
        # uniform on the surfaces: area-weighted triangles, uniform barycentric coordinates
        k = g.choice(len(tris), n_points, p=tri_area / tri_area.sum())
        u, v = g.random(n_points), g.random(n_points)
        flip = u + v > 1
        u[flip], v[flip] = 1 - u[flip], 1 - v[flip]
        t = tris[k]
        pts = t[:, 0] + u[:, None] * (t[:, 1] - t[:, 0]) + v[:, None] * (t[:, 2] - t[:, 0])
        pts = pts[keep_side(pts)]
        return pts, pts + g.normal(0, noise, pts.shape)

    target_clean, target = scan(lambda p: p[:, 0] < 1.0)
    world_clean, world_src = scan(lambda p: p[:, 0] > -1.2)
    axis = g.normal(size=3)
    axis /= np.sqrt(np.sum(axis * axis))
    direction = g.normal(size=3)
    direction /= np.sqrt(np.sum(direction * direction))
    R = _rotation(np.radians(rotation_deg) * axis)
    truth = SE3.from_rt(R, translation * direction)
    source = _rotate_rows(world_src - truth[:3, 3], R.T)  # truth^-1 applied
    source_clean = _rotate_rows(world_clean - truth[:3, 3], R.T)
    return PointCloudScene(PointCloudInput(source, target),
                           PointCloudTruth(truth, source_clean, target_clean))


def fpfh_features(points, voxel: float):
    """Voxel-downsampled points ``(K, 3)`` and their FPFH descriptors ``(K, 33)``.

    Normals from a ``2 voxel`` radius (30 neighbours at most), FPFH from a
    ``5 voxel`` radius (100 at most), as in Open3D's global registration
    tutorial. Also returns the Open3D cloud and feature for the Open3D
    registrations.
    """
    o3d = _o3d()
    voxel = check_positive(voxel, "voxel")
    down = _cloud(points).voxel_down_sample(voxel)
    down.estimate_normals(o3d.geometry.KDTreeSearchParamHybrid(radius=2 * voxel, max_nn=30))
    feat = o3d.pipelines.registration.compute_fpfh_feature(
        down, o3d.geometry.KDTreeSearchParamHybrid(radius=5 * voxel, max_nn=100))
    return np.asarray(down.points).copy(), np.asarray(feat.data).T.copy(), down, feat


def feature_correspondences(source_features, target_features, *, mutual: bool = True):
    """Nearest neighbours in descriptor space, ``(K, 2)`` rows ``(source, target)``.

    ``mutual`` keeps only pairs that are each other's nearest neighbour.
    """
    from scipy.spatial import cKDTree

    fs = np.asarray(source_features, dtype=float)
    ft = np.asarray(target_features, dtype=float)
    _, s2t = cKDTree(ft).query(fs)
    pairs = np.c_[np.arange(len(fs)), s2t]
    if mutual:
        _, t2s = cKDTree(fs).query(ft)
        pairs = pairs[t2s[s2t] == np.arange(len(fs))]
    return pairs.astype(np.intp)


def open3d_feature_ransac(source_down, target_down, source_feat, target_feat, *,
                          threshold: float, mutual: bool = True, max_iteration: int = 100000,
                          confidence: float = 0.999, seed: int = 0):
    """``registration_ransac_based_on_feature_matching`` (Open3D clouds and features).

    Returns ``(T, seconds)`` with ``T = T_target_source``.
    """
    o3d = _o3d()
    reg = o3d.pipelines.registration
    o3d.utility.random.seed(int(seed))
    t0 = time.perf_counter()
    res = reg.registration_ransac_based_on_feature_matching(
        source_down, target_down, source_feat, target_feat, mutual, threshold,
        reg.TransformationEstimationPointToPoint(False), 3,
        [reg.CorrespondenceCheckerBasedOnEdgeLength(0.9),
         reg.CorrespondenceCheckerBasedOnDistance(threshold)],
        reg.RANSACConvergenceCriteria(max_iteration, confidence))
    return np.asarray(res.transformation).copy(), time.perf_counter() - t0


def open3d_fgr(source_down, target_down, source_feat, target_feat, *, threshold: float):
    """Open3D's fast global registration on feature matching; returns ``(T, seconds)``."""
    o3d = _o3d()
    reg = o3d.pipelines.registration
    t0 = time.perf_counter()
    res = reg.registration_fgr_based_on_feature_matching(
        source_down, target_down, source_feat, target_feat,
        reg.FastGlobalRegistrationOption(maximum_correspondence_distance=threshold))
    return np.asarray(res.transformation).copy(), time.perf_counter() - t0
