"""Benchmark: CLAP's adaptive hypothesis budget, where it starts and where it stops.

Issue 14: does a smaller budget bring CLAP's time on homographies to
``cv2.RANSAC``'s (the performance chapter measures the part that does not
shrink with the budget)? This measures, on homogr (16 pairs), EVD (15) and the
synthetic hard pairs (12, drawn anew for every seed, as in the performance
chapter), the library's
CLAP (``estimate_homography(..., "clap")``, with and without the match
quality where a pair has it) with variants of its budget:

* the start ``n_hypotheses`` (1000 by default; 150, 300, 500), after which
  :func:`~clap_unified.fit` draws a second, larger set when the first
  estimate's inliers say that fewer than ``ALL_INLIER_SAMPLES`` all-inlier
  samples were to be expected (stopping early, in effect, where they were);
* the cap ``max_hypotheses`` (10000; 3000), which the low inlier ratios of
  EVD and the synthetic pairs reach.

Every variant runs with ``rng=seed`` for each seed of ``--seeds`` next to
``cv2.RANSAC`` (the time reference) and the peers of ``--peers``, on the
same matches, interleaved (for each repeat, one run of each method); the time
of a method on a pair is the median of ``--repeat`` runs of the estimate
only. Per data set and method: pairs within 5 px
(:func:`~clap_unified.imaging.evaluation.estimate_error`) averaged over the
seeds with their min-max, the median error over every pair and seed, the
median time over every pair and seed and its ratio to ``cv2.RANSAC``'s, and
the mean number of candidates the adaptive budget drew. Not a test: run it
with ``python bench/bench_budget.py`` (about 15 minutes with the defaults on
two cores).

OpenBLAS is limited to one thread unless ``OPENBLAS_NUM_THREADS`` is set
(see ``bench_homography.py``).
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402
from tqdm import tqdm  # noqa: E402

from clap_unified.imaging.estimate import estimate_homography  # noqa: E402
from clap_unified.imaging.evaluation import PEERS, estimate_error  # noqa: E402
from clap_unified.viz import format_table  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from bench_peers import DATASETS, machine_line  # noqa: E402

#: Variant label -> options of ``estimate_homography(..., "clap")`` over its protocol.
VARIANTS = {
    "start 1000 (default)": {},
    **{f"start {n}": {"n_hypotheses": n} for n in (500, 300, 150)},
    **{f"start {n}, at most {c}": {"n_hypotheses": n, "max_hypotheses": c}
       for n in (1000, 300) for c in (3000,)},
}

#: The time reference.
REFERENCE = "cv2.RANSAC"


def run_seed(loaded, methods, seed, repeat, progress):
    """Rows ``dataset, pair, method, seconds, error, hypotheses`` of one seed."""
    rows = []
    for d, pairs in loaded.items():
        for pair in pairs:
            m, q = pair.input.matches, pair.input.quality
            run = {label: (name, {**opts, **({"quality": q} if ordered else {})})
                   for label, (name, ordered, opts) in methods.items()
                   if not (ordered and q is None)}
            times = {label: [] for label in run}
            results = {}
            for _ in range(repeat):
                for label, (name, kw) in run.items():
                    t0 = time.perf_counter()
                    res = estimate_homography(m, name, rng=seed, **kw)
                    times[label].append(time.perf_counter() - t0)
                    results[label] = res
                    progress(1)
            for label, res in results.items():
                rows.append({"dataset": d, "seed": seed, "pair": pair.name, "method": label,
                             "seconds": float(np.median(times[label])),
                             "error": estimate_error(res.model if res.success else None, pair),
                             "hypotheses": res.diagnostics.get("adaptive_hypotheses",
                                                               np.nan)})
    return rows


def summary(rows, dataset, within=5.0):
    """Per method on ``dataset``: within (mean, min, max over seeds), errors, times."""
    mine = [r for r in rows if r["dataset"] == dataset]
    ref = np.median([r["seconds"] for r in mine if r["method"] == REFERENCE])
    out = []
    for method in dict.fromkeys(r["method"] for r in mine):
        rs = [r for r in mine if r["method"] == method]
        seeds = sorted({r["seed"] for r in rs})
        counts = [sum(r["error"] < within for r in rs if r["seed"] == s) for s in seeds]
        ms = np.median([r["seconds"] for r in rs])
        out.append({"method": method, "pairs": len(rs) // len(seeds),
                    "within": float(np.mean(counts)), "lo": min(counts), "hi": max(counts),
                    "median_error": float(np.median([r["error"] for r in rs])),
                    "ms": 1e3 * ms, "ratio": ms / ref,
                    "hypotheses": (np.nan if method in PEERS else
                                   float(np.mean([r["hypotheses"] for r in rs])))})
    return out


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=10, help="how many seeds (default 10)")
    parser.add_argument("--first-seed", type=int, default=0, help="the first seed (default 0)")
    parser.add_argument("--repeat", type=int, default=3, help="runs per method (default 3)")
    parser.add_argument("--variants", default=",".join(VARIANTS),
                        help=f"comma-separated, of {', '.join(VARIANTS)} (default: all)")
    parser.add_argument("--quality", choices=("both", "yes", "no"), default="both",
                        help="CLAP with the match quality where a pair has it, without, "
                             "or both (default)")
    parser.add_argument("--peers", default="cv2.USAC_MAGSAC,PoseLib",
                        help=f"comma-separated peers besides {REFERENCE}, of "
                             f"{', '.join(PEERS)} (default: cv2.USAC_MAGSAC,PoseLib)")
    parser.add_argument("--datasets", default=",".join(DATASETS),
                        help=f"comma-separated, of {', '.join(DATASETS)} (default: all)")
    args = parser.parse_args(argv)
    variants = [v.strip() for v in args.variants.split(",") if v.strip()]
    peers = [p.strip() for p in args.peers.split(",") if p.strip()]
    datasets = [d.strip() for d in args.datasets.split(",") if d.strip()]
    for bad, known, what in [(set(variants) - set(VARIANTS), VARIANTS, "--variants"),
                             (set(peers) - set(PEERS), PEERS, "--peers"),
                             (set(datasets) - set(DATASETS), DATASETS, "--datasets")]:
        if bad:
            parser.error(f"{what}: unknown {sorted(bad)}; expected some of {list(known)}")
    methods = {REFERENCE: (PEERS[REFERENCE][0], False, {})}
    methods.update({p: (PEERS[p][0], False, {}) for p in peers if p != REFERENCE})
    for v in variants:
        if args.quality in ("both", "no"):
            methods[f"CLAP {v}"] = ("clap", False, VARIANTS[v])
        if args.quality in ("both", "yes"):
            methods[f"CLAP q {v}"] = ("clap", True, VARIANTS[v])

    seeds = range(args.first_seed, args.first_seed + args.seeds)
    print(machine_line(args.repeat) + f"; seeds {seeds[0]}..{seeds[-1]}")
    rows = []
    per_seed = {}
    for seed in seeds:
        per_seed[seed] = {d: DATASETS[d](seed) for d in datasets}
    total = sum(args.repeat * sum(1 for _, ordered, _ in methods.values()
                                  if not (ordered and p.input.quality is None))
                for loaded in per_seed.values() for pairs in loaded.values() for p in pairs)
    with tqdm(total=total, file=sys.stderr, desc="runs", unit="run", mininterval=10) as bar:
        for seed, loaded in per_seed.items():
            rows += run_seed(loaded, methods, seed, args.repeat, bar.update)
    for d in datasets:
        table = summary(rows, d)
        print(f"\n{d}: {table[0]['pairs']} pairs x {args.seeds} seeds; within 5 px: mean "
              f"over seeds [min-max]; error and time: medians over pairs and seeds")
        print(format_table(
            [[s["method"], f"{s['within']:.1f} [{s['lo']}-{s['hi']}]", s["median_error"],
              s["ms"], s["ratio"], s["hypotheses"]] for s in table],
            [("method", "<22"), ("<= 5 px", ">12"), ("median error [px]", "17.2f"),
             ("median time [ms]", "16.2f"), (f"/ {REFERENCE}", "12.2f"),
             ("mean candidates", "15.0f")]))


if __name__ == "__main__":
    main()
