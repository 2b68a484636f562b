"""Benchmark: the compiled homography kernels (numba) against the numpy reference.

On the synthetic pairs of the performance chapter (seeded; matches only), the
homogr and the EVD pairs, :func:`clap_unified.reproduce.scaling.compiled_speedup`
times, interleaved and with one OpenBLAS thread, the polish (reweighted DLT
from OpenCV's unrefined RANSAC estimate) and the whole default CLAP estimate
(whose 4-point solver and anchor embedding of up to 10000 candidates are
kernels too), with the compiled kernels and with the numpy path
(``clap_unified._compiled.AVAILABLE = False``), and checks that both give the
same inliers. Prints the median times and speed-ups. Not a test: run it
with ``make bench`` or ``python bench/bench_compiled.py``.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import platform  # noqa: E402

import numpy as np  # noqa: E402

from clap_unified.imaging.datasets import (  # noqa: E402
    evd_names,
    homogr_names,
    load_evd,
    load_homogr,
    synthetic_pairs,
)
from clap_unified.reproduce.scaling import compiled_speedup  # noqa: E402
from clap_unified.viz import format_table  # noqa: E402


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5, help="runs per step and pair")
    args = parser.parse_args(argv)
    sets = {"synthetic": [p.input.matches for p in synthetic_pairs()],
            "homogr": [load_homogr(n).input.matches for n in homogr_names()],
            "EVD": [load_evd(n).input.matches for n in evd_names()]}
    print(f"{args.repeat} runs per step and pair; numpy {np.__version__}, "
          f"python {platform.python_version()}, {os.cpu_count()} CPUs")
    rows = []
    for name, matches in sets.items():
        s = compiled_speedup(matches, repeat=args.repeat)
        rows += [[name, "polish (reweighted DLT)", 1e3 * s["polish_numpy"],
                  1e3 * s["polish_compiled"], s["polish_speedup"], s["same"]],
                 [name, "default CLAP, whole estimate", 1e3 * s["estimate_numpy"],
                  1e3 * s["estimate_compiled"], s["estimate_speedup"], s["same"]]]
    print(format_table(rows, [("data", "<10"), ("step", "<29"), ("numpy [ms]", "11.2f"),
                              ("compiled [ms]", "14.2f"), ("speed-up", "9.1f"),
                              ("same inliers", ">13")]))


if __name__ == "__main__":
    main()
