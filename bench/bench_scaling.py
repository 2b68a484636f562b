"""Benchmark: CLAP's time and peak memory against the number of hypotheses H and of data N.

For homographies (the library's default ``"clap"``, whose density queries run
on a k-d tree, and ``"clap_densest"``, the earlier reading of the paper's
protocol, which builds the H x H distance matrix) and lines, on seeded
synthetic problems with half outliers: median wall time of ``--repeat`` runs,
the peak memory traced by ``tracemalloc`` and the slopes of log time and log
memory against log size.
Not a test: run it with ``make bench`` or ``python bench/bench_scaling.py``.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import platform  # noqa: E402

import numpy as np  # noqa: E402

from clap_unified.reproduce.scaling import FIXED, loglog_slope, scaling_runs  # noqa: E402
from clap_unified.viz import format_table  # noqa: E402

SIZES = {("homography", "hypotheses"): "250,500,1000,2000,4000",
         ("homography", "data"): "125,250,500,1000,2000,4000",
         ("line", "hypotheses"): "250,500,1000,2000",
         ("line", "data"): "250,500,1000,2000,4000"}


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--kind", choices=["homography", "line", "both"], default="both")
    parser.add_argument("--vary", choices=["hypotheses", "data", "both"], default="both")
    parser.add_argument("--sizes", help="comma-separated sizes (default: per kind)")
    parser.add_argument("--repeat", type=int, default=3, help="timed runs per size")
    parser.add_argument("--big", action=argparse.BooleanOptionalAction, default=True,
                        help="also the default homography CLAP at 10^4 and 10^5 hypotheses")
    args = parser.parse_args(argv)
    print(f"{platform.machine()}, {os.cpu_count()} CPUs, numpy {np.__version__}, python "
          f"{platform.python_version()}, OPENBLAS_NUM_THREADS="
          f"{os.environ.get('OPENBLAS_NUM_THREADS')}; median of {args.repeat} runs; "
          f"data fixed at {FIXED['data']} when H varies, H at {FIXED['hypotheses']} when N does")
    kinds = ["homography", "line"] if args.kind == "both" else [args.kind]
    varies = ["hypotheses", "data"] if args.vary == "both" else [args.vary]
    for kind in kinds:
        for vary in varies:
            sizes = [int(s) for s in (args.sizes or SIZES[kind, vary]).split(",") if s.strip()]
            rows = scaling_runs(kind, sizes, vary=vary, repeat=args.repeat)
            print(f"\n{kind}, varying the {vary}")
            print(format_table([[r["method"], r["size"], 1e3 * r["seconds"], r["peak_mb"],
                                 r["success"]] for r in rows],
                               [("method", "<11"), ("size", "7d"), ("time [ms]", "10.1f"),
                                ("peak [MB]", "9.1f"), ("success", ">7")]))
            for m in dict.fromkeys(r["method"] for r in rows):
                mine = [r for r in rows if r["method"] == m]
                x = [r["size"] for r in mine]
                print(f"  {m}: slope of time {loglog_slope(x, [r['seconds'] for r in mine]):.2f}, "
                      f"of memory {loglog_slope(x, [r['peak_mb'] for r in mine]):.2f}")
    if args.big and "homography" in kinds:
        rows = scaling_runs("homography", [10_000, 100_000], methods=["clap"], repeat=1)
        for r in rows:
            print(f"default homography CLAP at H = {r['size']}: {r['seconds']:.2f} s, "
                  f"peak {r['peak_mb']:.0f} MB")


if __name__ == "__main__":
    main()
