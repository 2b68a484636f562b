"""The strategy registry: one name, one consensus strategy.

A strategy is a function ``run(space, data, hypotheses, *, threshold, prior,
radius, rng, **options) -> Consensus`` registered under one name with
:func:`register_strategy`. :func:`~clap_unified.fit` looks it up by name, so
adding a strategy is one new module and one registration line; nothing else
dispatches on strategy names.

Examples
--------
A toy strategy that takes the first hypothesis, registered, run and removed:

>>> import numpy as np
>>> from clap_unified import fit
>>> from clap_unified.result import Cluster, Consensus
>>> from clap_unified.spaces import LineSpace
>>> def first(space, data, hypotheses, **_):
...     support = np.zeros(len(hypotheses), bool)
...     support[0] = True
...     return Consensus(hypotheses.models[0], (Cluster(hypotheses.models[0], 1, 0.0),),
...                      support, 1.0)
>>> _ = register_strategy(Strategy("first", first, summary="the first hypothesis"))
>>> pts = np.c_[np.arange(10.0), 2 * np.arange(10.0)]
>>> fit(LineSpace(), pts, "first", threshold=0.1, rng=0).n_inliers
10
>>> unregister_strategy("first")
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from dataclasses import dataclass

__all__ = ["Segmenter", "Strategy", "get_segmenter", "get_strategy", "load_plugins",
           "register_segmenter", "register_strategy", "segmenter_names", "strategy_names",
           "unregister_segmenter", "unregister_strategy"]

#: Entry-point group of strategies in other packages, loaded when clap_unified is imported:
#: in their pyproject.toml, ``[project.entry-points."clap_unified.strategies"]``
#: ``mine = "my_package.my_strategy"`` (a module that calls :func:`register_strategy`).
ENTRY_POINTS = "clap_unified.strategies"


@dataclass(frozen=True)
class Strategy:
    """A consensus strategy as :func:`~clap_unified.fit` sees it.

    Attributes
    ----------
    name : str
        The one name it is registered, selected and reported under.
    run : callable
        ``run(space, data, hypotheses, *, threshold, prior, radius, rng,
        n_hypotheses, **options) -> Consensus``. ``data`` is checked by the
        space, ``threshold`` is a positive float, ``rng`` is what the caller
        gave (``None``, an int or a Generator; the Generator the hypotheses
        were drawn from when :func:`~clap_unified.fit` drew them): a strategy
        that draws calls ``as_generator`` on it, ``hypotheses`` a
        :class:`~clap_unified.spaces.HypothesisSet` (``None`` when
        ``uses_hypotheses`` is False, or when ``draws_samples`` is True and
        the caller gave none).
    uses_hypotheses : bool
        Consensus over hypotheses from minimal samples (CLAP, RANSAC,
        randomized Hough); False for strategies that read the data only
        (the classical Hough transform, external estimators).
    draws_samples : bool
        The strategy draws its own minimal samples when given no hypotheses
        (RANSAC's adaptive stopping): :func:`~clap_unified.fit` then does not
        generate them first.
    gates_prior : bool
        With a prior, the strategy receives every hypothesis and applies
        ``space.near_prior`` itself (CLAP's local mode shares the distance
        computation); otherwise :func:`~clap_unified.fit` hands over only the
        hypotheses near the prior.
    applies_to : tuple of str, optional
        Names of the spaces it works in (``space.name``); ``None`` for any.
    finish : callable, optional
        ``finish(space, data, model, inliers, threshold, consensus) ->
        (score, reason)`` after refinement: the score of the returned model
        (e.g. RANSAC counts its inliers again) and ``"ok"`` or why it fails.
        Without it the consensus score stands.
    default_threshold : callable, optional
        ``default_threshold(space, data, options) -> float`` when the caller
        gives no threshold (default: ``space.default_threshold(data)``).
    summary : str
        One line for ``clap-unified strategies`` and the docs.
    baseline : bool
        Another library's estimator wrapped as a strategy (OpenCV, Open3D,
        PoseLib, COLMAP) so comparisons share the data checks, the threshold
        and the result type; False for the library's own strategies.
    """

    name: str
    run: Callable
    uses_hypotheses: bool = True
    draws_samples: bool = False
    gates_prior: bool = False
    applies_to: tuple | None = None
    finish: Callable | None = None
    default_threshold: Callable | None = None
    summary: str = ""
    baseline: bool = False

    def applies(self, space) -> bool:
        """Whether this strategy works in ``space``."""
        return self.applies_to is None or space.name in self.applies_to


@dataclass(frozen=True)
class Segmenter:
    """A multi-model strategy as :func:`~clap_unified.segment` sees it.

    Attributes
    ----------
    name : str
        The one name it is registered, selected and reported under (the
        multi-model counterpart of a strategy keeps the strategy's name:
        ``"clap"``, ``"ransac"``, ``"randomized_hough"``).
    run : callable
        ``run(space, data, hypotheses, *, threshold, rng, n_hypotheses,
        **options) -> Segmentation``; arguments as for :class:`Strategy`.
    uses_hypotheses : bool
        :func:`~clap_unified.segment` draws the hypotheses first (shared
        by every segmenter in a comparison).
    applies_to : tuple of str, optional
        Names of the spaces it works in; ``None`` for any.
    summary : str
    baseline : bool
        Another library's estimator wrapped as a segmenter.
    """

    name: str
    run: Callable
    uses_hypotheses: bool = True
    applies_to: tuple | None = None
    summary: str = ""
    baseline: bool = False

    def applies(self, space) -> bool:
        """Whether this segmenter works in ``space``."""
        return self.applies_to is None or space.name in self.applies_to


class _Registry:
    """Names to entries of one kind, safe to change from several threads."""

    def __init__(self, kind: type, noun: str):
        self.kind, self.noun = kind, noun
        self.entries: dict = {}
        self.lock = threading.Lock()

    def register(self, entry, replace: bool):
        if not isinstance(entry, self.kind):
            raise TypeError(f"{self.noun}: expected a {self.kind.__name__}, "
                            f"got {type(entry).__name__}")
        if not entry.name or not entry.name.replace("_", "").isalnum():
            raise ValueError(f"{self.noun}: name must be a word of letters, digits and "
                             f"underscores, got {entry.name!r}")
        with self.lock:
            if entry.name in self.entries and not replace:
                raise ValueError(f"{self.noun}: {entry.name!r} is already registered")
            self.entries[entry.name] = entry
        return entry

    def unregister(self, name: str) -> None:
        with self.lock:
            self.entries.pop(name, None)

    def names(self, space=None) -> tuple[str, ...]:
        with self.lock:
            items = list(self.entries.items())
        return tuple(n for n, e in items if space is None or e.applies(space))

    def get(self, name: str, space=None):
        if not isinstance(name, str) or name not in self.entries:
            # with a space, the choices are the names that work in it (the registry also
            # holds strategies of other spaces: OpenCV's homography estimators, Open3D's)
            choices = sorted(self.names(space))
            hint = ""
            if isinstance(name, str) and name.lower() in choices:
                hint = f" (names are lower case: {name.lower()!r})"
            raise ValueError(f"method: expected one of {choices}, got {name!r}{hint}")
        entry = self.entries[name]
        if space is not None and not entry.applies(space):
            raise ValueError(f"method: {name!r} works in the {', '.join(entry.applies_to)} "
                             f"space(s), not in the {space.name} space; choose one of "
                             f"{list(self.names(space))}")
        return entry


_STRATEGIES = _Registry(Strategy, "strategy")
_SEGMENTERS = _Registry(Segmenter, "segmenter")


def register_strategy(strategy: Strategy, *, replace: bool = False) -> Strategy:
    """Register ``strategy`` under ``strategy.name`` (a name already taken is an error)."""
    return _STRATEGIES.register(strategy, replace)


def unregister_strategy(name: str) -> None:
    """Remove a registered strategy (for tests and plug-ins)."""
    _STRATEGIES.unregister(name)


def strategy_names(space=None) -> tuple[str, ...]:
    """Registered strategy names, in registration order; with ``space``, those that apply."""
    return _STRATEGIES.names(space)


def get_strategy(name: str, space=None) -> Strategy:
    """The strategy registered as ``name``; ``ValueError`` naming ``method`` otherwise."""
    return _STRATEGIES.get(name, space)


def register_segmenter(segmenter: Segmenter, *, replace: bool = False) -> Segmenter:
    """Register a multi-model strategy under ``segmenter.name``."""
    return _SEGMENTERS.register(segmenter, replace)


def unregister_segmenter(name: str) -> None:
    """Remove a registered segmenter (for tests and plug-ins)."""
    _SEGMENTERS.unregister(name)


def segmenter_names(space=None) -> tuple[str, ...]:
    """Registered segmenter names, in registration order; with ``space``, those that apply."""
    return _SEGMENTERS.names(space)


def get_segmenter(name: str, space=None) -> Segmenter:
    """The segmenter registered as ``name``; ``ValueError`` naming ``method`` otherwise."""
    return _SEGMENTERS.get(name, space)


def load_plugins() -> tuple[str, ...]:
    """Import the modules other packages declare in the entry-point group
    ``clap_unified.strategies``.

    Each module registers its strategies when imported, so they are
    available to :func:`~clap_unified.fit`, :func:`~clap_unified.compare` and
    the command line like the built-in ones. Returns the names loaded; a
    plug-in that fails to import is reported as a warning, not an error.
    """
    import warnings
    from importlib.metadata import entry_points

    loaded = []
    for ep in entry_points(group=ENTRY_POINTS):
        try:
            ep.load()
        except Exception as exc:  # a broken plug-in must not break the library
            warnings.warn(f"strategy plug-in {ep.name!r} ({ep.value}) failed to load: {exc}",
                          RuntimeWarning, stacklevel=2)
        else:
            loaded.append(ep.name)
    return tuple(loaded)
