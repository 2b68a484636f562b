"""CLAP: density centres in hypothesis space."""

from .centres import CENTRES, cluster_centre
from .clap import clap, run_clap
from .density import auto_bandwidth, dense_candidates, knn_distance, neighbour_counts
from .rejection import mad_centre, trimmed_centre
from .segment import run_clap_segment

__all__ = ["CENTRES", "auto_bandwidth", "clap", "cluster_centre", "dense_candidates",
           "knn_distance", "mad_centre", "neighbour_counts", "run_clap", "run_clap_segment",
           "trimmed_centre"]
