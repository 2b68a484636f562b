"""Experiments of the paper as named, seeded, cacheable units of work.

An :class:`Experiment` is a function ``run(params, seed) -> dict`` plus the
parameters of its quick and full versions, the data sets it needs and the
figures drawn from its output. Its seed comes from its own name
(:func:`seed_for`), never from the order in which experiments run, so one job,
several jobs and a Dask cluster give the same numbers bit for bit.

The output of ``run`` is JSON data::

    {"data": "what the numbers were computed on (a substitute says so)",
     "tables": {"name": [row dict, ...]},   # written as CSV
     "numbers": {"key": value, ...},        # what the claims read
     "artifacts": {...},                    # anything the figures need
     # optional (the homography experiments):
     "protocol": "one line: the protocol of the primary numbers",
     "deviations": [{"paper": ..., "here": ..., "why": ...}, ...],
     "variants": {"key": {"label": ..., "kind": "sensitivity" | "extension" | "control",
                          "numbers": {...}, "tables": {...}}}}  # same formats as above

Timings are kept apart by the runner: they are the only part of a run that
may differ between two runs.
"""

from __future__ import annotations

import hashlib
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

__all__ = ["EXPERIMENTS", "Experiment", "experiment", "finite_or_none", "seed_for"]


@dataclass(frozen=True)
class Experiment:
    """One experiment of the paper.

    Attributes
    ----------
    name : str
        Identifier; also the seed source and the cache file name.
    title : str
        One line for people.
    run : callable
        ``run(params: dict, seed: int) -> dict`` (see the module docstring).
    quick, full : dict
        Parameters of the quick and the full version.
    datasets : tuple of str
        Data sets needed (keys of :data:`clap_unified.reproduce.data.DATASETS`).
    figures : callable or None
        ``figures(output) -> {name: matplotlib Figure}``.
    expected_seconds : (float, float)
        Rough one-core running time of the quick and the full version.
    version : int
        Bumped when the meaning of the output changes (part of the cache key).
    optional : bool
        The paper's own data that cannot always be had (VPG): when its data set
        is missing the experiment is skipped without stopping the run, and the
        claims fall back on the substitute experiments.
    """

    name: str
    title: str
    run: Callable
    quick: dict
    full: dict
    datasets: tuple = ()
    figures: Callable | None = None
    expected_seconds: tuple = (10.0, 60.0)
    version: int = 1
    optional: bool = False

    def params(self, quick: bool) -> dict:
        """A copy of the quick or the full parameters."""
        return dict(self.quick if quick else self.full)


#: Registered experiments, by name, in the order they were defined.
EXPERIMENTS: dict[str, Experiment] = {}


def experiment(name: str, title: str, *, quick: dict, full: dict, datasets=(), figures=None,
               expected_seconds=(10.0, 60.0), version: int = 1, optional: bool = False):
    """Decorator registering ``run(params, seed)`` as an :class:`Experiment` named ``name``."""

    def wrap(run):
        EXPERIMENTS[name] = Experiment(name, title, run, dict(quick), dict(full),
                                       tuple(datasets), figures, tuple(expected_seconds),
                                       version, optional)
        return run

    return wrap


def seed_for(name: str) -> int:
    """A 32-bit seed derived from an experiment's name alone.

    Examples
    --------
    >>> seed_for("localization3d") == seed_for("localization3d")
    True
    >>> seed_for("a") != seed_for("b")
    True
    """
    return int.from_bytes(hashlib.sha256(name.encode()).digest()[:4], "little")


def finite_or_none(x):
    """A JSON-safe number: NaN and infinities become None (JSON null).

    Examples
    --------
    >>> finite_or_none(1.5), finite_or_none(float("inf")), finite_or_none(None)
    (1.5, None, None)
    """
    if x is None:
        return None
    x = float(x)
    return x if np.isfinite(x) else None
