"""clap_unified: robust estimation by consensus over hypotheses.

Three strategies on one abstraction. A :class:`~clap_unified.spaces.HypothesisSpace`
turns minimal samples of data into candidate models living on a
:class:`~clap_unified.geometry.Manifold`; then

* :mod:`clap_unified.hough` clusters them on a grid (the Hough transform),
* :mod:`clap_unified.ransac` scores each against the data (RANSAC),
* :mod:`clap_unified.clap` finds density centres among them (CLAP).

All three return a :class:`~clap_unified.result.ConsensusResult`. The strategy
functions live in their subpackages (``from clap_unified.clap import clap``,
``from clap_unified.ransac import ransac``) so the subpackage names stay
importable; :func:`compare` runs several on one identical hypothesis set.
"""

from . import clap, geometry, hough, ransac, spaces
from .compare import METHODS, compare, fit_line
from .result import Cluster, ConsensusResult
from .spaces import HypothesisSet, HypothesisSpace, LineSpace, generate_hypotheses

__version__ = "0.1.0"

__all__ = [
    "METHODS",
    "Cluster",
    "ConsensusResult",
    "HypothesisSet",
    "HypothesisSpace",
    "LineSpace",
    "clap",
    "compare",
    "fit_line",
    "generate_hypotheses",
    "geometry",
    "hough",
    "ransac",
    "spaces",
]
