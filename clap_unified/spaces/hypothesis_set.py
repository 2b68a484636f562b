"""The hypotheses of a space: candidate models and the minimal samples they came from."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["HypothesisSet"]


@dataclass(frozen=True)
class HypothesisSet:
    """Candidate models generated from minimal samples.

    Attributes
    ----------
    models : ndarray of shape (H,) + model_shape
        The candidate models, one per row.
    samples : ndarray of shape (H, m)
        Indices of the data each model was solved from (``m`` = minimal sample size).
    n_draws : int
        Minimal samples drawn (or enumerated) to obtain them.
    n_degenerate : int
        Samples the solver rejected as degenerate.
    exhaustive : bool
        True when every subset of the data was enumerated.
    space : HypothesisSpace
        The space that generated them.
    """

    models: np.ndarray
    samples: np.ndarray
    n_draws: int
    n_degenerate: int
    exhaustive: bool
    space: object = field(repr=False)  # the HypothesisSpace (spaces.base) that made them

    def __post_init__(self):
        # read-only in place: a result's model may be a view of one of these rows
        for a in (self.models, self.samples):
            if isinstance(a, np.ndarray):
                a.flags.writeable = False

    def __len__(self) -> int:
        return int(self.models.shape[0])

    def subset(self, index) -> HypothesisSet:
        """A new set holding only ``models[index]``."""
        return HypothesisSet(self.models[index], self.samples[index], self.n_draws,
                             self.n_degenerate, self.exhaustive, self.space)
