"""Benchmark: fundamental matrices by RANSAC and CLAP against OpenCV, PoseLib and COLMAP.

Every method runs on the same matches in one process, through
:func:`~clap_unified.fit` in :class:`~clap_unified.FundamentalSpace`:

* ``ransac``: the library's RANSAC (7-point samples, fixed budget of
  ``--hypotheses``, Sampson-weighted 8-point refinement);
* ``clap``: CLAP with the paper's options (seeds by neighbour count, the
  largest cluster) in the Hartley frame of the matches (``for_data``);
* ``clap_knn``: CLAP with ``density="knn", select="consensus"`` (seeds by
  k-th neighbour distance, the cluster centres judged on the data);
* ``magsac``, ``cv2_ransac``: OpenCV's ``findFundamentalMat`` with
  ``cv2.USAC_MAGSAC`` and ``cv2.FM_RANSAC``; ``poselib``
  (``estimate_fundamental``) and ``colmap`` (``estimate_fundamental_matrix``):
  as the peers return them (``refine=False``), at most 1000 iterations,
  confidence 0.995.

Data: synthetic two-view scenes
(:func:`~clap_unified.imaging.datasets.synthetic_two_view`: random points,
two cameras with known ``K, R, t``, 0.5 px noise, 300 matches, 30 / 50 / 60 % outliers, ``--seeds``
scenes each), scored by the recall of the true inliers (Sampson error
within the threshold, 1 px) and their median Sampson error; and the 19
AdelaideRMF F sequences when present
(:func:`~clap_unified.imaging.datasets.load_adelaidermf`; multi-structure:
the estimate is scored by how many points of the largest true structure
are within the threshold, 2 px, and which fraction of its inliers belong
to that structure; the labels are used only to score). The
time is the median of ``--repeat`` runs of the whole ``fit`` call. Ratios are
against OpenCV's MAGSAC++, measured in the same run. Not a test: run it with
``python bench/bench_fundamental.py``.

OpenBLAS is limited to one thread unless ``OPENBLAS_NUM_THREADS`` is set.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import platform  # noqa: E402
import time  # noqa: E402

import cv2  # noqa: E402
import numpy as np  # noqa: E402

from clap_unified import FundamentalSpace, fit  # noqa: E402
from clap_unified.geometry import sampson_error  # noqa: E402
from clap_unified.imaging.datasets import (  # noqa: E402
    adelaidermf_names,
    load_adelaidermf,
    synthetic_two_view,
)
from clap_unified.viz import format_table  # noqa: E402

REFERENCE = "magsac"


def methods(n_hypotheses: int):
    """Label -> ``(strategy, fit options, whether the space is framed by the data)``."""
    peer = {"refine": False, "n_hypotheses": 1000, "confidence": 0.995}
    return {
        "ransac": ("ransac", {"n_hypotheses": n_hypotheses}, False),
        "clap": ("clap", {"n_hypotheses": n_hypotheses}, True),
        "clap_knn": ("clap", {"n_hypotheses": n_hypotheses, "density": "knn",
                              "select": "consensus"}, True),
        "magsac": ("magsac", peer, False),
        "cv2_ransac": ("cv2_ransac", peer, False),
        "poselib": ("poselib", peer, False),
        "colmap": ("colmap", peer, False),
    }


def synthetic(n, outliers, noise, seed):
    """Matches of a random two-view scene, the true ``F`` and the inlier mask."""
    pair = synthetic_two_view(n, outliers, noise, rng=seed)
    return pair.input.matches, pair.truth.F[0], pair.truth.labels == 1


def adelaide():
    """``(name, matches, mask of the largest structure)`` of each AdelaideRMF F sequence."""
    out = []
    for name in adelaidermf_names("fundamental"):
        pair = load_adelaidermf(name, "fundamental", images=False)
        label = pair.truth.labels
        largest = np.bincount(label[label > 0]).argmax()
        out.append((name, pair.input.matches, label == largest))
    return out


def run(label, spec, matches, threshold, seed, repeat):
    strategy, options, framed = spec
    seconds = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        space = FundamentalSpace.for_data(matches) if framed else FundamentalSpace()
        res = fit(space, matches, strategy, threshold=threshold, rng=seed, **options)
        seconds.append(time.perf_counter() - t0)
    return res, float(np.median(seconds))


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3, help="runs per method (default 3)")
    parser.add_argument("--seeds", type=int, default=5,
                        help="synthetic scenes per outlier ratio (default 5)")
    parser.add_argument("--hypotheses", type=int, default=3000,
                        help="budget of ransac and clap (default 3000)")
    args = parser.parse_args(argv)
    specs = methods(args.hypotheses)
    print(f"numpy {np.__version__}, opencv {cv2.__version__}, python "
          f"{platform.python_version()}, {os.cpu_count()} CPUs, OPENBLAS_NUM_THREADS="
          f"{os.environ.get('OPENBLAS_NUM_THREADS')}; {args.repeat} runs per method, median "
          f"time; ransac/clap budget {args.hypotheses}")

    # ---------------------------------------------------------------- synthetic
    for outliers in (0.3, 0.5, 0.6):
        rows = {m: [] for m in specs}
        for seed in range(args.seeds):
            matches, F, inl = synthetic(300, outliers, 0.5, seed)
            for label, spec in specs.items():
                res, sec = run(label, spec, matches, 1.0, seed, args.repeat)
                if res.success:
                    recall = float(np.mean(res.inliers[inl]))
                    err = float(np.median(sampson_error(res.model, matches[inl, :2],
                                                        matches[inl, 2:])))
                else:
                    recall, err = 0.0, np.inf
                rows[label].append((recall, err, sec))
        ref_ms = np.median([r[2] for r in rows[REFERENCE]]) * 1e3
        print(f"\nsynthetic, {int(100 * outliers)} % outliers, {args.seeds} scenes, "
              "threshold 1 px: recall of the true inliers, their median Sampson error")
        print(format_table(
            [[m, f"{sum(r[0] > 0.9 for r in v)}/{len(v)}", np.median([r[0] for r in v]),
              np.median([r[1] for r in v]), 1e3 * np.median([r[2] for r in v]),
              1e3 * np.median([r[2] for r in v]) / ref_ms] for m, v in rows.items()],
            [("method", "<11"), ("recall>0.9", ">10"), ("median recall", "13.3f"),
             ("sampson [px]", "12.3f"), ("time [ms]", "9.1f"), ("/ magsac", "8.2f")]))

    # ---------------------------------------------------------------- AdelaideRMF
    try:
        seqs = adelaide()
    except (FileNotFoundError, OSError) as err:
        print(f"\nAdelaideRMF not available, skipped: {err}")
        return
    rows = {m: [] for m in specs}
    for _, matches, truth in seqs:
        for label, spec in specs.items():
            res, sec = run(label, spec, matches, 2.0, 0, args.repeat)
            if res.success and res.inliers.any():
                recall = float(np.mean(res.inliers[truth]))
                precision = float(np.mean(truth[res.inliers]))
            else:
                recall = precision = 0.0
            rows[label].append((recall, precision, sec))
    print("\nAdelaideRMF F, per sequence: recall of the largest true structure "
          "(its share of the matches in brackets)")
    print(format_table(
        [[f"{name} ({np.mean(truth):.2f})", *(rows[m][i][0] for m in specs)]
         for i, (name, _, truth) in enumerate(seqs)],
        [("sequence", "<26"), *((m, f"{max(len(m), 6)}.2f") for m in specs)]))
    ref_ms = np.median([r[2] for r in rows[REFERENCE]]) * 1e3
    print(f"\nAdelaideRMF F, {len(seqs)} sequences, threshold 2 px: recall of the largest "
          "true structure, precision of the inliers against it")
    print(format_table(
        [[m, f"{sum(r[0] >= 0.8 for r in v)}/{len(v)}", np.median([r[0] for r in v]),
          np.median([r[1] for r in v]), 1e3 * np.median([r[2] for r in v]),
          1e3 * np.median([r[2] for r in v]) / ref_ms] for m, v in rows.items()],
        [("method", "<11"), ("recall>=0.8", ">11"), ("median recall", "13.3f"),
         ("precision", "9.3f"), ("time [ms]", "9.1f"), ("/ magsac", "8.2f")]))


if __name__ == "__main__":
    main()
