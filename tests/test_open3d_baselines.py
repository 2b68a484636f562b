"""Open3D wrappers and the generated point-cloud scene (small and fast)."""

import numpy as np

from clap_unified.localization.localize3d import align_correspondences, pose_errors
from clap_unified.localization.open3d_baselines import (
    feature_correspondences,
    fpfh_features,
    open3d_fgr,
    scene_point_clouds,
)
from clap_unified.spaces.rigid3d import Correspondence3DSpace


def test_scene_is_seeded_and_the_truth_relates_the_scans():
    a = scene_point_clouds(n_points=3000, rng=5)
    b = scene_point_clouds(n_points=3000, rng=5)
    assert np.array_equal(a.input.source, b.input.source)
    assert np.array_equal(a.truth.pose, b.truth.pose)
    # every source point, moved by the truth, lies near some target surface sample
    from scipy.spatial import cKDTree

    T = a.truth.pose
    moved = a.input.source @ T[:3, :3].T + T[:3, 3]
    d, _ = cKDTree(a.input.target).query(moved)
    overlap = moved[:, 0] < 0.9
    assert np.median(d[overlap]) < 0.06


def test_fpfh_pipeline_and_clap_on_feature_correspondences():
    sc = scene_point_clouds(n_points=12000, rng=1)
    ps, fs, pd, pf = fpfh_features(sc.input.source, 0.06)
    pt, ft, td, tf = fpfh_features(sc.input.target, 0.06)
    assert fs.shape == (len(ps), 33) and ft.shape == (len(pt), 33)
    pairs = feature_correspondences(fs, ft)
    assert pairs.ndim == 2 and pairs.shape[1] == 2 and len(pairs) > 100
    mutual = set(map(tuple, pairs))
    assert len(mutual) == len(pairs)
    data = np.c_[ps[pairs[:, 0]], pt[pairs[:, 1]]]
    space = Correspondence3DSpace(distance_tolerance=0.06, inlier_threshold=0.09)
    res = align_correspondences(data, n_hypotheses=300_000, space=space, bandwidth=0.3,
                                threshold=0.09, rng=0)
    assert res
    e_t, e_r = pose_errors(res.model, sc.truth.pose)
    assert e_t < 0.15 and e_r < 5.0
    T, seconds = open3d_fgr(pd, td, pf, tf, threshold=0.09)
    assert T.shape == (4, 4) and seconds > 0


_AGREEMENT_SCRIPT = """
import hashlib
import numpy as np
from clap_unified.localization.localize3d import localize3d, pose_errors
from clap_unified.localization.map3d import lab_map
from clap_unified.localization.open3d_baselines import (feature_correspondences, fpfh_features,
                                                        scene_point_clouds)
from clap_unified.localization.scene3d import mocap_trajectory, simulate_detections

sc = scene_point_clouds(n_points=6000, rng=2)
ps, fs, _, _ = fpfh_features(sc.input.source, 0.06)
pt, ft, _, _ = fpfh_features(sc.input.target, 0.06)
pairs = feature_correspondences(fs, ft)
print(hashlib.sha256(sc.input.source.tobytes() + fs.tobytes() + ft.tobytes()).hexdigest())
print(len(pairs), pairs[:20].tolist())
lab = lab_map()
T = mocap_trajectory(20, rng=0)
for f in (3, 11):
    det = simulate_detections(lab, T[f], outlier_ratio=0.7, rng=f)
    res = localize3d(det.input, lab, rng=f)
    e_t, e_r = pose_errors(res.model, det.truth.pose)
    print(f, res.n_inliers, f"{100 * e_t:.2f} cm {e_r:.3f} deg")
"""


def test_chapter_computations_print_the_same_with_one_and_two_blas_threads():
    """A short chapter-4 computation in fresh processes: 1 and 2 OpenBLAS threads agree.

    The point-cloud scans, their FPFH features and matches must agree bit for bit
    (the scans are computed without BLAS), and the printed localization results
    exactly, so a knife edge shows up here and not on a reader's machine.
    ``OPENBLAS_CORETYPE`` is left as the machine has it.
    """
    import os
    import subprocess
    import sys

    outputs = []
    for threads in ("1", "2"):
        env = dict(os.environ, OPENBLAS_NUM_THREADS=threads, OMP_NUM_THREADS="1",
                   OPEN3D_DISABLE_WEB_VISUALIZER="true")
        run = subprocess.run([sys.executable, "-c", _AGREEMENT_SCRIPT], env=env,
                             capture_output=True, text=True, timeout=600)
        assert run.returncode == 0, run.stderr[-2000:]
        outputs.append(run.stdout)
    assert outputs[0] == outputs[1]
    assert len(outputs[0].splitlines()) == 4
