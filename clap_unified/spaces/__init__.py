"""Hypothesis spaces: model families, their minimal solvers and residuals."""

from ..geometry.rigid import kabsch
from .base import HypothesisSpace
from .circles import CircleSpace
from .fundamental import FundamentalSpace
from .homography import HomographySpace, dlt
from .hypothesis_set import HypothesisSet
from .landmarks3d import Landmark3DSpace
from .lines import LineSpace
from .lines_nd import LineNDSpace
from .observations import ObservationSpace
from .rigid3d import Correspondence3DSpace
from .sampling import enumerate_hypotheses, generate_hypotheses, sample_subsets
from .skimage_model import SkimageModelSpace

__all__ = [
    "CircleSpace",
    "Correspondence3DSpace",
    "FundamentalSpace",
    "HypothesisSet",
    "HomographySpace",
    "HypothesisSpace",
    "Landmark3DSpace",
    "LineNDSpace",
    "LineSpace",
    "ObservationSpace",
    "SkimageModelSpace",
    "dlt",
    "enumerate_hypotheses",
    "generate_hypotheses",
    "kabsch",
    "sample_subsets",
]
