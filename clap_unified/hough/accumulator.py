"""The classical line Hough accumulator: every point votes for every angle."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validation import check_points, check_positive

__all__ = ["LineAccumulator", "line_accumulator"]


@dataclass(frozen=True)
class LineAccumulator:
    """Votes over a ``(theta, rho)`` grid.

    Attributes
    ----------
    votes : ndarray of int, shape (n_theta, n_rho)
    thetas : ndarray of shape (n_theta,)
        Cell centres in ``[0, pi)``.
    rhos : ndarray of shape (n_rho,)
        Cell centres of the offset measured from ``origin``.
    origin : ndarray of shape (2,)
    """

    votes: np.ndarray
    thetas: np.ndarray
    rhos: np.ndarray
    origin: np.ndarray

    def line(self, i: int, j: int) -> np.ndarray:
        """The line ``(theta, rho)`` (offset from the coordinate origin) of cell ``(i, j)``."""
        theta = self.thetas[i]
        rho = self.rhos[j] + np.cos(theta) * self.origin[0] + np.sin(theta) * self.origin[1]
        return np.array([theta, rho])


def line_accumulator(points, *, theta_resolution: float = np.pi / 180,
                     rho_resolution: float | None = None, origin=None) -> LineAccumulator:
    """Hough accumulator of 2D points.

    Each point ``(x, y)`` votes once for every angle ``theta``, in the cell of
    ``rho = (x - ox) cos(theta) + (y - oy) sin(theta)``.

    Parameters
    ----------
    points : ndarray of shape (N, 2)
    theta_resolution : float
        Angle step in radians (default one degree).
    rho_resolution : float, optional
        Offset step in data units; default 1/200 of the data's extent.
    origin : array_like of shape (2,), optional
        Where offsets are measured from; default the centroid of the points.

    Examples
    --------
    >>> pts = np.c_[np.arange(100.0), np.full(100, 2.0)]
    >>> acc = line_accumulator(pts, rho_resolution=0.5)
    >>> i, j = np.unravel_index(acc.votes.argmax(), acc.votes.shape)
    >>> int(acc.votes[i, j]), acc.line(i, j).round(3).tolist()
    (100, [1.571, 2.0])
    """
    pts = check_points(points, "points", dim=2, min_count=1)
    dt = check_positive(theta_resolution, "theta_resolution")
    o, rel, dr, rhos = _rho_grid(pts, rho_resolution, origin)
    n_rho = len(rhos)
    thetas = np.arange(0.0, np.pi, dt)
    rho = rel @ np.stack([np.cos(thetas), np.sin(thetas)])  # (N, n_theta)
    j = np.clip(np.rint(rho / dr).astype(np.intp) + n_rho // 2, 0, n_rho - 1)
    flat = j + (np.arange(len(thetas)) * n_rho)[None, :]
    votes = np.bincount(flat.ravel(), minlength=len(thetas) * n_rho).reshape(len(thetas), n_rho)
    return LineAccumulator(votes, thetas, rhos, o)


def _rho_grid(pts, rho_resolution, origin):
    """Origin, points relative to it, the rho step and the rho cell centres."""
    o = pts.mean(axis=0) if origin is None else np.asarray(origin, dtype=float)
    rel = pts - o
    r_max = float(np.max(np.hypot(rel[:, 0], rel[:, 1]))) if len(rel) else 0.0
    if rho_resolution is None:
        rho_resolution = max(2 * r_max / 200, 1e-12)
    dr = check_positive(rho_resolution, "rho_resolution")
    n_rho = int(np.floor(r_max / dr)) * 2 + 3
    return o, rel, dr, (np.arange(n_rho) - n_rho // 2) * dr


def rho_step(points, rho_resolution=None) -> float:
    """The accumulator's offset step for ``points`` (as ``rhos[1] - rhos[0]``)."""
    rhos = _rho_grid(np.asarray(points, dtype=float), rho_resolution, None)[3]
    return float(rhos[1] - rhos[0])
