"""How CLAP's time and peak memory grow with the number of hypotheses and of data.

:func:`compiled_speedup` measures what the compiled homography kernels
(:mod:`~clap_unified.spaces.homography_compiled`) save against the numpy
path they replace.

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
  time, ``O(H)`` memory) and ``"clap_densest"``, the package's earlier
  reading of the paper's protocol (an ``H x H`` first-order distance matrix
  up to ``DENSE_LIMIT`` of :mod:`clap_unified.clap.clap` hypotheses, blocks
  beyond; the paper's protocol as written, ``"clap_paper"``, builds the same
  matrix with matrix logarithms);
* ``"line"``: points on a line, half of them outliers, fitted by
  :func:`~clap_unified.fit_line` with ``"clap"`` (lines compared by the
  anchor-transfer metric: k-d tree density, as for homographies).
"""

from __future__ import annotations

import time
import tracemalloc

import numpy as np

from .._validation import check_choice, check_int

__all__ = ["compiled_speedup", "loglog_slope", "scaling_problem", "scaling_runs"]

#: Methods measured per kind of problem.
METHODS = {"homography": ("clap", "clap_densest"), "line": ("clap",)}

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


def compiled_speedup(matches, *, repeat: int = 5, method: str = "clap") -> dict:
    """Time of the polish and of a whole estimate, compiled kernels against numpy.

    For each matrix of matches, interleaved: the polish
    (:func:`~clap_unified.spaces.homography_polish.polish_checked`, threshold
    6 px) from OpenCV's unrefined RANSAC estimate with ``compiled=True`` and
    ``False``, and ``estimate_homography(m, method, rng=0)`` with the kernels
    on and switched off (``clap_unified._compiled.AVAILABLE`` ``= False``: the
    4-point solver, the anchor embedding and the polish all in numpy).

    Parameters
    ----------
    matches : iterable of ndarray of shape (N, 4)
        Estimator input only.
    repeat : int
        Timed runs of each; the median counts.
    method : str
        The estimate timed end to end.

    Returns
    -------
    dict
        ``polish_numpy, polish_compiled, estimate_numpy, estimate_compiled``:
        median seconds over the matrices; ``polish_speedup`` and
        ``estimate_speedup``: medians of the per-matrix ratios; ``same``:
        True when both paths gave the same inliers everywhere.

    Examples
    --------
    >>> from clap_unified.imaging.datasets import synthetic_pair
    >>> out = compiled_speedup([synthetic_pair(0.5, rng=0).input.matches], repeat=1)
    >>> out["same"], out["polish_speedup"] > 0
    (True, True)
    """
    from .. import _compiled
    from ..imaging.estimate import estimate_homography
    from ..spaces.homography_polish import polish_checked

    repeat = check_int(repeat, "repeat", minimum=1)
    if _compiled.njit is None:
        raise RuntimeError("compiled_speedup: numba is not importable, nothing to compare")
    switch = _compiled.AVAILABLE  # restored as it was found

    def timed(fn):
        times, out = [], None
        for _ in range(repeat):
            t0 = time.perf_counter()
            out = fn()
            times.append(time.perf_counter() - t0)
        return float(np.median(times)), out

    rows, same = [], True
    for m in matches:
        m = np.ascontiguousarray(m, dtype=float)
        start = estimate_homography(m, "cv2_ransac", rng=0, refine=False).model
        if start is None:
            continue
        polish_checked(start, m, 6.0, compiled=True)  # compiles on the first call
        t_pc, (_, inl_c) = timed(lambda s=start, m=m: polish_checked(s, m, 6.0, compiled=True))
        t_pn, (_, inl_n) = timed(lambda s=start, m=m: polish_checked(s, m, 6.0, compiled=False))
        est = {}
        for compiled in (True, False):
            _compiled.AVAILABLE = compiled
            try:
                est[compiled] = timed(lambda m=m: estimate_homography(m, method, rng=0))
            finally:
                _compiled.AVAILABLE = switch
        same &= bool(np.array_equal(inl_c, inl_n)
                     and np.array_equal(est[True][1].inliers, est[False][1].inliers))
        rows.append((t_pn, t_pc, est[False][0], est[True][0]))
    if not rows:
        raise ValueError("matches: no matrix gave a starting estimate")
    r = np.array(rows)
    return {"polish_numpy": float(np.median(r[:, 0])),
            "polish_compiled": float(np.median(r[:, 1])),
            "estimate_numpy": float(np.median(r[:, 2])),
            "estimate_compiled": float(np.median(r[:, 3])),
            "polish_speedup": float(np.median(r[:, 0] / r[:, 1])),
            "estimate_speedup": float(np.median(r[:, 2] / r[:, 3])),
            "same": same, "pairs": len(rows)}
