"""Presets: the one home of the library's defaults, by space, strategy and name.

A :class:`Preset` is what a strategy runs with in a space: how the space is
built from the data (``space``), :func:`~clap_unified.fit`'s own arguments
(``fit``: ``n_hypotheses``, ``threshold``, ``max_hypotheses``, ``refine``) and
the strategy's options (``options``). Each is frozen; :meth:`Preset.replace`
gives a copy with some values overridden, each key routed to its part.

``fit(space, data, method, preset=...)`` selects one by name:

* ``"default"`` (also what ``preset=None`` gives on a plain space): the
  library's best default. ``fit(HomographySpace(), matches, "clap")`` is the
  tuned CLAP of :func:`~clap_unified.imaging.estimate_homography`'s
  ``"clap"``, bit for bit;
* ``"paper"``: the paper's protocol (CLAP: Sec. "Image Stitching Results" as
  written; RANSAC and randomized Hough: the paper's baselines);
* ``"densest"`` (CLAP on homographies): CLAP (densest-cluster reading), another reading of
  the paper (the first-order distance, trimming inside the densest cluster, polished);
* ``"peer"`` (another library's estimator): reported as the peer returns it;
* ``"own"``: no preset, the strategy's and :func:`~clap_unified.fit`'s own
  defaults;
* a protocol name of :data:`~clap_unified.imaging.estimate.PROTOCOLS` that
  runs this strategy (``"clap"``, ``"clap_paper"``, ``"clap_densest"``,
  ``"ransac"``, ``"magsac"``...): the same preset under the name
  :func:`~clap_unified.imaging.estimate_homography` and the command line give
  it.

:data:`PRESETS` holds them all (homographies today: the space whose
strategies need tuning beyond their defaults); a space without an entry has
only ``"default"`` and ``"own"``, both the strategy's own defaults.
:data:`~clap_unified.imaging.estimate.PROTOCOLS`, ``clap-unified fit
homography`` (its ``--method`` help too), ``reproduce`` and the book read
these presets.

The other entry points keep their defaults here too, as presets of another
task (:data:`TASKS`, :data:`TASK_PRESETS`; ``get_preset(..., task=...)``):
``"segment"``, the multi-model defaults of
:func:`~clap_unified.imaging.segment_matches` per kind of matches (the same
for every segmenter: ``strategy=None``), and ``"localize"``, those of
:func:`~clap_unified.localization.localize2d`,
:func:`~clap_unified.localization.localize3d` and
:func:`~clap_unified.localization.align_correspondences` per pose space and
strategy. Their functions, commands, benchmarks and experiments read them.

A named preset given with a space configured by hand applies whole when the
space is the one the preset builds (:func:`space_conflicts` is empty), and
is refused otherwise (``ValueError`` naming ``preset`` and the settings):
never half applied. A preset is equal by value and hashable.

Examples
--------
>>> p = get_preset("homography", "clap", "paper")
>>> p.protocol, p.fit["n_hypotheses"], p.options["neighbourhood"]
('clap_paper', 400, 'all')
>>> q = p.replace(n_hypotheses=800, rounds=3, polish=True)
>>> q.fit["n_hypotheses"], q.options["rounds"], q.space["polish"], p.options["rounds"]
(800, 3, True, 5)
>>> preset_names("homography", "clap")
('default', 'paper', 'densest', 'clap', 'clap_paper', 'clap_densest', 'own')
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .geometry.homography_frame import HomographyInFrame
from .geometry.homography_transfer import HomographyTransfer
from .spaces.base import HypothesisSpace
from .spaces.homography import DEFAULT_THRESHOLD, HomographySpace
from .spaces.landmarks2d import HOUGH_CELL

__all__ = ["FIT_KEYS", "LOCALIZE_KEYS", "PRESETS", "SEGMENT_KEYS", "TASKS", "TASK_PRESETS",
           "Preset", "Settings", "get_preset", "preset_names", "protocol_presets",
           "resolve_preset", "space_conflicts"]

#: Keys of a preset's ``fit`` part: :func:`~clap_unified.fit`'s own arguments.
FIT_KEYS = ("n_hypotheses", "threshold", "max_hypotheses", "refine")
#: Keys of a segmentation preset's ``fit`` part: :func:`~clap_unified.segment`'s arguments
#: (``neighbours``: local samples, a datum and others among its ``neighbours`` nearest,
#: ``segment``'s ``sampling={"neighbours": k}``; sequential RANSAC draws its own so).
SEGMENT_KEYS = ("threshold", "n_hypotheses", "neighbours", "coherence",
                "coherence_neighbours")
#: Keys of a localization preset's ``fit`` part: the arguments of
#: :func:`~clap_unified.localization.localize2d`, :func:`~clap_unified.localization.localize3d`
#: and :func:`~clap_unified.localization.align_correspondences` that every strategy reads
#: (the candidate budget, the inlier threshold, the gate around a prior).
LOCALIZE_KEYS = ("n_hypotheses", "threshold", "radius", "max_translation", "max_rotation")
#: The entry points presets serve, each with the keys of its presets' ``fit`` part:
#: ``"fit"`` (:func:`~clap_unified.fit`, :func:`~clap_unified.imaging.estimate_homography`),
#: ``"segment"`` (:func:`~clap_unified.imaging.segment_matches`) and ``"localize"`` (the
#: one-frame localization functions); their commands read the same presets.
TASKS = {"fit": FIT_KEYS, "segment": SEGMENT_KEYS, "localize": LOCALIZE_KEYS}

#: Per space name, the keys of a preset's ``space`` part and their defaults: how
#: the space is built from the data (homographies: in the frame of the matches,
#: :meth:`~clap_unified.spaces.HomographySpace.for_data`, with its ``metric`` and
#: ``screen``, and the reweighted-DLT ``polish`` of the refinement).
SPACE_KEYS = {"homography": {"frame": False, "metric": "lie_linear", "polish": False,
                             "screen": 1.0}}


def _hashable(value):
    """``value`` as a hashable of the same content (dicts as item sets, sequences as tuples)."""
    if isinstance(value, dict):
        return frozenset((k, _hashable(v)) for k, v in value.items())
    if isinstance(value, (list, tuple)):
        return tuple(_hashable(v) for v in value)
    if isinstance(value, np.ndarray):
        return (value.dtype.str, value.shape, value.tobytes())
    return value


class Settings(dict):
    """A preset's settings: a dict that refuses changes, and pickles (a process pool can
    take it), unlike ``types.MappingProxyType``; equal by value, and hashable (a preset
    can be a dict key or a cache key).

    Examples
    --------
    >>> s = Settings(rounds=5)
    >>> s["rounds"] = 3
    Traceback (most recent call last):
    ...
    TypeError: read-only: a preset cannot change; use Preset.replace()
    >>> s == {"rounds": 5}, hash(s) == hash(Settings(rounds=5))
    (True, True)
    """

    def _refuse(self, *args, **kwargs):
        raise TypeError("read-only: a preset cannot change; use Preset.replace()")

    __setitem__ = __delitem__ = _refuse
    clear = pop = popitem = setdefault = update = __ior__ = _refuse

    def __hash__(self):
        return hash(_hashable(dict(self)))

    def __reduce__(self):
        return (Settings, (dict(self),))


def _frozen(mapping) -> Settings:
    return Settings(mapping)


@dataclass(frozen=True)
class Preset:
    """A strategy's settings in a space, under a name.

    Frozen, equal by value and hashable: two presets with the same settings are
    equal whatever dicts built them, and a preset can key a dict or a cache.

    Parameters
    ----------
    name : str
        ``"default"``, ``"paper"``, ``"densest"``, ``"peer"``...
    space_name : str
        The space it applies to (``HypothesisSpace.name``, e.g. ``"homography"``).
    strategy : str or None
        The registered strategy (or segmenter) it runs; ``None``: every strategy
        of the space (a segmentation or localization preset whose settings do not
        depend on the strategy).
    space : mapping
        How the space is built from the data (keys of ``SPACE_KEYS[space_name]``);
        only the keys this preset sets.
    fit : mapping
        The entry point's own arguments (keys of ``TASKS[task]``: for ``"fit"``,
        :func:`~clap_unified.fit`'s, :data:`FIT_KEYS`).
    options : mapping
        The strategy's own options.
    protocol : str, optional
        Its name among :func:`~clap_unified.imaging.estimate_homography`'s
        methods (``"clap"``, ``"clap_paper"``...).
    aliases : tuple of str
        Other names of the same preset (RANSAC's ``"default"`` is its ``"paper"``).
    summary : str
        One line for listings.
    label : str
        A few words for a command's ``--method`` help (``"the library's CLAP"``).
    task : {"fit", "segment", "localize"}
        The entry point it serves (:data:`TASKS`).

    Examples
    --------
    >>> p = Preset("mine", "homography", "ransac", fit={"n_hypotheses": 50})
    >>> p.replace(threshold=2.0).fit == {"n_hypotheses": 50, "threshold": 2.0}
    True
    >>> p == Preset("mine", "homography", "ransac", fit=dict(n_hypotheses=50))
    True
    >>> len({p, p.replace(), p.replace(n_hypotheses=60)})
    2
    """

    name: str
    space_name: str
    strategy: str
    space: Settings = field(default_factory=dict)
    fit: Settings = field(default_factory=dict)
    options: Settings = field(default_factory=dict)
    protocol: str | None = None
    aliases: tuple[str, ...] = ()
    summary: str = ""
    label: str = ""
    task: str = "fit"

    def __post_init__(self):
        if self.task not in TASKS:
            raise ValueError(f"task: expected one of {', '.join(map(repr, TASKS))}, "
                             f"got {self.task!r}")
        space_keys = SPACE_KEYS.get(self.space_name, {})
        for key in self.space:
            if key not in space_keys:
                raise ValueError(f"space: {key!r} is not a setting of the {self.space_name} "
                                 f"space (its settings: {', '.join(space_keys) or 'none'})")
        keys = TASKS[self.task]
        for key in self.fit:
            if key not in keys:
                raise ValueError(f"fit: {key!r} is not one of {self.task}'s arguments "
                                 f"({', '.join(keys)})")
        for part in ("space", "fit", "options"):
            object.__setattr__(self, part, _frozen(getattr(self, part)))
        object.__setattr__(self, "aliases", tuple(self.aliases))

    @property
    def names(self) -> tuple[str, ...]:
        """Every name this preset is found by: its name, its aliases, its protocol."""
        return tuple(dict.fromkeys([self.name, *self.aliases,
                                    *([self.protocol] if self.protocol else [])]))

    def replace(self, **changes) -> Preset:
        """A copy with ``changes``: space settings, fit's arguments, else strategy options.

        Examples
        --------
        >>> p = get_preset("homography", "clap", "default").replace(n_refine=1, metric="lie")
        >>> p.options["n_refine"], p.space["metric"], p.fit["threshold"]
        (1, 'lie', 3.0)
        """
        space_keys = SPACE_KEYS.get(self.space_name, {})
        keys = TASKS[self.task]
        space, fit, options = dict(self.space), dict(self.fit), dict(self.options)
        for key, value in changes.items():
            (space if key in space_keys else fit if key in keys else options)[key] = value
        return Preset(self.name, self.space_name, self.strategy, space, fit, options,
                      self.protocol, self.aliases, self.summary, self.label, self.task)

    def as_protocol(self) -> dict:
        """The flat dict of :data:`~clap_unified.imaging.estimate.PROTOCOLS`.

        Examples
        --------
        >>> get_preset("homography", "ransac", "paper").as_protocol()
        {'frame': False, 'polish': False, 'n_hypotheses': 1000, 'threshold': 3.0}
        >>> get_preset("homography", "clap", "paper").as_protocol()["strategy"]
        'clap'
        """
        head = {} if self.protocol in (None, self.strategy) else {"strategy": self.strategy}
        return {**head, **self.space, **self.fit, **self.options}

    def build_space(self, data) -> HypothesisSpace:
        """The space this preset asks for, built from ``data`` (a plain space's data).

        Examples
        --------
        >>> src = np.random.default_rng(0).uniform(0, 640, (20, 2))
        >>> get_preset("homography", "clap", "default").build_space(np.c_[src, src + 1.0])
        HomographySpace(residual='transfer', normalization='h33', polish=2.0)
        """
        if self.space_name != "homography":  # no other space is built by a preset yet
            raise ValueError(f"space: presets build no {self.space_name} space")
        s = {**SPACE_KEYS["homography"], **self.space}
        if s["frame"]:
            return HomographySpace.for_data(data, metric=s["metric"], polish=s["polish"],
                                            screen=s["screen"])
        return HomographySpace(polish=s["polish"])


def _homography_presets() -> tuple[Preset, ...]:
    t = DEFAULT_THRESHOLD  # the one threshold of every homography preset, in pixels
    peers_opencv = ("cv2_ransac", "magsac", "usac_accurate", "usac_ransac_fixed")
    peers_lo = ("poselib", "colmap")
    return (
        Preset("default", "homography", "clap",
               space={"frame": True, "metric": "transfer", "polish": 2.0},
               fit={"n_hypotheses": 1000, "threshold": t, "max_hypotheses": 10_000},
               options={"density": "knn", "k": 2, "bandwidth": 3.0, "suppress": 3.0,
                        "rounds": 0, "max_clusters": 16, "min_support": 1,
                        "select": "consensus", "n_refine": 3},
               protocol="clap", label="the library's CLAP",
               summary="the library's CLAP: anchor-transfer distance, k-NN seeds, clusters "
                       "scored by truncated consensus, polished; up to 10000 hypotheses"),
        Preset("paper", "homography", "clap",
               space={"frame": True, "metric": "lie", "polish": False},
               fit={"n_hypotheses": 400, "threshold": t},
               options={"neighbourhood": "all", "rounds": 5, "discard_fraction": 0.2,
                        "bandwidth_quantile": 0.02},
               protocol="clap_paper", label="the paper's protocol as written",
               summary="the paper's CLAP as written: 400 hypotheses, ||log(H1^-1 H2)||, the "
                       "robust centre of all of them, DLT refit"),
        Preset("densest", "homography", "clap",
               space={"frame": True, "metric": "lie_linear", "polish": True},
               fit={"n_hypotheses": 400, "threshold": t},
               options={"bandwidth_quantile": 0.02, "rounds": 5, "discard_fraction": 0.2},
               protocol="clap_densest",
               label="the densest-cluster reading of it: the first-order distance, "
                     "trimming inside the densest cluster, polished",
               summary="CLAP (densest-cluster reading), another reading of the paper: the "
                       "first-order distance, trimming inside the densest cluster, polished"),
        Preset("default", "homography", "ransac", space={"frame": False, "polish": False},
               fit={"n_hypotheses": 1000, "threshold": t}, protocol="ransac",
               aliases=("paper",),
               summary="the paper's RANSAC: DLT on 4-samples, 1000 trials, DLT refit"),
        Preset("default", "homography", "randomized_hough",
               space={"frame": True, "metric": "lie_linear", "polish": False},
               fit={"n_hypotheses": 400, "threshold": t}, options={"cell_size": 0.05},
               protocol="randomized_hough", aliases=("paper",),
               summary="400 hypotheses voted into cells of edge 0.05 of the normalised "
                       "log chart"),
        *(Preset("default", "homography", name, space={"frame": False},
                 fit={"refine": False, "n_hypotheses": 1000, "threshold": t},
                 protocol=name, aliases=("peer",),
                 summary="OpenCV's estimator as it returns it, at most 1000 iterations")
          for name in peers_opencv),
        *(Preset("default", "homography", name, space={"frame": False},
                 fit={"refine": False, "n_hypotheses": 100_000, "threshold": t},
                 options={"confidence": 0.9999, "min_iterations": 1000},
                 protocol=name, aliases=("peer",),
                 summary="the peer's LO-RANSAC as it returns it, with its own defaults")
          for name in peers_lo),
    )


def _segment_presets() -> tuple[Preset, ...]:
    """The defaults of :func:`~clap_unified.imaging.segment_matches`, per kind, for every
    segmenter: the inlier threshold (pixels, the space's residual), the hypotheses drawn and
    how (local samples: a match and others among its 20 nearest, for every segmenter that
    uses the shared hypotheses; sequential RANSAC draws its own the same way) and the
    spatial coherence of the common finish (two matches among each other's 8 nearest, in
    the four coordinates, pay 0.05 of an outlier's cost to lie on different models;
    :mod:`clap_unified.coherence`). Chosen on AdelaideRMF by the benchmark
    ``bench/bench_adelaidermf.py``."""
    shared = {"n_hypotheses": 1000, "neighbours": 20, "coherence": 0.05,
              "coherence_neighbours": 8}
    return (
        Preset("default", "homography", None, fit={"threshold": 5.0, **shared},
               task="segment", summary="several planes: 5 px, 1000 local samples of 20 "
                                       "neighbours, spatial coherence 0.05"),
        Preset("default", "fundamental", None, fit={"threshold": 2.0, **shared},
               task="segment", summary="several rigid motions: 2 px Sampson, 1000 local "
                                       "samples of 20 neighbours, spatial coherence 0.05"),
    )


def _localize_presets() -> tuple[Preset, ...]:
    """The defaults of the one-frame localization functions and their commands: the
    candidate budget, the inlier threshold (metres), the gate around a prior, and each
    strategy's options."""
    peaks = 5  # clusters CLAP reports, peaks the randomized Hough transform reports
    fit2d = {"n_hypotheses": 20000, "threshold": 0.3, "radius": 1.0}
    fit3d = {"n_hypotheses": 1000, "threshold": 0.15}
    gate3d = {"max_translation": 0.5, "max_rotation": float(np.radians(10.0))}
    clap3d = {"bandwidth": 0.15, "centre": "medoid", "min_support": 3, "prune": True}
    return (
        # localize2d: the RoboCup field (the original CLAP, RoboCup 2024 AdultSize)
        Preset("default", "pose2d", None, task="localize", fit=fit2d,
               summary="every observation pair up to 20000, inliers within 0.3 m, a 1 m "
                       "gate around a prior"),
        Preset("default", "pose2d", "clap", task="localize", fit=fit2d,
               options={"bandwidth": 0.25, "max_clusters": peaks, "min_support": 1}),
        Preset("default", "pose2d", "randomized_hough", task="localize", fit=fit2d,
               options={"cell_size": HOUGH_CELL, "num_peaks": peaks}),
        # localize3d: typed 3D landmarks and their map
        Preset("default", "pose3d", None, task="localize", fit={**fit3d, **gate3d},
               summary="every detection triplet up to 1000, inliers within 0.15 m, a gate "
                       "of 0.5 m and 10 degrees around a prior"),
        Preset("default", "pose3d", "clap", task="localize", fit={**fit3d, **gate3d},
               options={**clap3d, "max_clusters": peaks, "select": "support"}),
        Preset("default", "pose3d", "open3d", task="localize",
               fit={**fit3d, **gate3d, "n_hypotheses": 100_000},
               summary="Open3D's correspondence RANSAC, at most 100000 iterations"),
        # align_correspondences: putative 3D correspondences
        Preset("default", "rigid3d", None, task="localize", fit=fit3d,
               summary="1000 random triplets, inliers within 0.15 m"),
        Preset("default", "rigid3d", "clap", task="localize", fit=fit3d, options=clap3d),
    )


#: Every preset of :func:`~clap_unified.fit`, by ``(space name, strategy, preset name)``:
#: the one home of the library's defaults. Protocol order (``"clap"``, ``"clap_paper"``...)
#: is :data:`~clap_unified.imaging.estimate.PROTOCOLS`'s.
PRESETS = Settings({(p.space_name, p.strategy, p.name): p for p in _homography_presets()})

#: Every preset, per task (:data:`TASKS`), by ``(space name, strategy, preset name)``;
#: ``TASK_PRESETS["fit"]`` is :data:`PRESETS`. A strategy ``None`` holds the settings of
#: every strategy of the space without its own preset.
TASK_PRESETS = Settings({
    "fit": PRESETS,
    **{task: Settings({(p.space_name, p.strategy, p.name): p for p in presets})
       for task, presets in (("segment", _segment_presets()),
                             ("localize", _localize_presets()))}})

#: The name of "no preset": the strategy's and :func:`~clap_unified.fit`'s own defaults.
OWN = "own"


def _space_name(space) -> str:
    return space.name if isinstance(space, HypothesisSpace) else str(space)


def _presets(task: str) -> Settings:
    if task not in TASKS:
        raise ValueError(f"task: expected one of {', '.join(map(repr, TASKS))}, got {task!r}")
    return TASK_PRESETS[task]


def _candidates(space_name: str, strategy, task: str) -> list[Preset]:
    """The presets of ``strategy`` in the space, then those of every strategy (``None``)."""
    presets = _presets(task)
    own = [p for (s, g, _), p in presets.items() if s == space_name and g == strategy]
    shared = [p for (s, g, _), p in presets.items() if s == space_name and g is None
              and not any(p.name == q.name for q in own)]
    return own + shared


def preset_names(space, strategy: str | None, *, task: str = "fit") -> tuple[str, ...]:
    """The names :func:`get_preset` accepts for ``strategy`` in ``space`` (a space or its name).

    Examples
    --------
    >>> preset_names("homography", "ransac")
    ('default', 'paper', 'ransac', 'own')
    >>> preset_names("line", "clap")
    ('default', 'own')
    >>> preset_names("homography", "t_linkage", task="segment")
    ('default', 'own')
    """
    presets = _candidates(_space_name(space), strategy, task)
    short = [n for p in presets for n in (p.name, *p.aliases)]
    long = [p.protocol for p in presets if p.protocol]
    return tuple(dict.fromkeys(["default", *short, *long, OWN]))


def get_preset(space, strategy: str | None, name: str = "default", *,
               task: str = "fit") -> Preset | None:
    """The preset ``name`` of ``strategy`` in ``space`` (a space or its name), for ``task``.

    ``None`` for ``"own"``, and for ``"default"`` where the library has no
    preset (the strategy's own defaults are the default). A strategy without a
    preset of its own takes the space's preset of every strategy (``strategy``
    ``None``), if any: the segmentation defaults of a kind of matches are the
    same for every segmenter.

    Raises
    ------
    ValueError
        An unknown name: the message names ``preset`` and lists the choices.

    Examples
    --------
    >>> get_preset("homography", "clap", "clap_paper").name
    'paper'
    >>> get_preset("line", "clap") is None
    True
    >>> get_preset("homography", "ransac", task="segment").fit["threshold"]
    5.0
    >>> get_preset("pose2d", "clap", task="localize").options["bandwidth"]
    0.25
    >>> get_preset("homography", "clap", "papr")
    Traceback (most recent call last):
    ...
    ValueError: preset: unknown preset 'papr' of 'clap' in the homography space; choices: \
'default', 'paper', 'densest', 'clap', 'clap_paper', 'clap_densest', 'own'
    """
    space_name = _space_name(space)
    if not isinstance(name, str):
        raise ValueError(f"preset: expected a name or a Preset, got {type(name).__name__}")
    for p in _candidates(space_name, strategy, task):
        if name in p.names:
            return p
    if name in (OWN, "default"):
        return None
    choices = ", ".join(repr(n) for n in preset_names(space_name, strategy, task=task))
    raise ValueError(f"preset: unknown preset {name!r} of {strategy!r} in the {space_name} "
                     f"space; choices: {choices}")


def protocol_presets(space="homography") -> dict[str, Preset]:
    """Every preset with a protocol name, by that name (``"clap"``, ``"clap_paper"``...).

    Examples
    --------
    >>> list(protocol_presets())[:4]
    ['clap', 'clap_paper', 'clap_densest', 'ransac']
    """
    name = _space_name(space)
    return {p.protocol: p for (s, _, _), p in PRESETS.items() if s == name and p.protocol}


def _space_settings(space) -> dict:
    """The preset settings (``SPACE_KEYS``) a space was built with; ``{}`` for a space whose
    presets set none."""
    if space.name != "homography" or not isinstance(space, HomographySpace):
        return {}
    # the manifold a frame set, read without building the default one (the property
    # builds it on first use; reading the settings leaves the space as it was)
    manifold = vars(space).get("_manifold")
    if isinstance(manifold, HomographyTransfer):
        return {"frame": True, "metric": "transfer", "polish": space.polish}
    if isinstance(manifold, HomographyInFrame):
        return {"frame": True, "metric": manifold.metric, "screen": manifold.screen,
                "polish": space.polish}
    return {"frame": False, "polish": space.polish}


def space_conflicts(preset: Preset, space) -> dict:
    """The space settings of ``preset`` that a space built by hand does not have.

    ``{setting: (the preset's value, the space's value)}``, empty when the
    space is the one the preset would build (the settings that matter: a
    preset without a frame sets no metric). :func:`resolve_preset` refuses a
    named preset on a configured space with conflicts.

    Examples
    --------
    >>> src = np.random.default_rng(0).uniform(0, 640, (20, 2))
    >>> m = np.c_[src, src + 1.0]
    >>> paper = get_preset("homography", "clap", "paper")
    >>> space_conflicts(paper, HomographySpace.for_data(m, metric="lie"))
    {}
    >>> space_conflicts(paper, HomographySpace.for_data(m, metric="transfer", polish=True))
    {'metric': ('lie', 'transfer'), 'polish': (False, True)}
    """
    have = _space_settings(space)
    if not have or preset.space_name != space.name:
        return {}
    want = {**SPACE_KEYS.get(preset.space_name, {}), **preset.space}
    keys = (("frame", "polish") if not want["frame"] else
            ("frame", "metric", "polish") if want["metric"] == "transfer" else
            ("frame", "metric", "screen", "polish"))
    return {k: (want[k], have[k]) for k in keys  # a setting the space has no use for: none
            if k in have and (want[k] != have[k]
                              or (type(want[k]) is bool) != (type(have[k]) is bool))}


def resolve_preset(space, data, method: str, preset, given: dict, options: dict, *,
                   hypotheses_given: bool = False):
    """What :func:`~clap_unified.fit` runs: ``(space, fit's arguments, strategy options)``.

    ``preset`` is ``None`` (the ``"default"`` preset when ``space`` is plain,
    else none), a name, or a :class:`Preset`. ``given`` holds the fit
    arguments passed explicitly (not ``None``; keys of :data:`FIT_KEYS`) and
    ``options`` the keywords; both override the preset. A preset's
    ``max_hypotheses`` is dropped when ``hypotheses`` are given
    (``hypotheses_given``), and raised to an explicit ``n_hypotheses`` above
    it. A space configured by hand (not plain) is used as given: with no
    preset (``preset=None`` or ``"own"``), the strategy's own defaults; with a
    named preset, that preset's arguments and options, provided the space is
    the one the preset builds (:func:`space_conflicts`), else ``ValueError``
    naming ``preset`` and the conflicting settings: a preset is never half
    applied.

    Examples
    --------
    >>> src = np.random.default_rng(0).uniform(0, 640, (20, 2))
    >>> m = np.c_[src, src + 1.0]
    >>> space, args, opts = resolve_preset(HomographySpace(), m, "clap", None,
    ...                                    {"n_hypotheses": 20000}, {"n_refine": 1})
    >>> space.polish, args["max_hypotheses"], opts["n_refine"], opts["select"]
    (2.0, 20000, 1, 'consensus')
    >>> resolve_preset(HomographySpace(), m, "clap", "own", {}, {})[1]
    {}
    """
    plain = getattr(space, "is_plain", False)
    if isinstance(preset, Preset):
        if preset.strategy != method or preset.space_name != space.name:
            raise ValueError(f"preset: a preset of {preset.strategy!r} in the "
                             f"{preset.space_name} space, not of {method!r} in the "
                             f"{space.name} space")
        chosen = preset
    elif preset is None:
        chosen = get_preset(space, method) if plain else None
    else:
        chosen = get_preset(space, method, preset)
    if chosen is None:
        return space, dict(given), dict(options)
    if not plain and (conflicts := space_conflicts(chosen, space)):
        said = ", ".join(f"{k}={have!r} (the preset's {want!r})"
                         for k, (want, have) in conflicts.items())
        fix = ", ".join(f"{k}={have!r}" for k, (_, have) in conflicts.items())
        raise ValueError(
            f"preset: {chosen.name!r} of {method!r} builds its own {chosen.space_name} space, "
            f"and the space given, configured by hand, differs: {said}. Pass a plain "
            f"{type(space).__name__}() for the preset to build its space, preset='own' for "
            f"the strategy's own defaults on this space, or the preset changed to this "
            f"space: get_preset({chosen.space_name!r}, {method!r}, {chosen.name!r})"
            f".replace({fix})")
    space_keys = SPACE_KEYS.get(chosen.space_name, {})
    for key in options:
        if key in space_keys and not plain:
            raise ValueError(f"{key}: a setting of the space a preset builds, and only from "
                             f"a plain {type(space).__name__}(); this space is configured")
    merged = chosen.replace(**given, **options)
    args = {k: v for k, v in merged.fit.items()}
    if "max_hypotheses" not in given and args.get("max_hypotheses") is not None:
        if hypotheses_given:
            args.pop("max_hypotheses")  # given hypotheses: nothing more to draw
        elif "n_hypotheses" in given:  # a budget above the preset's cap raises the cap
            args["max_hypotheses"] = max(args["max_hypotheses"], int(given["n_hypotheses"]))
    if plain:
        space = merged.build_space(data)
    return space, args, dict(merged.options)
