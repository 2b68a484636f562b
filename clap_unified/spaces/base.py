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

import dataclasses
from abc import ABC, abstractmethod
from dataclasses import dataclass

import numpy as np

from ..geometry.base import Manifold
from ..refine import inliers_of, refit_on_inliers
from .hypothesis_set import HypothesisSet  # noqa: F401  (the protocol's hypotheses, re-exported)

__all__ = ["Capabilities", "HypothesisSpace"]


@dataclass(frozen=True)
class Capabilities:
    """The optional abilities of a hypothesis space, declared in one place.

    Strategies and :func:`~clap_unified.fit` read these flags; nothing probes
    a space for methods. Every space has the protocol's required methods and
    the defaults of :class:`HypothesisSpace`; the flags say where a space
    does more.

    Attributes
    ----------
    prior_hypotheses : bool
        :meth:`HypothesisSpace.hypotheses` uses a prior: given one, it builds
        only the candidates of the data association the prior implies
        (local mode of the localization spaces).
    local_refit : bool
        :meth:`HypothesisSpace.refit_steps` shares work between the inlier
        test and the refit (the data-to-map association computed for the
        inliers is the one the refit needs).
    split_mean : bool
        The manifold averages its parts apart (rotation and translation):
        CLAP's ``centre="split"``.
    chordal_embedding : bool
        The manifold embeds its points in a Euclidean space whose distance
        bounds its own: CLAP's ``prune`` counts neighbours with a k-d tree.
    grid : bool
        :meth:`HypothesisSpace.hough_grid` gives coordinates of its own for
        the randomized Hough grid (otherwise the manifold's log chart).
    """

    prior_hypotheses: bool = False
    local_refit: bool = False
    split_mean: bool = False
    chordal_embedding: bool = False
    grid: bool = False


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
    #: What this space can do beyond the protocol (see
    #: :class:`~clap_unified.spaces.base.Capabilities`).
    #: The manifold's flags (``split_mean``, ``chordal_embedding``) are added
    #: by :attr:`capabilities`.
    declared: Capabilities = Capabilities()

    @property
    def capabilities(self) -> Capabilities:
        """The space's declared capabilities with its manifold's (computed once)."""
        caps = self.__dict__.get("_capabilities")
        if caps is None or caps[0] is not self.manifold:
            m = self.manifold
            caps = (m, dataclasses.replace(self.declared, split_mean=m.has_split_mean,
                                           chordal_embedding=m.has_chordal_embedding))
            self.__dict__["_capabilities"] = caps
        return caps[1]

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
        models : ndarray of shape (K,) + model_shape
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

    def default_threshold(self, data: np.ndarray) -> float:
        """An inlier threshold (data units) when the user gives none."""
        raise ValueError(f"threshold: no default for the {self.name} space; pass one")

    # -- defaults of the optional parts; a space overrides them and says so in `declared`

    def hypotheses(self, data: np.ndarray, n: int, *, rng=None, prior=None, radius=None,
                   **sampling) -> HypothesisSet:
        """Candidate models from minimal samples of ``data`` (``n`` wanted).

        The default draws uniform random minimal samples
        (:func:`~clap_unified.spaces.generate_hypotheses`, every subset when
        there are few). A space with ``prior_hypotheses`` uses ``prior`` and
        ``radius``; others ignore them. ``sampling`` holds space-specific
        sampling options (e.g. the match quality of homographies);
        ``neighbours=k`` draws local samples in every space (a seed and others
        among its ``k`` nearest data). ``data`` is as :meth:`check_data` returns it
        (what :func:`~clap_unified.fit` passes): it is not checked again.
        """
        from .._validation import Checked
        from .sampling import generate_hypotheses

        unknown = sorted(set(sampling) - {"neighbours"})
        if unknown:
            raise ValueError(f"sampling: the {self.name} space takes only 'neighbours' (local "
                             f"sampling), got {unknown}")
        return generate_hypotheses(self, Checked(np.asarray(data, dtype=float)), n, rng=rng,
                                   **sampling)

    def near_prior(self, prior, models, radius) -> np.ndarray:
        """Boolean mask of the ``models`` within ``radius`` of ``prior`` (the local gate).

        A scalar ``radius`` always means the manifold's distance (strategies
        may compute it with other distances at once); a space may accept other
        gate specifications besides (e.g. a translation and a rotation bound).
        """
        if np.ndim(radius) != 0:
            raise ValueError(f"radius: the {self.name} space gates with one distance, got "
                             f"{np.asarray(radius).tolist()}")
        return self.manifold.distance(prior, models) <= radius

    def inliers(self, model, data: np.ndarray, threshold: float) -> np.ndarray:
        """Boolean mask of the data whose residual to ``model`` is below ``threshold``."""
        return inliers_of(self, model, data, threshold)

    def refit_steps(self, data: np.ndarray, threshold: float):
        """Two functions, ``inliers(model)`` and ``refit(inliers, model)``, for refinement.

        The default is the plain route: :meth:`inliers` and
        ``refit(data[inliers], initial=model)``. A space with ``local_refit``
        shares work between them.
        """
        def inliers(model):
            return inliers_of(self, model, data, threshold)

        def refit(inl, model):
            return self.refit(data[inl], initial=model)

        return inliers, refit

    def refine(self, model, data: np.ndarray, threshold: float):
        """The space's one refinement route: ``(model, inliers)`` after local optimisation.

        The default refits on the inliers (:func:`~clap_unified.refine.refit_on_inliers`).
        """
        return refit_on_inliers(self, model, data, threshold)

    def hough_grid(self):
        """``(coordinates, periods)`` for the randomized Hough grid, or ``None`` (log chart)."""
        return None

    def default_cell_size(self, data: np.ndarray):
        """Randomized Hough cell edge when the user gives none: twice the default threshold."""
        return 2.0 * self.default_threshold(data)
