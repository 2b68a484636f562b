"""Homography from point matches: :func:`~clap_unified.fit` with named protocols.

:func:`estimate_homography` is a thin application of :func:`~clap_unified.fit`:
it fits in a plain :class:`~clap_unified.spaces.HomographySpace` with the
method's preset (:mod:`clap_unified.presets`, the one home of these
defaults), which builds the space the protocol asks for. The protocols, one
dict per method name in :data:`PROTOCOLS` (derived from the presets; a
registered strategy without one gets :data:`DEFAULT_PROTOCOL`).
``estimate_homography(matches, "clap")`` is ``fit(HomographySpace(), matches,
"clap")``, bit for bit, and ``"clap_paper"`` is ``fit(..., "clap",
preset="paper")``:

* ``"clap"`` (the library's default CLAP): 1000 candidate homographies from
  random 4-match samples, compared by where they send five anchors of the
  matched region (:class:`~clap_unified.geometry.homography_transfer.HomographyTransfer`,
  a distance in pixels, neighbour queries on a k-d tree); seeds ranked by
  the distance to their second-nearest candidate, clusters within 3 px of a
  seed, 9 px suppressed around each, up to 16 clusters; the clusters'
  centres are scored against the matches by truncated consensus (MSAC), the
  best three refined, the best after refinement is the answer
  (``select="consensus"``); refinement is the DLT refit and the reweighted
  DLT with weights reaching zero at twice the threshold (``polish=2.0``).
  When the estimate's inlier ratio says fewer than five all-inlier samples
  are expected among the 1000, up to 10000 candidates are drawn and
  clustered again (``max_hypotheses``, see :func:`~clap_unified.fit`).
  Every other cluster is reported too: a second, coherent motion in the
  matches shows up as the second cluster;
* ``"clap_paper"`` (the paper's, Sec. "Image Stitching Results", as
  written): 400 candidates compared by the paper's distance
  ``||log(H1^-1 H2)||_F`` (``metric="lie"``) in the normalised frame of the
  matches (:meth:`HomographySpace.for_data`; the exact logarithm for every
  pair whose first-order distance is below 1, the first-order value beyond,
  where no two candidates are alike); the robust single centre of *all*
  candidates (``neighbourhood="all"``): their medoid, then 5 rounds each
  discarding the 20 % farthest from the current medoid; then the same
  re-estimation as RANSAC's, a DLT refit on the data inliers of the centre
  (no polish);
* ``"clap_densest"`` (CLAP (densest-cluster reading), another reading of
  the same words, kept for comparison): the candidates compared by the first-order distance
  ``"lie_linear"``, bandwidth the 2 % quantile of their 4-NN distances,
  the cluster with the most candidates, its robust centre by 5 rounds of
  trimming 20 % (medoid), then the DLT refit and a polish by reweighted DLT
  (``polish=True``, :mod:`~clap_unified.spaces.homography_polish`), which
  the paper's RANSAC baseline does not get;
* ``"ransac"``: the paper's baseline, DLT on 4-samples, a fixed budget of
  1000 trials, DLT refit on the inliers, no polish;
* ``"randomized_hough"``: the same candidates as CLAP voted into cells of
  edge 0.05 of the normalised-frame log chart;
* ``"cv2_ransac"``, ``"magsac"``, ``"usac_accurate"``,
  ``"usac_ransac_fixed"``: OpenCV's estimators
  (:mod:`clap_unified.external.opencv`), reported as OpenCV returns them
  (``refine=False``), at most 1000 iterations;
* ``"poselib"``, ``"colmap"``: PoseLib's and COLMAP's LO-RANSAC
  (:mod:`clap_unified.external.poselib`, :mod:`clap_unified.external.colmap`),
  reported as the peer returns them (``refine=False``), with the peers' own
  defaults (at least 1000 and at most 100000 iterations, confidence 0.9999:
  what a user calling them gets), seeded from ``rng``.

Every protocol uses the inlier threshold of
:data:`~clap_unified.spaces.homography.DEFAULT_THRESHOLD` (3 px). ``quality`` (lower is
better, e.g. the SIFT ratio of each match) makes the samples progressive, as
in PROSAC (:meth:`HomographySpace.hypotheses`): the first candidates are
drawn from the best few matches, later ones from more and more of them. That
is what lets clustering work when only a few percent of the matches are
right.
"""

from __future__ import annotations

from .._validation import Checked
from ..fitting import fit
from ..presets import Preset, Settings, protocol_presets
from ..result import ConsensusResult
from ..spaces.homography import DEFAULT_THRESHOLD, HomographySpace

__all__ = ["DEFAULT_PROTOCOL", "MIN_MATCHES", "PROTOCOLS", "clap_homography",
           "estimate_homography", "method_names", "ransac_homography", "strategy_of"]

#: Per method name, the defaults of :func:`estimate_homography`, derived from the
#: presets of :mod:`clap_unified.presets` (their one home: change a default there).
#: Keys: ``strategy`` (the registered strategy a protocol of another name runs;
#: default: the method name itself), ``frame`` (compare hypotheses in a frame
#: of the matches, :meth:`HomographySpace.for_data`), ``metric`` and
#: ``screen`` (its distance), ``polish`` (the space's refinement ends with the
#: reweighted DLT); every other key is an argument of :func:`~clap_unified.fit` or an
#: option of the strategy. A read-only view: override a protocol with
#: ``estimate_homography(..., **options)`` or ``Preset.replace``.
PROTOCOLS = Settings({name: Settings(p.as_protocol())
                      for name, p in protocol_presets(HomographySpace.name).items()})

#: The protocol of a registered homography strategy without an entry in :data:`PROTOCOLS`.
DEFAULT_PROTOCOL = Settings({"frame": False, "polish": False, "threshold": DEFAULT_THRESHOLD})

#: Matches below this count cannot give a homography worth reporting.
MIN_MATCHES = 8


def method_names() -> tuple[str, ...]:
    """Every name :func:`estimate_homography` accepts: protocols and homography strategies.

    Examples
    --------
    >>> {"clap", "clap_paper", "clap_densest", "ransac"} <= set(method_names())
    True
    """
    from ..registry import strategy_names

    names = strategy_names(HomographySpace())
    return tuple(dict.fromkeys([*names, *(m for m in PROTOCOLS if m not in names)]))


def strategy_of(method: str) -> str:
    """The registered strategy that ``method`` (a protocol or strategy name) runs.

    Examples
    --------
    >>> strategy_of("clap_paper"), strategy_of("magsac")
    ('clap', 'magsac')
    """
    return PROTOCOLS.get(method, {}).get("strategy", method)


def estimate_homography(matches, method: str = "clap", *, rng=None, quality=None,
                        **options) -> ConsensusResult:
    """Homography from ``matches`` by ``method`` with its protocol in :data:`PROTOCOLS`.

    Parameters
    ----------
    matches : ndarray of shape (N, 4)
        Rows ``(x1, y1, x2, y2)``; ``H`` maps point 1 to point 2. At least
        :data:`MIN_MATCHES`.
    method : str
        A protocol of :data:`PROTOCOLS` or a registered strategy that applies
        to homographies (``method_names``). ``"clap"`` is the library's
        default CLAP, ``"clap_paper"`` the paper's protocol.
    rng : None, int or numpy.random.Generator
    quality : ndarray of shape (N,), optional
        Per-match quality, lower is better: progressive sampling of the
        hypotheses (methods that use hypotheses).
    **options
        Override the protocol: ``polish``, ``frame``, ``metric``, ``screen`` (the space),
        :func:`~clap_unified.fit`'s arguments (``n_hypotheses``,
        ``threshold``, ``hypotheses``, ``refine``) and the strategy's options
        (e.g. ``neighbourhood``, ``bandwidth_quantile``, ``centre``,
        ``cell_size``, ``confidence``). With ``"clap_paper"``,
        ``neighbourhood="bandwidth"`` trims inside the densest cluster instead
        (bandwidth from ``bandwidth_quantile``): CLAP (paper) + in-cluster
        trim, which keeps the paper's distance and has no polish, unlike
        ``"clap_densest"``.

    Returns
    -------
    ConsensusResult
        ``diagnostics["seconds"]`` is the wall time of the fit.

    Raises
    ------
    ValueError
        Fewer than :data:`MIN_MATCHES` matches, bad matches, an unknown
        method or option.

    Examples
    --------
    >>> rng = np.random.default_rng(1)
    >>> src = rng.uniform(0, 640, (200, 2))
    >>> dst = src @ np.array([[0.9, 0.1], [-0.1, 0.9]]).T + [30.0, -20.0]
    >>> dst += rng.normal(0, 0.5, dst.shape)
    >>> dst[:100] = rng.uniform(0, 640, (100, 2))           # 50 % outliers
    >>> res = estimate_homography(np.c_[src, dst], "clap", rng=0)
    >>> res.success, np.round(res.model[:2, 2]).tolist()
    (True, [30.0, -20.0])
    >>> res = estimate_homography(np.c_[src, src + [4.0, 2.0]], "randomized_hough", rng=0)
    >>> res.success, np.round(res.model[:2, 2], 3).tolist()
    (True, [4.0, 2.0])
    """
    data = HomographySpace().check_data(matches)  # the one check of the matches: fit and
    if len(data) < MIN_MATCHES:                   # the preset's space get them Checked
        raise ValueError(f"matches: too few matches ({len(data)}); at least {MIN_MATCHES} "
                         "are needed for a robust homography")
    protocol = protocol_presets(HomographySpace.name).get(method)
    if protocol is None:  # a registered strategy without a protocol of its own
        protocol = Preset("default", HomographySpace.name, method).replace(**DEFAULT_PROTOCOL)
    if "max_hypotheses" in options and options["max_hypotheses"] is None:
        options = dict(options)  # no adaptive budget, whatever the protocol's
        protocol = protocol.replace(max_hypotheses=options.pop("max_hypotheses"))
    strategy = protocol.strategy
    sampling = None if quality is None else {"quality": quality}
    res = fit(HomographySpace(), Checked(data), strategy, rng=rng, sampling=sampling,
              preset=protocol, **options)
    return res if strategy == method else res.replace(method=method)


def clap_homography(matches, **options) -> ConsensusResult:
    """CLAP with the paper's protocol: ``estimate_homography(matches, "clap_paper", **options)``.

    The library's default CLAP for homographies is ``estimate_homography(matches, "clap")``.
    """
    return estimate_homography(matches, "clap_paper", **options)


def ransac_homography(matches, **options) -> ConsensusResult:
    """The paper's RANSAC baseline: ``estimate_homography(matches, "ransac", **options)``."""
    return estimate_homography(matches, "ransac", **options)
