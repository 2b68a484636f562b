"""Image datasets: manifests and loaders (nothing large is committed).

Every loader returns a frozen object whose ``input`` is what an estimator may
see and whose ``truth`` is evaluation data (:mod:`clap_unified.datatypes`).

* :mod:`.sources`: mirror / cache / public source lookup with sha256 checks;
* :mod:`.homography_benchmarks`: homogr and EVD pairs with ground truth;
* :mod:`.adelaidermf`: AdelaideRMF, the multi-model fitting benchmark (image
  pairs with several planes or moving objects, labelled correspondences) and
  the published misclassification errors on it;
* :mod:`.vpg`: the VPG stitching dataset layout;
* ``synthetic_pairs``: synthetic hard homography pairs (few inliers, a
  coherent decoy motion, uniform outliers) with exact ground truth;
* ``synthetic_two_view``: two views of one or several rigid motions
  (fundamental matrices) with outliers and exact ground truth;
* :mod:`.synthetic_vpg`: a VPG-layout set from scikit-image photographs and
  textures, pure-rotation cameras, exact ground truth;
* :mod:`.stitching_sets`: eleven real panorama sets with parallax and no
  ground truth (the substitute for VPG's real-world sets S13-S36).
"""

from .adelaidermf import (
    MultiModelInput,
    MultiModelPair,
    MultiModelTruth,
    adelaidermf_names,
    load_adelaidermf,
    published_results,
)
from .homography_benchmarks import (
    HomographyInput,
    HomographyPair,
    HomographyTruth,
    evd_names,
    homogr_names,
    load_evd,
    load_homogr,
)
from .sources import fetch, load_manifest
from .stitching_sets import (
    PanoramaInput,
    PanoramaSet,
    PanoramaTruth,
    load_stitching_set,
    stitching_set_names,
)
from .synthetic_pairs import SyntheticTruth, synthetic_pair, synthetic_pairs
from .synthetic_two_view import TwoViewTruth, synthetic_two_view
from .synthetic_vpg import SCENES, load_synthetic_vpg, make_synthetic_vpg
from .vpg import VPGInput, VPGSet, VPGTruth, list_vpg_sets, load_vpg_set, vpg_root

__all__ = ["SCENES", "HomographyInput", "HomographyPair", "HomographyTruth", "MultiModelInput",
           "MultiModelPair", "MultiModelTruth", "PanoramaInput", "PanoramaSet", "PanoramaTruth",
           "SyntheticTruth", "TwoViewTruth", "VPGInput", "VPGSet", "VPGTruth", "adelaidermf_names",
           "evd_names", "fetch", "homogr_names", "list_vpg_sets", "load_adelaidermf", "load_evd",
           "load_homogr", "load_manifest", "load_stitching_set", "load_synthetic_vpg",
           "load_vpg_set", "make_synthetic_vpg", "published_results", "stitching_set_names",
           "synthetic_pair", "synthetic_pairs", "synthetic_two_view", "vpg_root"]
