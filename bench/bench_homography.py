"""Benchmark: homography estimation on homogr and EVD, CLAP against RANSAC and OpenCV.

For every pair of homogr (16) and EVD (15), on the same tentative matches
(``pair.input``: homogr's label 0 rows, never its 8 validation points; every
EVD row):
CLAP with the paper's protocol (400 candidates, 5 rounds of 20 % trimming,
re-estimation on the inliers), CLAP with candidates ordered by match quality
(EVD only, where the SIFT ratio is given), the library's DLT + RANSAC (1000
iterations, refit on the inliers), ``cv2.findHomography`` with ``cv2.RANSAC``
(``maxIters=1000``, OpenCV's default confidence 0.995, so it stops early on
easy pairs), with ``cv2.USAC_MAGSAC``, and plain RANSAC in OpenCV's USAC
framework with exactly 1000 iterations (confidence 1: the paper's fixed
budget in C++). Per pair: wall time (median of
``--repeat`` runs) and the paper's Lie distance ``||log(H_gt^-1 H)||_F`` to
the ground truth, the fraction of ground-truth inliers kept and, on homogr,
the median symmetric reprojection error of the validation points; then
medians per method and their ratios to ``cv2.RANSAC``
and ``cv2.USAC_MAGSAC``. Not a test: run it with ``make bench`` or
``python bench/bench_homography.py``.

OpenBLAS is limited to one thread unless ``OPENBLAS_NUM_THREADS`` is set:
on a shared two-core machine its spinning threads otherwise triple the
library's times. The data come from the homogr / EVD mirror or download
(:mod:`clap_unified.imaging.datasets`).
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import platform  # noqa: E402

import cv2  # noqa: E402
import numpy as np  # noqa: E402

from clap_unified.imaging.datasets import (  # noqa: E402
    evd_names,
    homogr_names,
    load_evd,
    load_homogr,
)
from clap_unified.imaging.evaluation import EVALUATED, evaluate_pair, summarise  # noqa: E402
from clap_unified.viz import format_table  # noqa: E402


def run(dataset, names, load, repeat, seed):
    rows = []
    for name in names:
        pair = load(name)
        h, w = cv2.imread(pair.input.image_a, cv2.IMREAD_GRAYSCALE).shape
        for r in evaluate_pair(pair, size=(w, h), seed=seed, repeat=repeat):
            r.update(pair=name, n=len(pair.input.matches), ratio=pair.inlier_ratio)
            rows.append(r)
    return rows


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5, help="runs per method (default 5)")
    parser.add_argument("--seed", type=int, default=0, help="seed of the library's methods")
    parser.add_argument("--summary", action="store_true",
                        help="print only the medians, not every pair")
    parser.add_argument("--candidates", default="100,200,400,800",
                        help="CLAP candidate counts for the homogr sweep (comma separated; "
                             "empty to skip)")
    args = parser.parse_args(argv)

    print(f"numpy {np.__version__}, opencv {cv2.__version__}, python "
          f"{platform.python_version()}, {os.cpu_count()} CPUs, OPENBLAS_NUM_THREADS="
          f"{os.environ.get('OPENBLAS_NUM_THREADS')}; {args.repeat} runs per method, "
          "median time")
    for dataset, names, load in [("homogr", homogr_names(), load_homogr),
                                 ("EVD", evd_names(), load_evd)]:
        rows = run(dataset, names, load, args.repeat, args.seed)
        if not args.summary:
            ref = {(r["pair"], r["method"]): r for r in rows}
            print(f"\n{dataset}: per pair (ratios to cv2.RANSAC's time and MAGSAC++'s distance)")
            print(format_table(
                [[r["pair"], r["n"], r["ratio"], r["method"], 1e3 * r["seconds"],
                  r["seconds"] / ref[(r["pair"], "cv2.RANSAC")]["seconds"], r["lie"],
                  r["lie"] / ref[(r["pair"], "cv2.USAC_MAGSAC")]["lie"], r["recall"],
                  r["validation"]]
                 for r in rows],
                [("pair", "<13"), ("matches", "7d"), ("inlier ratio", "12.2f"),
                 ("method", "<16"), ("time [ms]", "9.2f"), ("/ cv2.RANSAC", "12.2f"),
                 ("Lie dist.", "10.3f"), ("/ MAGSAC++", "10.2f"), ("GT inliers kept", "15.2f"),
                 ("validation SRE [px]", "19.2f")]))
        t, lie, rec, val = (summarise(rows, k) for k in ("seconds", "lie", "recall",
                                                         "validation"))
        ref_r, ref_m = t["cv2.RANSAC"], t["cv2.USAC_MAGSAC"]
        lie_m = lie["cv2.USAC_MAGSAC"]
        print(f"\n{dataset}: {len(names)} pairs, medians over pairs")
        print(format_table(
            [[m, 1e3 * t[m], t[m] / ref_r, t[m] / ref_m, lie[m], lie[m] / lie_m, rec[m],
              val[m]] for m in EVALUATED if m in t],
            [("method", "<16"), ("time [ms]", "9.2f"), ("/ cv2.RANSAC", "12.2f"),
             ("/ MAGSAC++", "10.1f"), ("Lie dist.", "9.3f"), ("/ MAGSAC++", "10.2f"),
             ("GT inliers kept", "15.2f"), ("validation SRE [px]", "19.2f")]))
        by_pair = {}
        for r in rows:
            by_pair.setdefault(r["pair"], {})[r["method"]] = r["seconds"]
        faster = np.mean([d["CLAP"] <= d["cv2.RANSAC"] for d in by_pair.values()])
        print(f"CLAP no slower than cv2.RANSAC on {faster:.0%} of the pairs; "
              f"targets: median time <= cv2.RANSAC: {t['CLAP'] <= ref_r}; "
              f"median Lie distance <= MAGSAC++: {lie['CLAP'] <= lie_m}")

    counts = [int(c) for c in args.candidates.split(",") if c.strip()]
    if counts:
        sweep(counts, args.repeat, args.seed)


def sweep(counts, repeat, seed):
    """CLAP's time and accuracy on homogr against its number of candidates."""
    methods = {"cv2.RANSAC": ("cv2_ransac", False)}
    rows = []
    for name in homogr_names():
        pair = load_homogr(name)
        ref = evaluate_pair(pair, methods=methods, repeat=repeat)[0]
        for n in counts:
            r = evaluate_pair(pair, methods={"CLAP": ("clap", False)},
                              seed=seed, repeat=repeat, n_hypotheses=n)[0]
            rows.append((n, r["seconds"], r["seconds"] / ref["seconds"], r["lie"]))
    rows = np.array(rows)
    print("\nhomogr: CLAP against its number of candidates (the paper uses 400); medians "
          "over pairs of the time, of the per-pair ratio to cv2.RANSAC and of the Lie "
          "distance")
    print(format_table(
        [[int(n), 1e3 * np.median(rows[rows[:, 0] == n, 1]),
          np.median(rows[rows[:, 0] == n, 2]), np.median(rows[rows[:, 0] == n, 3]),
          int(np.sum(rows[rows[:, 0] == n, 3] > 100))] for n in counts],
        [("candidates", "10d"), ("time [ms]", "9.2f"), ("/ cv2.RANSAC", "12.2f"),
         ("Lie dist.", "9.3f"), ("failed (>100)", "13d")]))


if __name__ == "__main__":
    main()
