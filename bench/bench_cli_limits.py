"""Benchmark: the command line at the largest inputs it accepts.

Every command refuses sizes beyond its limits before any work (exit 2); this
runs each one at (or near) those limits, on inputs built to be hard: all
detections of one type, every detection a true landmark (the candidates pile
up in a few huge clusters), an exact line (every hypothesis the same), the
most matches ``fit homography`` reads. Each case runs as its own process
(``python -m clap_unified``); the table shows its wall time, peak memory
(maximum resident set) and exit status. The goal: every case answers within
a few seconds, with memory well below the machine's. Not a test: run it with
``make bench`` or ``python bench/bench_cli_limits.py``. Timings on a shared
machine are noisy.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from clap_unified.cli import MAX_WORK
from clap_unified.geometry import SE2
from clap_unified.imaging.cli import MAX_MATCHES
from clap_unified.localization.cli import MAX_DETECTIONS
from clap_unified.localization.cli3d import MAX_DETECTIONS as MAX_DETECTIONS_3D
from clap_unified.localization.cli3d import MAX_LANDMARKS
from clap_unified.maps.field import load_field
from clap_unified.viz import format_table


def _write_json(path: Path, items) -> str:
    path.write_text(json.dumps(items))
    return str(path)


def _inputs(folder: Path, rng) -> list[tuple[str, list[str]]]:
    """``(case, argv)`` for each case, its inputs written to ``folder``."""
    n = MAX_DETECTIONS
    field = load_field("adult")
    pose = np.linalg.inv(SE2.from_xytheta(1.0, -0.5, 0.3))
    local = field.positions @ pose[:2, :2].T + pose[:2, 2]
    corners = np.flatnonzero(field.types == "L")
    random_l = [{"type": "L", "x": x, "y": y} for x, y in rng.uniform(-5, 5, (n, 2)).tolist()]
    true_l = [{"type": "L", "x": x, "y": y} for x, y in
              (local[rng.choice(corners, n)] + rng.normal(0, 0.01, (n, 2))).tolist()]
    x = np.linspace(0.0, 10.0, 1000)
    line = folder / "line.csv"
    np.savetxt(line, np.c_[x, 2 * x + 1], delimiter=",", fmt="%.6f")
    src = rng.uniform(0, 1000, (MAX_MATCHES, 2))
    H = np.array([[1.1, 0.05, 20.0], [0.02, 0.95, -10.0], [1e-5, 2e-5, 1.0]])
    p = np.c_[src, np.ones(len(src))] @ H.T
    dst = p[:, :2] / p[:, 2:] + rng.normal(0, 1.0, src.shape)
    wrong = rng.random(len(src)) < 0.5
    dst[wrong] = rng.uniform(0, 1000, (wrong.sum(), 2))
    matches = folder / "matches.csv"
    np.savetxt(matches, np.c_[src, dst], delimiter=",", fmt="%.3f")
    world = rng.uniform(-5, 5, (MAX_LANDMARKS, 3))
    marks = [{"type": "a", "x": a, "y": b, "z": c} for a, b, c in world.tolist()]
    body = world[rng.integers(0, MAX_LANDMARKS, MAX_DETECTIONS_3D)] + rng.normal(0, 0.01, (
        MAX_DETECTIONS_3D, 3))
    seen = [{"type": "a", "x": a, "y": b, "z": c} for a, b, c in body.tolist()]
    hyp = MAX_WORK // 1000
    return [
        (f"localize2d: {n} random L detections",
         ["localize2d", _write_json(folder / "random_l.json", random_l)]),
        (f"localize2d: {n} true L detections (giant clusters)",
         ["localize2d", _write_json(folder / "true_l.json", true_l)]),
        (f"localize2d: {n} true L detections, ransac",
         ["localize2d", str(folder / "true_l.json"), "--method", "ransac"]),
        (f"fit line: exact line, 1000 points, {hyp} hypotheses",
         ["fit", "line", str(line), "--hypotheses", str(hyp)]),
        (f"fit line: ransac, 1000 points, {hyp} hypotheses",
         ["fit", "line", str(line), "--hypotheses", str(hyp), "--method", "ransac"]),
        (f"fit homography: clap, {MAX_MATCHES} matches", ["fit", "homography", str(matches)]),
        (f"fit homography: ransac, {MAX_MATCHES} matches",
         ["fit", "homography", str(matches), "--method", "ransac"]),
        (f"localize3d: {MAX_DETECTIONS_3D} detections, {MAX_LANDMARKS} landmarks of one type",
         ["localize3d", _write_json(folder / "seen.json", seen), "--map",
          _write_json(folder / "map.json", marks)]),
    ]


def _run(argv: list[str]) -> tuple[float, float, int]:
    """Wall seconds, peak memory (MB) and exit status of one command in its own process."""
    code = ("import resource, sys\n"
            "from clap_unified.cli import main\n"
            "status = main(sys.argv[1:])\n"
            "sys.stderr.write(f'PEAK {resource.getrusage(resource.RUSAGE_SELF).ru_maxrss}\\n')\n"
            "sys.exit(status)\n")
    t0 = time.perf_counter()
    run = subprocess.run([sys.executable, "-c", code, *argv, "--quiet"], capture_output=True,
                         text=True, env={**os.environ, "OPENBLAS_NUM_THREADS": "1"})
    seconds = time.perf_counter() - t0
    peak = [line for line in run.stderr.splitlines() if line.startswith("PEAK ")]
    kb = float(peak[-1].split()[1]) if peak else float("nan")
    return seconds, kb / 1024, run.returncode


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    rng = np.random.default_rng(args.seed)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for case, argv in _inputs(Path(tmp), rng):
            seconds, mb, status = _run(argv)
            rows.append([case, seconds, mb, status])
            print(f"  {case}: {seconds:.1f} s", file=sys.stderr)
    print(format_table(rows, [("case", "s"), ("seconds", ".1f"), ("peak MB", ".0f"),
                              ("exit", "d")]))
    print(f"(one process each, OPENBLAS_NUM_THREADS=1; peak memory of this run: "
          f"{resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024:.0f} MB)")


if __name__ == "__main__":
    main()
