"""How CLAP's time and peak memory grow with the number of hypotheses and of data.

:func:`scaling_runs` fits seeded synthetic problems of growing size and
records, per method and size, the wall time (median of ``repeat`` runs) and
the peak memory traced by :mod:`tracemalloc` (numpy's allocations included)
above what was allocated when the run started. :func:`loglog_slope` fits the
exponent of a power law to such a series. The performance chapter plots them;
``bench/bench_scaling.py`` prints them.

Two kinds of problem:

* ``"homography"``: matches of a planar homography, half of them uniform
  outliers (noise 0.5 px), fitted by :func:`~clap_unified.imaging.estimate_homography`
  with the library's default ``"clap"`` (k-d tree density: ``O(H log H)``
  time, ``O(H)`` memory) and the paper's ``"clap_paper"`` (an ``H x H``
  distance matrix up to ``DENSE_LIMIT`` of :mod:`clap_unified.clap.clap`
  hypotheses, blocks beyond);
* ``"line"``: points on a line, half of them outliers, fitted by
  :func:`~clap_unified.fit_line` with ``"clap"`` (the line manifold has no
  exact Euclidean embedding: the matrix path).
"""

from __future__ import annotations

import time
import tracemalloc

import numpy as np

from .._validation import check_choice, check_int

__all__ = ["loglog_slope", "scaling_problem", "scaling_runs"]

#: Methods measured per kind of problem.
METHODS = {"homography": ("clap", "clap_paper"), "line": ("clap",)}

#: Data size when the hypotheses vary, and hypotheses when the data vary.
FIXED = {"data": 1000, "hypotheses": 500}


def scaling_problem(kind: str, n: int, *, seed: int = 0) -> np.ndarray:
    """Seeded data of ``n`` rows for ``kind``: half inliers, half uniform outliers.

    A line scene of :func:`~clap_unified.viz.scenes.line_scene` (noise 0.05)
    or the matches of a
    :func:`~clap_unified.imaging.datasets.synthetic_pairs.synthetic_pair`
    (noise 0.5 px); the evaluation data of either stays behind.

    Examples
    --------
    >>> scaling_problem("homography", 10).shape, scaling_problem("line", 10).shape
    ((10, 4), (10, 2))
    """
    check_choice(kind, "kind", set(METHODS))
    n = check_int(n, "n", minimum=8)
    if kind == "line":
        from ..viz.scenes import line_scene

        return line_scene(n, 0.5, rng=seed).input.points
    from ..imaging.datasets.synthetic_pairs import synthetic_pair

    return synthetic_pair(0.5, n_matches=n, noise=0.5, rng=seed).input.matches


def _fit(kind, method, data, n_hypotheses, seed):
    if kind == "line":
        from ..fitting import fit_line

        return fit_line(data, method, n_hypotheses=n_hypotheses, threshold=0.15, rng=seed)
    from ..imaging.estimate import estimate_homography

    return estimate_homography(data, method, n_hypotheses=n_hypotheses, rng=seed)


def scaling_runs(kind: str, sizes, *, vary: str = "hypotheses", methods=None,
                 repeat: int = 3, seed: int = 0) -> list[dict]:
    """Time and peak memory of CLAP at each size.

    Parameters
    ----------
    kind : {"homography", "line"}
    sizes : sequence of int
        Numbers of hypotheses (``vary="hypotheses"``, data fixed at
        ``FIXED["data"]``) or of data (``vary="data"``, hypotheses fixed at
        ``FIXED["hypotheses"]``).
    vary : {"hypotheses", "data"}
    methods : sequence of str, optional
        Default ``METHODS[kind]``.
    repeat : int
        Timed runs per size; the time is their median, the memory the peak of
        a separate traced run (tracing slows numpy down).
    seed : int
        Seed of the data and of the estimator.

    Returns
    -------
    list of dict
        Keys ``kind, vary, method, size, seconds, peak_mb, success``.

    Examples
    --------
    >>> rows = scaling_runs("line", [50, 100], repeat=1)
    >>> [(r["method"], r["size"], r["success"]) for r in rows]
    [('clap', 50, True), ('clap', 100, True)]
    >>> all(r["peak_mb"] > 0 and r["seconds"] > 0 for r in rows)
    True
    """
    check_choice(kind, "kind", set(METHODS))
    check_choice(vary, "vary", {"hypotheses", "data"})
    repeat = check_int(repeat, "repeat", minimum=1)
    methods = METHODS[kind] if methods is None else tuple(methods)
    sizes = [check_int(s, "sizes", minimum=8) for s in sizes]
    rows = []
    for method in methods:
        for size in sizes:
            n_data = size if vary == "data" else FIXED["data"]
            n_hyp = size if vary == "hypotheses" else FIXED["hypotheses"]
            data = scaling_problem(kind, n_data, seed=seed)
            if not rows or rows[-1]["method"] != method:
                _fit(kind, method, data, n_hyp, seed)  # warm-up: imports, caches
            times = []
            for _ in range(repeat):
                t0 = time.perf_counter()
                res = _fit(kind, method, data, n_hyp, seed)
                times.append(time.perf_counter() - t0)
            tracemalloc.start()
            try:
                base = tracemalloc.get_traced_memory()[0]
                _fit(kind, method, data, n_hyp, seed)
                peak = tracemalloc.get_traced_memory()[1] - base
            finally:
                tracemalloc.stop()
            rows.append({"kind": kind, "vary": vary, "method": method, "size": size,
                         "seconds": float(np.median(times)), "peak_mb": peak / 2**20,
                         "success": bool(res.success)})
    return rows


def loglog_slope(sizes, values) -> float:
    """Least-squares slope of ``log(values)`` on ``log(sizes)``: the exponent of a power law.

    Examples
    --------
    >>> round(loglog_slope([10, 100, 1000], [3.0, 300.0, 30000.0]), 6)
    2.0
    """
    x = np.log(np.asarray(sizes, dtype=float))
    y = np.log(np.asarray(values, dtype=float))
    if len(x) < 2 or len(x) != len(y) or not (np.all(np.isfinite(x)) and np.all(np.isfinite(y))):
        raise ValueError("sizes, values: expected two or more positive pairs")
    return float(np.polyfit(x, y, 1)[0])
