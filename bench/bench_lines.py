"""Benchmark: line fitting by the library against scikit-image and OpenCV.

One seeded scene (default 1,000 points, 50 % outliers, noise 0.05 across the
line ``y = 0.3 x + 1``); every method runs ``--repeat`` times on it and the
table shows the median and best wall-clock time, the median's ratio to
``skimage.measure.ransac`` and to ``cv2.HoughLinesPointSet``, and the angle
error of the fitted line. CLAP runs twice: in ``LineSpace.for_data(points)``
(the ``(theta, rho)`` chart distance of chapters 1 and 2, an ``H x H``
matrix) and as :func:`~clap_unified.fit_line` runs it (the anchor-transfer
metric, neighbour queries on a k-d tree). Not a test: run it with ``make bench`` or
``python bench/bench_lines.py``.
"""

from __future__ import annotations

import argparse
import os
import platform
import time

import cv2
import numpy as np
import skimage
from skimage.measure import LineModelND
from skimage.measure import ransac as skimage_ransac

from clap_unified import LineSpace, fit_line
from clap_unified.clap import clap
from clap_unified.geometry import Line2D, canonical_lines
from clap_unified.hough import hough_lines, randomized_hough
from clap_unified.ransac import ransac
from clap_unified.viz import format_table, line_errors, line_scene


class CountingLineModel(LineModelND):
    """``LineModelND`` that counts its estimates (RANSAC trials plus one final refit)."""

    calls = 0

    @classmethod
    def from_estimate(cls, data):
        cls.calls += 1
        return super().from_estimate(data)


def skimage_line(points, threshold, trials, seed):
    """``skimage.measure.ransac`` with ``LineModelND``; returns ``(theta, rho)``."""
    model, _ = skimage_ransac(points, CountingLineModel, min_samples=2,
                              residual_threshold=threshold, max_trials=trials, rng=seed)
    d = model.direction
    normal = np.array([-d[1], d[0]])
    return Line2D.from_normal_offset(normal, normal @ model.origin)


def cv2_line(points, rho_step, theta_step=np.pi / 180):
    """Strongest line of ``cv2.HoughLinesPointSet`` as ``(theta, rho)``."""
    reach = float(np.abs(points).max()) * np.sqrt(2) + rho_step
    found = cv2.HoughLinesPointSet(points.astype(np.float32).reshape(-1, 1, 2), 1, 1,
                                   -reach, reach, rho_step, 0.0, np.pi, theta_step)
    _, rho, theta = found[0]
    return canonical_lines([theta, rho])


def time_runs(fn, repeat):
    """Call ``fn`` ``repeat`` times; return (median seconds, best seconds, last result)."""
    times, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return float(np.median(times)), float(np.min(times)), out


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--points", type=int, default=1000, help="points (default 1000)")
    parser.add_argument("--outliers", type=float, default=0.5,
                        help="outlier ratio (default 0.5)")
    parser.add_argument("--noise", type=float, default=0.05,
                        help="noise standard deviation across the line (default 0.05)")
    parser.add_argument("--hypotheses", type=int, default=1000,
                        help="hypotheses / RANSAC trials (default 1000)")
    parser.add_argument("--repeat", type=int, default=5, help="runs per method (default 5)")
    parser.add_argument("--seed", type=int, default=0, help="scene seed (default 0)")
    args = parser.parse_args(argv)

    scene = line_scene(args.points, args.outliers, noise=args.noise, rng=args.seed)
    pts, truth = scene.input.points, scene.truth  # methods see pts; truth only scores
    space = LineSpace.for_data(pts)
    t = 3.0 * args.noise
    h = args.hypotheses
    dr = hough_lines(pts, space=space, threshold=t).diagnostics["rho_resolution"]

    methods = {
        "hough_lines": lambda: hough_lines(pts, space=space, threshold=t).model,
        "randomized_hough": lambda: randomized_hough(space, pts, n_hypotheses=h, cell_size=2 * t,
                                                     threshold=t, rng=1).model,
        "ransac": lambda: ransac(space, pts, n_hypotheses=h, threshold=t, rng=1).model,
        "clap (chart metric)": lambda: clap(space, pts, n_hypotheses=h, threshold=t,
                                            rng=1).model,
        "clap (fit_line default)": lambda: fit_line(pts, "clap", n_hypotheses=h, threshold=t,
                                                    rng=1).model,
        "skimage.measure.ransac": lambda: skimage_line(pts, t, h, 1),
        "cv2.HoughLinesPointSet": lambda: cv2_line(pts, dr),
    }
    stats = {}
    for name, fn in methods.items():
        fn()  # warm-up: imports, caches
        CountingLineModel.calls = 0
        med, best, model = time_runs(fn, args.repeat)
        stats[name] = (med, best, float(line_errors(model, truth.line)[0]))
        if name == "skimage.measure.ransac":
            sk_trials = CountingLineModel.calls // args.repeat - 1

    print(f"scene: {args.points} points, {args.outliers:.0%} outliers, noise {args.noise:g}, "
          f"threshold {t:g}, seed {args.seed}; {h} hypotheses / trials; "
          f"{args.repeat} runs per method")
    print(f"numpy {np.__version__}, scikit-image {skimage.__version__}, "
          f"opencv {cv2.__version__}, python {platform.python_version()}, "
          f"{os.cpu_count()} CPUs")
    ref_sk = stats["skimage.measure.ransac"][0]
    ref_cv = stats["cv2.HoughLinesPointSet"][0]
    rows = [[name, med, best, med / ref_sk, med / ref_cv, err]
            for name, (med, best, err) in stats.items()]
    print(format_table(rows, [("method", "<24"), ("median [s]", "10.5f"), ("best [s]", "8.5f"),
                              ("/ skimage ransac", "16.2f"), ("/ cv2 Hough", "11.1f"),
                              ("angle err [deg]", "15.3f")]))
    print(f"skimage.measure.ransac stopped after {sk_trials} of {h} trials "
          "(adaptive stopping; it has no fixed-budget mode)")


if __name__ == "__main__":
    main()
