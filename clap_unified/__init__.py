"""clap_unified: robust estimation by consensus over hypotheses.

Three strategies on one abstraction. A :class:`~clap_unified.spaces.HypothesisSpace`
turns minimal samples of data into candidate models living on a
:class:`~clap_unified.geometry.Manifold`; then

* :mod:`clap_unified.hough` clusters them on a grid (the Hough transform),
* :mod:`clap_unified.ransac` scores each against the data (RANSAC),
* :mod:`clap_unified.clap` finds density centres among them (CLAP).

Each is a strategy registered under one name (:mod:`clap_unified.registry`);
:func:`fit` is the one entry point, and :func:`compare` runs several strategies
on one identical hypothesis set. All return a frozen
:class:`~clap_unified.result.ConsensusResult`. The house is described in
``ARCHITECTURE.md``.
"""

from . import geometry, spaces
from .fitting import compare, fit, fit_line
from .registry import (
    Segmenter,
    Strategy,
    get_segmenter,
    get_strategy,
    register_segmenter,
    register_strategy,
    segmenter_names,
    strategy_names,
)
from .result import Cluster, Consensus, ConsensusResult, Segmentation, SegmentationResult
from .segmenting import compare_segmenters, segment
from .spaces import (
    CircleSpace,
    FundamentalSpace,
    HomographySpace,
    HypothesisSet,
    HypothesisSpace,
    LineNDSpace,
    LineSpace,
    SkimageModelSpace,
    generate_hypotheses,
)

# The strategies register themselves on import (subpackages: hough, ransac, clap).
from . import hough, ransac, clap, preference  # noqa: E402,I001  isort: skip
from . import external  # noqa
from .registry import load_plugins  # noqa: E402

load_plugins()

__version__ = "0.1.0"

__all__ = [
    "CircleSpace",
    "Cluster",
    "Consensus",
    "ConsensusResult",
    "FundamentalSpace",
    "HomographySpace",
    "HypothesisSet",
    "HypothesisSpace",
    "LineNDSpace",
    "LineSpace",
    "clap",
    "compare",
    "compare_segmenters",
    "fit",
    "fit_line",
    "get_strategy",
    "generate_hypotheses",
    "geometry",
    "hough",
    "preference",
    "ransac",
    "register_segmenter",
    "register_strategy",
    "segment",
    "segmenter_names",
    "Segmentation",
    "SegmentationResult",
    "SkimageModelSpace",
    "Segmenter",
    "get_segmenter",
    "spaces",
    "strategy_names",
    "Strategy",
]
