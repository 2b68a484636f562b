"""Monte Carlo localization: a particle filter fed the raw landmark detections.

The baseline CLAP replaced. Particles ``(x, y, theta)`` move with noisy
odometry; each frame, every detection is moved to the field by every particle
and matched to the nearest map landmark of its type; the particle's weight is
the product over detections of a robust likelihood: a Gaussian in that
distance (standard deviation growing with range) mixed with a uniform floor
for false detections. Systematic resampling when the effective sample size
drops below half. Random particles are injected so a lost filter can
recover: a small constant fraction, plus the adaptive share of augmented MCL
(Thrun, Burgard and Fox, *Probabilistic Robotics*, table 8.3):
``max(0, 1 - w_fast / w_slow)`` from short- and long-term averages of the
measurement likelihood, which grows when the detections stop fitting.
"""

from __future__ import annotations

import numpy as np

from .._validation import as_generator, check_fraction, check_int, check_positive
from ..geometry.lines import wrap_angle
from ..maps.field import LANDMARK_TYPES, Field

__all__ = ["ParticleFilter"]


class ParticleFilter:
    """Augmented MCL on a landmark map.

    Parameters
    ----------
    field : Field
    n_particles : int
    initial : (x, y, theta), optional
        Start around this pose (spread ``initial_spread``); default uniform on
        the field.
    initial_spread : (float, float)
        Metres, radians.
    odometry_noise : float
        Motion noise as a fraction of the increment (plus a small floor).
    range_noise : (float, float)
        ``sigma(r) = sigma0 + growth * r**2`` of the detections.
    false_rate : float
        Weight of the uniform floor in each detection's likelihood.
    injection : float
        Fraction of particles replaced by random ones each frame, at least.
    alpha_slow, alpha_fast : float
        Smoothing of the long- and short-term likelihood averages of augmented
        MCL (``alpha_fast = 0`` turns the adaptive injection off).
    rng : None, int or numpy.random.Generator

    Examples
    --------
    >>> from clap_unified.localization import load_field, simulate_observations
    >>> from clap_unified.geometry import SE2
    >>> f = load_field("adult")
    >>> pf = ParticleFilter(f, 500, initial=(3.0, 1.0, 0.2), rng=0)
    >>> obs = simulate_observations(f, SE2.from_xytheta(3.0, 1.0, 0.2), rng=1)
    >>> pf.update(obs.input.data)
    >>> x, y, th = pf.estimate()
    >>> print(f"{x:.1f} {y:.1f} {th:.1f}")
    3.0 1.0 0.2
    """

    def __init__(self, field: Field, n_particles: int = 500, *, initial=None,
                 initial_spread=(0.3, np.pi / 18), odometry_noise: float = 0.15,
                 range_noise=(0.01, 0.004), false_rate: float = 0.3, injection: float = 0.01,
                 alpha_slow: float = 0.05, alpha_fast: float = 0.5, rng=None):
        self.field = field
        self.n = check_int(n_particles, "n_particles", minimum=1)
        self.odometry_noise = check_positive(odometry_noise, "odometry_noise", allow_zero=True)
        self.range_noise = (float(range_noise[0]), float(range_noise[1]))
        self.false_rate = check_fraction(false_rate, "false_rate")
        self.injection = check_fraction(injection, "injection")
        self.alpha_slow = check_fraction(alpha_slow, "alpha_slow")
        self.alpha_fast = check_fraction(alpha_fast, "alpha_fast")
        self.w_slow = self.w_fast = None
        self.rng = as_generator(rng)
        dims = field.dimensions
        self._bounds = (dims["length"] / 2 + dims.get("border", 0.0),
                        dims["width"] / 2 + dims.get("border", 0.0))
        self._type_ids = np.array([LANDMARK_TYPES.index(t) for t in field.types])
        # uniform density over a detection's possible positions (about the camera's view)
        self._floor = 1.0 / 30.0
        if initial is None:
            self.particles = self._random(self.n)
        else:
            x, y, th = (float(v) for v in initial)
            s = self.rng.standard_normal((self.n, 3)) * [initial_spread[0], initial_spread[0],
                                                         initial_spread[1]]
            self.particles = np.c_[x + s[:, 0], y + s[:, 1], wrap_angle(th + s[:, 2])]
        self.weights = np.full(self.n, 1.0 / self.n)

    def _random(self, m):
        hl, hw = self._bounds
        return np.c_[self.rng.uniform(-hl, hl, m), self.rng.uniform(-hw, hw, m),
                     self.rng.uniform(-np.pi, np.pi, m)]

    def predict(self, odometry) -> None:
        """Move every particle by the odometry ``(dx, dy, dtheta)`` plus sampled noise."""
        dx, dy, dth = (float(v) for v in odometry)
        step = np.hypot(dx, dy)
        sigma = self.odometry_noise * np.array([abs(dx) + 0.1 * step + 0.005,
                                                abs(dy) + 0.1 * step + 0.005,
                                                abs(dth) + 0.1 * step + 0.005])
        u = np.array([dx, dy, dth]) + self.rng.standard_normal((self.n, 3)) * sigma
        th = self.particles[:, 2]
        c, s = np.cos(th), np.sin(th)
        self.particles = np.c_[self.particles[:, 0] + c * u[:, 0] - s * u[:, 1],
                               self.particles[:, 1] + s * u[:, 0] + c * u[:, 1],
                               wrap_angle(th + u[:, 2])]

    def log_likelihood(self, data) -> np.ndarray:
        """Log-likelihood of detections ``(N, 3)`` for every particle, shape ``(P,)``."""
        data = np.asarray(data, dtype=float).reshape(-1, 3)
        ll = np.zeros(self.n)
        if len(data) == 0:
            return ll
        th = self.particles[:, 2]
        c, s = np.cos(th), np.sin(th)
        loc = data[:, 1:]
        wx = self.particles[:, 0:1] + c[:, None] * loc[:, 0] - s[:, None] * loc[:, 1]
        wy = self.particles[:, 1:2] + s[:, None] * loc[:, 0] + c[:, None] * loc[:, 1]
        r2 = np.einsum("ij,ij->i", loc, loc)
        sigma = self.range_noise[0] + self.range_noise[1] * r2 + 0.05  # + map / pose slack
        ids = data[:, 0].astype(int)
        for t in np.unique(ids):
            cols = np.flatnonzero(ids == t)
            marks = self.field.positions[self._type_ids == t]
            if len(marks) == 0:
                ll += len(cols) * np.log(self.false_rate * self._floor)
                continue
            d2 = ((wx[:, cols, None] - marks[:, 0]) ** 2
                  + (wy[:, cols, None] - marks[:, 1]) ** 2).min(axis=-1)
            sig = sigma[cols]
            gauss = np.exp(-0.5 * d2 / sig**2) / (2 * np.pi * sig**2)
            ll += np.log((1 - self.false_rate) * gauss + self.false_rate * self._floor).sum(axis=1)
        return ll

    def update(self, data) -> None:
        """Resample if degenerate, inject random particles, weigh by the detections.

        Resampling comes first, so after an update the weights always hold
        this frame's likelihoods (the estimate needs them); injected particles
        are weighed like the others, so they matter only where the detections
        agree with them.
        """
        if 1.0 / np.sum(self.weights**2) < self.n / 2:
            self._resample()
        share = self.injection
        if self.w_slow is not None and self.alpha_fast > 0:
            share = max(share, 1.0 - self.w_fast / self.w_slow)
        m = int(round(min(share, 0.5) * self.n))
        if m:
            idx = self.rng.choice(self.n, m, replace=False)
            self.particles[idx] = self._random(m)
        data = np.asarray(data, dtype=float).reshape(-1, 3)
        ll = self.log_likelihood(data)
        if len(data):
            # per-detection geometric mean, so the average does not underflow
            w_avg = float(np.mean(np.exp(ll / len(data))))
            if self.w_slow is None:
                self.w_slow = self.w_fast = w_avg
            self.w_slow += self.alpha_slow * (w_avg - self.w_slow)
            self.w_fast += self.alpha_fast * (w_avg - self.w_fast)
        logw = np.log(self.weights) + ll
        logw -= logw.max()
        w = np.exp(logw)
        self.weights = w / w.sum()

    def _resample(self) -> None:
        positions = (self.rng.random() + np.arange(self.n)) / self.n
        idx = np.minimum(np.searchsorted(np.cumsum(self.weights), positions), self.n - 1)
        self.particles = self.particles[idx]
        self.weights = np.full(self.n, 1.0 / self.n)

    def estimate(self, radius: float = 0.5) -> np.ndarray:
        """Weighted mean ``(x, y, theta)`` of the particles near the heaviest one.

        A plain mean of a multimodal cloud (the pose and its mirror) would sit
        between the modes; the mean is taken over the particles within
        ``radius`` metres and 45 degrees of the heaviest particle.
        """
        p, w = self.particles, self.weights
        best = p[np.argmax(w)]
        near = ((np.hypot(p[:, 0] - best[0], p[:, 1] - best[1]) <= radius)
                & (np.abs(wrap_angle(p[:, 2] - best[2])) <= np.pi / 4))
        w = w * near
        w = w / w.sum()
        th = np.arctan2(w @ np.sin(p[:, 2]), w @ np.cos(p[:, 2]))
        return np.array([w @ p[:, 0], w @ p[:, 1], th])
