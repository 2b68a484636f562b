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
* ``"densest"`` (CLAP on homographies): another reading of the paper;
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
homography``, ``reproduce`` and the book read these presets.

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

from .spaces.base import HypothesisSpace
from .spaces.homography import DEFAULT_THRESHOLD, HomographySpace

__all__ = ["FIT_KEYS", "PRESETS", "Preset", "Settings", "get_preset", "preset_names",
           "protocol_presets", "resolve_preset"]

#: Keys of a preset's ``fit`` part: :func:`~clap_unified.fit`'s own arguments.
FIT_KEYS = ("n_hypotheses", "threshold", "max_hypotheses", "refine")

#: Per space name, the keys of a preset's ``space`` part and their defaults: how
#: the space is built from the data (homographies: in the frame of the matches,
#: :meth:`~clap_unified.spaces.HomographySpace.for_data`, with its ``metric`` and
#: ``screen``, and the reweighted-DLT ``polish`` of the refinement).
SPACE_KEYS = {"homography": {"frame": False, "metric": "lie_linear", "polish": False,
                             "screen": 1.0}}


class Settings(dict):
    """A preset's settings: a dict that refuses changes, and pickles (a process pool can
    take it), unlike ``types.MappingProxyType``.

    Examples
    --------
    >>> s = Settings(rounds=5)
    >>> s["rounds"] = 3
    Traceback (most recent call last):
    ...
    TypeError: read-only: a preset cannot change; use Preset.replace()
    """

    def _refuse(self, *args, **kwargs):
        raise TypeError("read-only: a preset cannot change; use Preset.replace()")

    __setitem__ = __delitem__ = _refuse
    clear = pop = popitem = setdefault = update = __ior__ = _refuse

    def __reduce__(self):
        return (Settings, (dict(self),))


def _frozen(mapping) -> Settings:
    return Settings(mapping)


@dataclass(frozen=True)
class Preset:
    """A strategy's settings in a space, under a name.

    Parameters
    ----------
    name : str
        ``"default"``, ``"paper"``, ``"densest"``, ``"peer"``...
    space_name : str
        The space it applies to (``HypothesisSpace.name``, e.g. ``"homography"``).
    strategy : str
        The registered strategy it runs.
    space : mapping
        How the space is built from the data (keys of ``SPACE_KEYS[space_name]``);
        only the keys this preset sets.
    fit : mapping
        :func:`~clap_unified.fit`'s arguments (keys of :data:`FIT_KEYS`).
    options : mapping
        The strategy's own options.
    protocol : str, optional
        Its name among :func:`~clap_unified.imaging.estimate_homography`'s
        methods (``"clap"``, ``"clap_paper"``...).
    aliases : tuple of str
        Other names of the same preset (RANSAC's ``"default"`` is its ``"paper"``).
    summary : str
        One line for listings.

    Examples
    --------
    >>> p = Preset("mine", "homography", "ransac", fit={"n_hypotheses": 50})
    >>> p.replace(threshold=2.0).fit == {"n_hypotheses": 50, "threshold": 2.0}
    True
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

    def __post_init__(self):
        space_keys = SPACE_KEYS.get(self.space_name, {})
        for key in self.space:
            if key not in space_keys:
                raise ValueError(f"space: {key!r} is not a setting of the {self.space_name} "
                                 f"space (its settings: {', '.join(space_keys) or 'none'})")
        for key in self.fit:
            if key not in FIT_KEYS:
                raise ValueError(f"fit: {key!r} is not one of fit's arguments "
                                 f"({', '.join(FIT_KEYS)})")
        for part in ("space", "fit", "options"):
            object.__setattr__(self, part, _frozen(getattr(self, part)))

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
        space, fit, options = dict(self.space), dict(self.fit), dict(self.options)
        for key, value in changes.items():
            (space if key in space_keys else fit if key in FIT_KEYS else options)[key] = value
        return Preset(self.name, self.space_name, self.strategy, space, fit, options,
                      self.protocol, self.aliases, self.summary)

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
               protocol="clap",
               summary="the library's CLAP: anchor-transfer distance, k-NN seeds, clusters "
                       "scored by truncated consensus, polished; up to 10000 hypotheses"),
        Preset("paper", "homography", "clap",
               space={"frame": True, "metric": "lie", "polish": False},
               fit={"n_hypotheses": 400, "threshold": t},
               options={"neighbourhood": "all", "rounds": 5, "discard_fraction": 0.2,
                        "bandwidth_quantile": 0.02},
               protocol="clap_paper",
               summary="the paper's CLAP as written: 400 hypotheses, ||log(H1^-1 H2)||, the "
                       "robust centre of all of them, DLT refit"),
        Preset("densest", "homography", "clap",
               space={"frame": True, "metric": "lie_linear", "polish": True},
               fit={"n_hypotheses": 400, "threshold": t},
               options={"bandwidth_quantile": 0.02, "rounds": 5, "discard_fraction": 0.2},
               protocol="clap_densest",
               summary="another reading of the paper: trimming inside the densest "
                       "cluster, polished"),
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


#: Every preset, by ``(space name, strategy, preset name)``: the one home of the
#: library's defaults. Protocol order (``"clap"``, ``"clap_paper"``...) is
#: :data:`~clap_unified.imaging.estimate.PROTOCOLS`'s.
PRESETS = Settings({(p.space_name, p.strategy, p.name): p for p in _homography_presets()})

#: The name of "no preset": the strategy's and :func:`~clap_unified.fit`'s own defaults.
OWN = "own"


def _space_name(space) -> str:
    return space.name if isinstance(space, HypothesisSpace) else str(space)


def preset_names(space, strategy: str) -> tuple[str, ...]:
    """The names :func:`get_preset` accepts for ``strategy`` in ``space`` (a space or its name).

    Examples
    --------
    >>> preset_names("homography", "ransac")
    ('default', 'paper', 'ransac', 'own')
    >>> preset_names("line", "clap")
    ('default', 'own')
    """
    name = _space_name(space)
    presets = [p for (s, g, _), p in PRESETS.items() if s == name and g == strategy]
    short = [n for p in presets for n in (p.name, *p.aliases)]
    long = [p.protocol for p in presets if p.protocol]
    return tuple(dict.fromkeys(["default", *short, *long, OWN]))


def get_preset(space, strategy: str, name: str = "default") -> Preset | None:
    """The preset ``name`` of ``strategy`` in ``space`` (a space or its name).

    ``None`` for ``"own"``, and for ``"default"`` where the library has no
    preset (the strategy's own defaults are the default).

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
    >>> get_preset("homography", "clap", "papr")
    Traceback (most recent call last):
    ...
    ValueError: preset: unknown preset 'papr' of 'clap' in the homography space; choices: \
'default', 'paper', 'densest', 'clap', 'clap_paper', 'clap_densest', 'own'
    """
    space_name = _space_name(space)
    if not isinstance(name, str):
        raise ValueError(f"preset: expected a name or a Preset, got {type(name).__name__}")
    for (s, g, _), p in PRESETS.items():
        if s == space_name and g == strategy and name in p.names:
            return p
    if name in (OWN, "default"):
        return None
    choices = ", ".join(repr(n) for n in preset_names(space_name, strategy))
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


def resolve_preset(space, data, method: str, preset, given: dict, options: dict, *,
                   hypotheses_given: bool = False):
    """What :func:`~clap_unified.fit` runs: ``(space, fit's arguments, strategy options)``.

    ``preset`` is ``None`` (the ``"default"`` preset when ``space`` is plain,
    else none), a name, or a :class:`Preset`. ``given`` holds the fit
    arguments passed explicitly (not ``None``; keys of :data:`FIT_KEYS`) and
    ``options`` the keywords; both override the preset. A preset's
    ``max_hypotheses`` is dropped when ``hypotheses`` are given
    (``hypotheses_given``), and raised to an explicit ``n_hypotheses`` above
    it. A space configured by hand (not plain) is used as given.

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
