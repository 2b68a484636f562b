"""Benchmark: the library's CLAP against its peers (OpenCV, PoseLib, COLMAP) on the same matches.

For every pair of homogr (16), EVD (15) and the synthetic hard pairs (12: 8
to 30 % inliers, up to 20 % decoys of a second motion), every method runs on
the same tentative matches (``pair.input``) in one process: CLAP with the
library's protocol (``estimate_homography(..., "clap")``), CLAP with the match
quality where the data has it (EVD's SIFT ratio, the synthetic pairs'
simulated ratio), and every peer of
:data:`~clap_unified.imaging.evaluation.PEERS` (``cv2.RANSAC``,
``cv2.USAC_MAGSAC``, ``cv2.USAC_ACCURATE``, PoseLib, COLMAP), each at the
inlier threshold of 3 px and at most 1000 iterations. Methods are
interleaved (for each repeat, one run of each); the time is the median of
``--repeat`` runs, of the estimate only. The error of an estimate is
:func:`~clap_unified.imaging.evaluation.estimate_error` (median symmetric
reprojection error on the validation points, else on the labelled inliers;
a failure is inf). Per data set: how many pairs are within 5 px, the median
error, the median time and its ratios to ``cv2.RANSAC`` and to the best
peer (most pairs within 5 px, then the lower median error). Not a test: run
it with ``make bench`` or ``python bench/bench_peers.py``.

OpenBLAS is limited to one thread unless ``OPENBLAS_NUM_THREADS`` is set
(see ``bench_homography.py``).
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import platform  # noqa: E402
import sys  # noqa: E402

import cv2  # noqa: E402
import numpy as np  # noqa: E402
from tqdm import tqdm  # noqa: E402

from clap_unified.imaging.datasets import (  # noqa: E402
    evd_names,
    homogr_names,
    load_evd,
    load_homogr,
    synthetic_pairs,
)
from clap_unified.imaging.evaluation import PEER_METHODS, compare_peers, peer_table  # noqa: E402
from clap_unified.viz import format_table  # noqa: E402

#: Data set name -> a function of the seed returning its pairs.
DATASETS = {
    "homogr": lambda seed: [load_homogr(n, images=False) for n in homogr_names()],
    "EVD": lambda seed: [load_evd(n, images=False) for n in evd_names()],
    "synthetic": lambda seed: synthetic_pairs(seed),
}


def _version(module):
    try:
        return __import__(module).__version__
    except ImportError:
        return "not installed"


def machine_line(repeat: int) -> str:
    """Versions, CPUs and the OpenBLAS setting."""
    return (f"numpy {np.__version__}, opencv {cv2.__version__}, poselib {_version('poselib')}, "
            f"pycolmap {_version('pycolmap')}, python {platform.python_version()}, "
            f"{os.cpu_count()} CPUs, OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS')}"
            f"; {repeat} runs per method, median time")


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5, help="runs per method (default 5)")
    parser.add_argument("--seed", type=int, default=0,
                        help="seed of every method and of the synthetic pairs (default 0)")
    parser.add_argument("--methods", default=",".join(PEER_METHODS),
                        help="comma-separated labels (default: all of "
                             f"{', '.join(PEER_METHODS)})")
    parser.add_argument("--datasets", default=",".join(DATASETS),
                        help=f"comma-separated, of {', '.join(DATASETS)} (default: all)")
    parser.add_argument("--summary", action="store_true",
                        help="print only the tables per data set, not every pair")
    args = parser.parse_args(argv)
    labels = [m.strip() for m in args.methods.split(",") if m.strip()]
    datasets = [d.strip() for d in args.datasets.split(",") if d.strip()]
    for bad, known, what in [(set(labels) - set(PEER_METHODS), PEER_METHODS, "--methods"),
                             (set(datasets) - set(DATASETS), DATASETS, "--datasets")]:
        if bad:
            parser.error(f"{what}: unknown {sorted(bad)}; expected some of {list(known)}")
    methods = {m: PEER_METHODS[m] for m in labels}

    print(machine_line(args.repeat))
    loaded = {d: DATASETS[d](args.seed) for d in datasets}
    total = sum(args.repeat * sum(1 for _, q in methods.values()
                                  if not (q and p.input.quality is None))
                for pairs in loaded.values() for p in pairs)
    rows = []
    with tqdm(total=total, file=sys.stderr, desc="runs", unit="run") as bar:
        for d, pairs in loaded.items():
            rows += compare_peers(pairs, methods, repeat=args.repeat, seed=args.seed,
                                  dataset=d, progress=bar.update)
    table = peer_table(rows)
    for d in datasets:
        mine = [r for r in rows if r["dataset"] == d]
        if not args.summary:
            print(f"\n{d}: per pair")
            print(format_table(
                [[r["pair"], r["n"], r["ratio"], r["method"], r["error"], 1e3 * r["seconds"],
                  r["inliers"]] for r in mine],
                [("pair", "<30"), ("matches", "7d"), ("inlier ratio", "12.2f"),
                  ("method", "<18"), ("error [px]", "10.2f"), ("time [ms]", "9.2f"),
                  ("inliers", "7d")]))
        summary = [s for s in table if s["dataset"] == d]
        n_pairs = len({r["pair"] for r in mine})
        best = summary[0]["best_peer"] if summary else None
        print(f"\n{d}: {n_pairs} pairs; error: median symmetric reprojection error "
              f"({'validation points' if d != 'EVD' else 'labelled inliers'}); "
              f"best peer: {best}")
        print(format_table(
            [[s["method"], f"{s['within']}/{s['pairs']}", s["median_error"], s["ms"],
              s["vs_reference"], s["vs_best_peer"]] for s in summary],
            [("method", "<18"), ("<= 5 px", ">7"), ("median error [px]", "17.2f"),
             ("median time [ms]", "16.2f"), ("/ cv2.RANSAC", "12.2f"),
             ("/ best peer", "11.2f")]))


if __name__ == "__main__":
    main()
