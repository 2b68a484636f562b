"""CLAP: density centres in hypothesis space."""

from .centres import CENTRES, cluster_centre
from .clap import clap
from .density import auto_bandwidth, knn_distance, neighbour_counts
from .rejection import mad_centre, trimmed_centre

__all__ = ["CENTRES", "auto_bandwidth", "clap", "cluster_centre", "knn_distance",
           "mad_centre", "neighbour_counts", "trimmed_centre"]
