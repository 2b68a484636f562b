"""Preference analysis: clustering the data by the hypotheses they agree with."""

from .tlinkage import run_t_linkage, t_linkage_clusters

__all__ = ["run_t_linkage", "t_linkage_clusters"]
