"""Benchmark: 6-DoF pose from 50 putative 3D correspondences, 60 % of them wrong.

``--scenes`` seeded scenes (default 20): body-frame points in the camera's
view cone, their world positions under a MoCap-trajectory pose with
range-dependent noise, and 60 % of the world points replaced by random points
of the lab. Each method runs ``--repeat`` times per scene; the table shows
the median time per call over all runs, its ratio to Open3D's
``registration_ransac_based_on_correspondence`` (default convergence
criteria: at most 100,000 iterations, early stop at 0.999 confidence), the
success rate (within 5 cm and 1 degree) and the median translation and
rotation errors. CLAP and RANSAC share one budget of ``--budget`` random
triplets ("(250 triplets)": a quarter of it); "open3d (budget)" caps Open3D at the same
number of iterations; "+ refit" adds the library's inlier refit to Open3D's pose. Open3D's
RANSAC is not reproducible run to run (even seeded), so its rows vary a little.
Not a test: run it with ``make bench`` or ``python bench/bench_localize3d.py``.
Timings on a shared machine are noisy; the ratios come from one run.
"""

from __future__ import annotations

import argparse
import os
import platform
import time

import numpy as np

from clap_unified.localization.localize3d import align_correspondences, pose_errors
from clap_unified.localization.open3d_baselines import open3d_correspondence_ransac
from clap_unified.localization.scene3d import correspondence_scene
from clap_unified.viz import format_table


def open3d_run(data, threshold, iterations, seed):
    n = len(data)
    T, _ = open3d_correspondence_ransac(data[:, :3], data[:, 3:], np.c_[np.arange(n),
                                        np.arange(n)], threshold=threshold,
                                        max_iteration=iterations, seed=seed)
    return T


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--correspondences", type=int, default=50)
    parser.add_argument("--outliers", type=float, default=0.6)
    parser.add_argument("--budget", type=int, default=1000,
                        help="triplets for CLAP and RANSAC (default 1000)")
    parser.add_argument("--scenes", type=int, default=20)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--threshold", type=float, default=0.15, help="inlier distance, m")
    args = parser.parse_args(argv)

    t, b = args.threshold, args.budget
    methods = {
        "clap": lambda d, s: align_correspondences(d, n_hypotheses=b, threshold=t,
                                                   rng=s).model,
        "ransac (same triplets)": lambda d, s: align_correspondences(
            d, method="ransac", n_hypotheses=b, threshold=t, rng=s).model,
        f"clap ({b // 4} triplets)": lambda d, s: align_correspondences(
            d, n_hypotheses=b // 4, threshold=t, rng=s).model,
        f"ransac ({b // 4} triplets)": lambda d, s: align_correspondences(
            d, method="ransac", n_hypotheses=b // 4, threshold=t, rng=s).model,
        "open3d": lambda d, s: open3d_run(d, t, 100000, s),
        "open3d (budget)": lambda d, s: open3d_run(d, t, b, s),
        "open3d + refit": lambda d, s: align_correspondences(
            d, method="open3d", n_hypotheses=100000, threshold=t, rng=s).model,
        "open3d (budget) + refit": lambda d, s: align_correspondences(
            d, method="open3d", n_hypotheses=b, threshold=t, rng=s).model,
    }
    scenes = [correspondence_scene(args.correspondences, args.outliers, s)
              for s in range(args.scenes)]
    for fn in methods.values():  # warm-up: imports, caches
        fn(scenes[0][0], 0)
    stats = {}
    for name, fn in methods.items():
        times, errors = [], []
        for s, (data, truth) in enumerate(scenes):
            for _ in range(args.repeat):
                t0 = time.perf_counter()
                model = fn(data, s)
                times.append(time.perf_counter() - t0)
            errors.append(pose_errors(model, truth) if model is not None else (np.inf, np.inf))
        e = np.array(errors)
        ok = (e[:, 0] < 0.05) & (e[:, 1] < 1.0)
        stats[name] = (float(np.median(times)), ok.mean(), np.median(e[:, 0]),
                       np.median(e[:, 1]))

    print(f"{args.scenes} scenes of {args.correspondences} correspondences, "
          f"{args.outliers:.0%} outliers, threshold {t:g} m; budget {b} triplets; "
          f"{args.repeat} runs per scene and method")
    import open3d

    print(f"numpy {np.__version__}, open3d {open3d.__version__}, "
          f"python {platform.python_version()}, {os.cpu_count()} CPUs, "
          f"OMP_NUM_THREADS={os.environ.get('OMP_NUM_THREADS', 'unset')} (Open3D's RANSAC is "
          "multi-threaded; the library runs on one thread)")
    ref = stats["open3d"][0]
    rows = [[name, med * 1e3, med / ref, ok, et * 100, er]
            for name, (med, ok, et, er) in stats.items()]
    print(format_table(rows, [("method", "<24"), ("median [ms]", "11.3f"),
                              ("/ open3d", "8.2f"), ("success", "7.2f"),
                              ("median e_t [cm]", "15.2f"), ("median e_r [deg]", "16.3f")]))


if __name__ == "__main__":
    main()
