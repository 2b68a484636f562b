"""Plotting helpers for the line chapters and the error curves of every chapter. Each draws
on an ``Axes`` it is given."""

from __future__ import annotations

import numpy as np

from ..geometry.lines import Line2D, canonical_lines
from .style import METHOD_STYLE, TRUTH_COLOUR

__all__ = ["plot_accumulator", "plot_error_cdf", "plot_error_curves", "plot_hypotheses",
           "plot_points_and_lines"]


def _rho_from(lines, origin):
    """``(theta in degrees, rho measured from origin)`` of canonical lines."""
    lines = canonical_lines(np.atleast_2d(np.asarray(lines, dtype=float)))
    normal, rho = Line2D.normal_offset(lines)
    return np.degrees(lines[:, 0]), rho - normal @ np.asarray(origin, dtype=float)


def plot_points_and_lines(ax, points, lines=(), *, labels=None, colors=None, inliers=None,
                          margin: float = 0.5):
    """Scatter 2D points and draw lines ``(theta, rho)`` across them.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    points : ndarray of shape (N, 2)
    lines : array_like of shape (L, 2)
        Lines ``x cos(theta) + y sin(theta) = rho``.
    labels, colors : sequence of str, optional
        One per line.
    inliers : ndarray of bool, shape (N,), optional
        Drawn darker than the other points.
    margin : float
        Padding around the points, in data units.

    Examples
    --------
    >>> from matplotlib.figure import Figure
    >>> ax = Figure().subplots()
    >>> plot_points_and_lines(ax, np.array([[0.0, 0.0], [1.0, 1.0]]),
    ...                       [[3 * np.pi / 4, 0.0]], labels=["y = x"])
    >>> len(ax.lines)
    1
    """
    pts = np.asarray(points, dtype=float)
    lo, hi = pts.min(axis=0) - margin, pts.max(axis=0) + margin
    if inliers is None:
        ax.scatter(pts[:, 0], pts[:, 1], s=8, color="0.45", lw=0, label="points")
    else:
        mask = np.asarray(inliers, bool)
        ax.scatter(pts[~mask, 0], pts[~mask, 1], s=8, color="0.7", lw=0, label="other points")
        ax.scatter(pts[mask, 0], pts[mask, 1], s=8, color="0.2", lw=0, label="inliers")
    lines = np.asarray(lines, dtype=float).reshape(-1, 2)
    reach = float(np.hypot(*(hi - lo))) + float(np.abs(pts).max())
    for k, line in enumerate(lines):
        normal, rho = Line2D.normal_offset(line)
        foot, along = rho * normal, np.array([-normal[1], normal[0]])
        ends = foot + np.outer([-reach, reach], along)
        kw = {"lw": 1.4}
        if labels is not None:
            kw["label"] = labels[k]
        if colors is not None:
            kw["color"] = colors[k]
        ax.plot(ends[:, 0], ends[:, 1], **kw)
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_aspect("equal")
    ax.set_xlabel("x")
    ax.set_ylabel("y")


def plot_hypotheses(ax, models, *, values=None, origin=(0.0, 0.0), truth=None, centres=None,
                    cmap="viridis", colorbar_label=None, size: float = 6.0, inset=None):
    """Line hypotheses as points in ``(theta, rho)``: the space CLAP clusters in.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    models : ndarray of shape (H, 2)
        Lines ``(theta, rho)``; drawn with ``theta`` in degrees in ``[0, 180)``.
    values : ndarray of shape (H,), optional
        Colour of each hypothesis (e.g. its neighbour count or RANSAC score);
        high values are drawn on top.
    origin : array_like of shape (2,)
        ``rho`` is drawn as the offset from this point (use the origin of
        the Hough accumulator to compare the two pictures).
    truth : array_like of shape (2,) or (K, 2), optional
        The true line(s), drawn as stars.
    centres : array_like of shape (K, 2), optional
        Cluster centres, drawn as crosses.
    cmap : str
    colorbar_label : str, optional
        Add a colour bar with this label (only with ``values``).
    size : float
        Marker size.
    inset : (float, float, float, float), optional
        ``(theta_min, theta_max, rho_min, rho_max)`` (degrees, data units):
        repeat the plot zoomed on this window in an inset at the upper right.

    Returns
    -------
    matplotlib.collections.PathCollection

    Examples
    --------
    >>> from matplotlib.figure import Figure
    >>> ax = Figure().subplots()
    >>> sc = plot_hypotheses(ax, np.array([[0.1, 1.0], [0.2, 1.1]]), values=[1.0, 2.0],
    ...                      inset=(0.0, 20.0, 0.0, 2.0))
    >>> len(ax.child_axes)
    1
    """
    theta, rho = _rho_from(models, origin)
    v = None if values is None else np.asarray(values, dtype=float)
    order = np.arange(len(theta)) if v is None else np.argsort(v, kind="stable")
    targets = [ax]
    if inset is not None:
        sub = ax.inset_axes([0.6, 0.6, 0.38, 0.38])
        sub.set_xlim(inset[0], inset[1])
        sub.set_ylim(inset[2], inset[3])
        sub.tick_params(labelsize=9)  # 8 px or more once a 1000 px figure fits the column
        ax.indicate_inset_zoom(sub, edgecolor="0.3")
        targets.append(sub)
    for target in targets:
        big = target is ax
        if v is None:
            sc_ = target.scatter(theta, rho, s=size if big else 3 * size, color="0.3", lw=0,
                                 alpha=0.6)
        else:
            sc_ = target.scatter(theta[order], rho[order], c=v[order], s=size if big else 3 * size,
                                 cmap=cmap, vmin=v.min(), vmax=v.max(), lw=0)
        if big:
            sc = sc_
        if truth is not None:
            t, r = _rho_from(truth, origin)
            target.scatter(t, r, marker="*", s=160 if big else 90, facecolor="none",
                           edgecolor=TRUTH_COLOUR, lw=1.4, label="true line" if big else None)
        if centres is not None and len(centres):
            t, r = _rho_from(centres, origin)
            target.scatter(t, r, marker="x", s=60, color=TRUTH_COLOUR, lw=1.6,
                           label="cluster centres" if big else None)
    if v is not None and colorbar_label is not None:
        ax.figure.colorbar(sc, ax=ax, label=colorbar_label)
    ax.set_xlim(0, 180)
    ax.set_xlabel(r"$\theta$ [deg]")
    ax.set_ylabel(r"$\rho$")
    return sc


def plot_accumulator(ax, acc, peaks=None, *, truth=None, colorbar_label="votes"):
    """A Hough accumulator as an image, with its peaks and the true line.

    The colour scale is a square root of the votes, so single sinusoids stay
    visible next to the peaks.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    acc : clap_unified.hough.LineAccumulator
    peaks : ndarray of int, shape (K, 2), optional
        ``(theta_index, rho_index)`` rows, e.g. from
        :func:`~clap_unified.hough.accumulator_peaks`; drawn as circles.
    truth : array_like of shape (2,), optional
        The true line, drawn as a star (offset taken from ``acc.origin``).
    colorbar_label : str or None
        Label of the colour bar; ``None`` draws none.

    Returns
    -------
    matplotlib.image.AxesImage
    """
    th = np.degrees(acc.thetas)
    dth = th[1] - th[0] if len(th) > 1 else 1.0
    dr = acc.rhos[1] - acc.rhos[0] if len(acc.rhos) > 1 else 1.0
    extent = (th[0] - dth / 2, th[-1] + dth / 2, acc.rhos[0] - dr / 2, acc.rhos[-1] + dr / 2)
    from matplotlib.colors import PowerNorm

    im = ax.imshow(acc.votes.T, origin="lower", aspect="auto", extent=extent, cmap="magma",
                   interpolation="nearest", norm=PowerNorm(0.5, vmin=0, vmax=acc.votes.max()))
    if colorbar_label is not None:
        ax.figure.colorbar(im, ax=ax, label=colorbar_label)
    if peaks is not None and len(peaks):
        p = np.asarray(peaks)
        ax.scatter(th[p[:, 0]], acc.rhos[p[:, 1]], s=80, facecolor="none", edgecolor="cyan",
                   lw=1.2, label="peaks")
    if truth is not None:
        t, r = _rho_from(truth, acc.origin)
        ax.scatter(t, r, marker="*", s=160, facecolor="none", edgecolor="lime", lw=1.2,
                   label="true line")
    ax.grid(False)
    ax.set_xlabel(r"$\theta$ [deg]")
    ax.set_ylabel(r"$\rho$ from the centroid")
    return im


def plot_error_curves(axes, ratios, errors, *, quantiles=(0.25, 0.75), log: bool = True):
    """Median error against outlier ratio, one curve and band per method.

    Parameters
    ----------
    axes : pair of matplotlib.axes.Axes
        Angle errors are drawn in the first, offset errors in the second.
    ratios : ndarray of shape (R,)
        Outlier ratios (drawn in percent).
    errors : dict
        Method name to a pair ``(angle, offset)`` of arrays of shape
        ``(R, T)`` (degrees, data units), ``T`` seeded trials per ratio.
        Names in :data:`~clap_unified.viz.style.METHOD_STYLE` get its colours,
        markers and line styles.
    quantiles : (float, float)
        The shaded band (default: the inter-quartile range).
    log : bool
        Logarithmic error axes.

    Examples
    --------
    >>> from matplotlib.figure import Figure
    >>> axes = Figure().subplots(1, 2)
    >>> r = np.array([0.0, 0.5])
    >>> plot_error_curves(axes, r, {"clap": (np.ones((2, 3)), np.ones((2, 3)))})
    >>> len(axes[0].lines), axes[0].get_yscale()
    (1, 'log')
    """
    x = 100 * np.asarray(ratios, dtype=float)
    for name, pair in errors.items():
        style = METHOD_STYLE.get(name, {"label": name})
        for ax, err in zip(axes, pair, strict=True):
            err = np.asarray(err, dtype=float)
            med = np.median(err, axis=1)
            lo, hi = np.quantile(err, quantiles, axis=1)
            ax.plot(x, med, marker=style.get("marker", "o"), color=style.get("color"),
                    ls=style.get("linestyle", "-"), label=style["label"], ms=5)
            ax.fill_between(x, lo, hi, color=style.get("color"), alpha=0.15, lw=0)
    for ax, what in zip(axes, ("angle error [deg]", "offset error"), strict=True):
        if log:
            ax.set_yscale("log")
        ax.set_xlabel("outliers [%]")
        ax.set_ylabel(what)


def plot_error_cdf(ax, errors, name, *, order=0, of=1, cap=1e3, lw=1.8, n_marks=5):
    """The empirical CDF of one method's errors, as a step curve in its book style.

    Methods that share hypotheses and the refit often return the same estimates,
    so their CDFs coincide. Each curve therefore has its method's line style and
    a few markers, placed at different data points for each method (``order`` of
    ``of``), so that every method stays visible where the curves overlap.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    errors : array_like of shape (N,)
        One error per trial; ``inf`` (a failure) is drawn at ``cap``.
    name : str
        Method name; names in :data:`~clap_unified.viz.style.METHOD_STYLE` get
        its colour, marker, line style and label.
    order, of : int
        This method's position among the ``of`` methods drawn on ``ax``: shifts
        its markers so that coinciding curves show all of them.
    cap : float
        Errors above it (and failures) are drawn at it.
    lw : float
        Line width.
    n_marks : int
        About how many markers per curve.

    Returns
    -------
    matplotlib.lines.Line2D

    Examples
    --------
    >>> from matplotlib.figure import Figure
    >>> ax = Figure().subplots()
    >>> line = plot_error_cdf(ax, [0.3, 0.1, np.inf, 0.2], "clap")
    >>> line.get_label(), float(line.get_ydata()[-1]), float(line.get_xdata()[-1])
    ('CLAP', 1.0, 1000.0)
    """
    x = np.sort(np.minimum(np.asarray(errors, dtype=float), cap))
    y = np.arange(1, len(x) + 1) / max(len(x), 1)
    style = METHOD_STYLE.get(name, {"label": name})
    step = max(1, len(x) // max(n_marks, 1))
    start = (order * step) // max(of, 1)
    (line,) = ax.step(x, y, where="post", color=style.get("color"),
                      ls=style.get("linestyle", "-"), lw=lw, label=style["label"],
                      marker=style.get("marker"), markevery=(start, step), ms=6,
                      markerfacecolor="none", markeredgewidth=1.3)
    return line
