"""The hypothesis-space protocol every model family implements.

A *hypothesis space* knows how to turn a minimal sample of data into candidate
models, how far a model is from each datum (residuals), how to refit a model
to many weighted data, and which manifold its models live in. The three
consensus strategies (Hough, RANSAC, CLAP) are written against this protocol
only, so one set of hypotheses can be handed to all three.

Conventions (PoseLib style): a minimal solver returns 0..k models per sample;
zero models means the sample was degenerate. Residuals are computed for many
models against many data at once, ``(H, N)``.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass, field

import numpy as np

from ..geometry.base import Manifold

__all__ = ["HypothesisSpace", "HypothesisSet"]


@dataclass(frozen=True)
class HypothesisSet:
    """Candidate models generated from minimal samples.

    Attributes
    ----------
    models : ndarray of shape (H, *model_shape)
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
    space: HypothesisSpace = field(repr=False)

    def __len__(self) -> int:
        return int(self.models.shape[0])

    def subset(self, index) -> HypothesisSet:
        """A new set holding only ``models[index]``."""
        return HypothesisSet(self.models[index], self.samples[index], self.n_draws,
                             self.n_degenerate, self.exhaustive, self.space)


class HypothesisSpace(ABC):
    """A family of models estimated from data by minimal samples.

    Subclasses set :attr:`min_samples` and :attr:`model_shape` and implement
    :meth:`check_data`, :meth:`solve_minimal`, :meth:`refit`, :meth:`residuals`
    and :attr:`manifold`.
    """

    #: Size of a minimal sample.
    min_samples: int
    #: Shape of one model array.
    model_shape: tuple
    #: Short name used in results and the command line.
    name: str = "space"

    @property
    @abstractmethod
    def manifold(self) -> Manifold:
        """The manifold (often a Lie group) the models live in."""

    @abstractmethod
    def check_data(self, data) -> np.ndarray:
        """Validate ``data`` and return it as an array; raise ``ValueError`` naming ``data``."""

    @abstractmethod
    def solve_minimal(self, data: np.ndarray, samples: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Solve many minimal samples at once.

        Parameters
        ----------
        data : ndarray of shape (N, ...)
        samples : ndarray of int, shape (S, min_samples)
            Row ``s`` lists the data indices of one minimal sample.

        Returns
        -------
        models : ndarray of shape (K, *model_shape)
            All models found; a sample can give 0..k of them (0 = degenerate).
        owner : ndarray of int, shape (K,)
            ``owner[j]`` is the row of ``samples`` model ``j`` came from.
        """

    @abstractmethod
    def refit(self, data: np.ndarray, weights=None, initial=None):
        """Non-minimal (weighted) least-squares fit; ``None`` when degenerate.

        ``initial`` is the current model: spaces whose fit needs an association
        (landmarks to map features) use it, the others ignore it.
        """

    @abstractmethod
    def residuals(self, models, data: np.ndarray) -> np.ndarray:
        """Residuals of every model against every datum, shape ``(H, N)``, in data units."""

    def model_to_dict(self, model) -> dict:
        """A JSON-friendly description of one model."""
        return {"model": np.asarray(model).tolist()}

    def default_residual_threshold(self, data: np.ndarray) -> float:
        """A residual threshold for inliers when the user gives none."""
        raise ValueError(f"residual_threshold: no default for the {self.name} space; pass one")
