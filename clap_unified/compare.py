"""Side-by-side: the three strategies on one identical hypothesis set."""

from __future__ import annotations

import time

from ._validation import as_generator, check_choice, check_int
from .clap import clap
from .hough import hough_lines, randomized_hough
from .ransac import ransac
from .result import ConsensusResult
from .spaces import LineSpace, generate_hypotheses

__all__ = ["METHODS", "compare", "fit_line"]

#: Strategy names accepted by :func:`compare` and :func:`fit_line`.
METHODS = ("hough", "randomized_hough", "ransac", "clap")


def compare(space, data, *, methods=("randomized_hough", "ransac", "clap"),
            n_hypotheses: int = 1000, residual_threshold: float | None = None, rng=None,
            options: dict | None = None) -> dict[str, ConsensusResult]:
    """Run several strategies on the *same* hypotheses drawn once from ``data``.

    Parameters
    ----------
    space : HypothesisSpace
    data : array_like
    methods : sequence of str
        Any of ``"randomized_hough"``, ``"ransac"``, ``"clap"`` (and
        ``"hough"`` for the classical line transform, which uses the data).
    n_hypotheses : int
    residual_threshold : float, optional
        Same data-space inlier threshold for every strategy.
    rng : None, int or numpy.random.Generator
    options : dict, optional
        Per-method keyword arguments, e.g. ``{"randomized_hough": {"cell_size": 0.1}}``.

    Returns
    -------
    dict
        Method name to :class:`~clap_unified.result.ConsensusResult`;
        each result's ``diagnostics["seconds"]`` is its own run time and
        ``diagnostics["generation_seconds"]`` the shared generation time.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> x = rng.uniform(-5, 5, 100)
    >>> pts = np.c_[x, 0.5 * x + rng.normal(0, 0.01, 100)]
    >>> pts[:50] = rng.uniform(-5, 5, (50, 2))
    >>> out = compare(LineSpace.for_data(pts), pts, residual_threshold=0.05, rng=0,
    ...               options={"randomized_hough": {"cell_size": 0.1}})
    >>> {name: r.n_inliers >= 50 for name, r in out.items()}
    {'randomized_hough': True, 'ransac': True, 'clap': True}
    """
    for m in methods:
        check_choice(m, "methods", set(METHODS))
    n_hypotheses = check_int(n_hypotheses, "n_hypotheses", minimum=1)
    options = {} if options is None else dict(options)
    data = space.check_data(data)
    t0 = time.perf_counter()
    hyps = generate_hypotheses(space, data, n_hypotheses, rng=as_generator(rng))
    gen = time.perf_counter() - t0
    out = {}
    for m in methods:
        kw = {"residual_threshold": residual_threshold, **options.get(m, {})}
        if m == "hough":
            res = hough_lines(data, space=space, **kw)
        elif m == "randomized_hough":
            kw.setdefault("cell_size", _default_cell(space, data))
            res = randomized_hough(space, data, hypotheses=hyps, **kw)
        elif m == "ransac":
            kw.setdefault("max_trials", len(hyps))
            res = ransac(space, data, hypotheses=hyps, **kw)
        else:
            res = clap(space, data, hypotheses=hyps, **kw)
        res.diagnostics["generation_seconds"] = gen
        out[m] = res
    return out


def _default_cell(space, data) -> float:
    return 2.0 * space.default_residual_threshold(data)


def fit_line(points, method: str = "clap", *, n_hypotheses: int = 1000,
             residual_threshold: float | None = None, rng=None, **options) -> ConsensusResult:
    """Fit one line to 2D points with the chosen strategy.

    Parameters
    ----------
    points : ndarray of shape (N, 2)
    method : {"hough", "randomized_hough", "ransac", "clap"}
    n_hypotheses : int
        Hypotheses (CLAP, randomized Hough) or RANSAC trials.
    residual_threshold : float, optional
        Inlier distance in data units; default 2 % of the data's RMS radius.
    rng : None, int or numpy.random.Generator
    **options
        Passed to the strategy.

    Examples
    --------
    >>> pts = np.c_[np.arange(5.0), np.arange(5.0)]
    >>> res = fit_line(pts, "ransac", rng=0)
    >>> [round(v, 4) for v in res.space.model_to_dict(res.model)["normal"]]
    [-0.7071, 0.7071]
    """
    check_choice(method, "method", set(METHODS))
    space = LineSpace.for_data(points)
    data = space.check_data(points)
    if method == "hough":
        return hough_lines(data, space=space, residual_threshold=residual_threshold, **options)
    if method == "randomized_hough":
        options.setdefault("cell_size", _default_cell(space, data))
        return randomized_hough(space, data, n_hypotheses=n_hypotheses,
                                residual_threshold=residual_threshold, rng=rng, **options)
    if method == "ransac":
        return ransac(space, data, max_trials=n_hypotheses,
                      residual_threshold=residual_threshold, rng=rng, **options)
    return clap(space, data, n_hypotheses=n_hypotheses, residual_threshold=residual_threshold,
                rng=rng, **options)
