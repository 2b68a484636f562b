"""A scikit-image model class as a hypothesis space.

scikit-image's ``ransac(data, model_class, min_samples, residual_threshold,
is_data_valid=, is_model_valid=, model_kwargs=)`` takes any class with a
``from_estimate`` class method (or the older ``estimate`` method) and a
``residuals`` method: ``skimage.measure.CircleModel``, ``EllipseModel``,
``LineModelND``, the ``skimage.transform`` transforms, or a user's own.
:class:`SkimageModelSpace` wraps such a class so that every strategy of this
library runs on it through :func:`~clap_unified.fit`: the minimal solver is
``from_estimate`` on each minimal sample (a failed estimate, or a sample or
model the hooks refuse, is a degenerate sample), the residuals and the refit
are the class's own, and hypotheses are compared on their parameter vectors in
the flat manifold :class:`~clap_unified.geometry.Euclidean` (CLAP's
neighbourhoods, randomized Hough's cells).

scikit-image itself is not a dependency: the module only calls the class it is
given.
"""

from __future__ import annotations

import inspect
import warnings

import numpy as np

from .._validation import check_array, check_int
from ..geometry.euclidean import Euclidean
from ..geometry.lines_nd import canonical_lines_nd
from .base import HypothesisSpace

__all__ = ["SkimageModelSpace"]


def _known(model_class, dim):
    """``(n_params, to_params, from_params)`` for scikit-image's own fit models, else None.

    scikit-image 0.26 gives them named attributes and constructors (``CircleModel(center,
    radius)``); before, a ``params`` tuple set on an instance: both are read and built.
    """
    name = getattr(model_class, "__name__", "")
    fields = {"CircleModel": (3, ("center", "radius"), (slice(0, 2), 2)),
              "EllipseModel": (5, ("center", "axis_lengths", "theta"),
                               (slice(0, 2), slice(2, 4), 4)),
              "LineModelND": (2 * dim, ("origin", "direction"),
                              (slice(0, dim), slice(dim, 2 * dim)))}
    if name not in fields:
        return None
    n, attrs, parts = fields[name]
    new_api = callable(getattr(model_class, "from_estimate", None))

    def to_params(model):
        if new_api:
            values = [getattr(model, a) for a in attrs]
        else:
            values = model.params
        p = np.concatenate([np.ravel(np.asarray(v, dtype=float)) for v in values])
        if name == "LineModelND":
            # canonical: the foot from the coordinate origin and a signed direction, so
            # that equal lines have equal parameters (scikit-image's origin is a mean)
            p = canonical_lines_nd(p.reshape(2, dim)).ravel()
        return p

    def from_params(p):
        values = [p[k] for k in parts]
        if new_api:
            return model_class(*values)
        model = model_class()
        model.params = tuple(values)
        return model

    return n, to_params, from_params


class SkimageModelSpace(HypothesisSpace):
    """Hypotheses from a scikit-image style model class.

    Parameters
    ----------
    model_class : type
        A class with ``from_estimate(*data, **model_kwargs)`` (a class method
        returning a model, falsy on failure) or, the older protocol,
        ``estimate(*data)`` on an instance (returning a bool), and
        ``residuals(*data)`` on a model (one residual per datum).
    min_samples : int
        Data in a minimal sample (scikit-image's ``min_samples``).
    widths : tuple of int, optional
        The column count of each array when the data are several arrays of one
        length (``(2, 2)`` for ``(src, dst)`` of a 2-D transform); the model's
        methods then receive them as separate arguments. Default: one array, of 2
        columns for ``CircleModel`` and ``EllipseModel``, ``dim`` for
        ``LineModelND``, any number otherwise.
    dim : int
        The dimension of the points of ``LineModelND`` (its parameter vector
        has ``2 * dim`` entries). Default 2.
    n_params : int, optional
        Length of a model's parameter vector. Known for ``CircleModel`` (3),
        ``EllipseModel`` (5) and ``LineModelND``; required otherwise.
    to_params, from_params : callable, optional
        A model to its parameter vector, and back. Known for the three fit
        models; for a class whose constructor takes ``matrix=`` (the
        ``skimage.transform`` transforms), the default is ``model.params``
        flattened and ``model_class(matrix=p.reshape(k, k))``.
    is_data_valid : callable, optional
        ``is_data_valid(*sample) -> bool``, called before estimating from a
        minimal sample (as scikit-image's ``ransac``): ``False`` makes the sample
        degenerate.
    is_model_valid : callable, optional
        ``is_model_valid(model, *sample) -> bool``, called on each model from a
        minimal sample, and on the refitted model with its data.
    model_kwargs : dict, optional
        Keyword arguments of every ``from_estimate`` call.
    tangent_weights : array_like of shape (n_params,), optional
        Weights of the parameters in the Euclidean distance between hypotheses
        (units per parameter); default 1 each.

    Examples
    --------
    >>> from skimage.measure import CircleModel
    >>> from clap_unified import fit
    >>> t = np.linspace(0, 2 * np.pi, 60, endpoint=False)
    >>> pts = np.c_[10 + 3 * np.cos(t), 12 + 3 * np.sin(t)]
    >>> pts[::4] = np.random.default_rng(0).uniform(0, 20, (15, 2))
    >>> space = SkimageModelSpace(CircleModel, 3)
    >>> res = fit(space, pts, "clap", threshold=0.01, rng=0, n_hypotheses=300)
    >>> res.model.round(6).tolist(), res.n_inliers
    ([10.0, 12.0, 3.0], 45)
    >>> space.to_model(res.model).radius.round(6)
    np.float64(3.0)
    """

    name = "skimage_model"

    def __init__(self, model_class, min_samples: int, *, widths=None, dim: int = 2,
                 n_params: int | None = None, to_params=None, from_params=None,
                 is_data_valid=None, is_model_valid=None, model_kwargs=None,
                 tangent_weights=None):
        if not isinstance(model_class, type):
            raise ValueError(f"model_class: expected a class, got {type(model_class).__name__}")
        has_from = callable(getattr(model_class, "from_estimate", None))
        if not (has_from or callable(getattr(model_class, "estimate", None))):
            raise ValueError(f"model_class: {model_class.__name__} has neither `from_estimate` "
                             "nor `estimate`")
        if has_from and not isinstance(inspect.getattr_static(model_class, "from_estimate"),
                                       classmethod):
            raise ValueError(f"model_class: {model_class.__name__}.from_estimate must be a "
                             "class method")
        if not callable(getattr(model_class, "residuals", None)):
            raise ValueError(f"model_class: {model_class.__name__} has no `residuals`")
        for name, hook in (("is_data_valid", is_data_valid), ("is_model_valid", is_model_valid),
                           ("to_params", to_params), ("from_params", from_params)):
            if hook is not None and not callable(hook):
                raise ValueError(f"{name}: expected a callable, got {type(hook).__name__}")
        if model_kwargs is not None and not isinstance(model_kwargs, dict):
            raise ValueError(f"model_kwargs: expected a dict, got {type(model_kwargs).__name__}")
        self.model_class = model_class
        self.min_samples = check_int(min_samples, "min_samples", minimum=1)
        dim = check_int(dim, "dim", minimum=1)
        known = _known(model_class, dim)
        if widths is None and known is not None:  # the fit models take points (N, 2 or dim)
            widths = (dim if model_class.__name__ == "LineModelND" else 2,)
        self.widths = None if widths is None else tuple(
            check_int(w, "widths", minimum=1) for w in widths)
        if self.widths is not None and not self.widths:
            raise ValueError("widths: expected at least one array width")
        if n_params is None and known is None:
            raise ValueError(f"n_params: the length of a {model_class.__name__} parameter vector "
                             "is not known; pass it")
        self.n_params = check_int(known[0] if n_params is None else n_params, "n_params",
                                  minimum=1)
        self.model_shape = (self.n_params,)
        if to_params is None:
            to_params = known[1] if known else (lambda m: np.asarray(m.params, float).ravel())
        if from_params is None:
            if known:
                from_params = known[2]
            elif "matrix" in inspect.signature(model_class).parameters:
                k = int(round(np.sqrt(self.n_params)))
                if k * k != self.n_params:
                    raise ValueError(f"n_params: a matrix transform has k*k parameters, got "
                                     f"{self.n_params}")
                from_params = lambda p: model_class(matrix=p.reshape(k, k))  # noqa: E731
            else:
                raise ValueError(f"from_params: cannot rebuild a {model_class.__name__} from "
                                 "its parameters; pass from_params")
        self._to_params, self._from_params = to_params, from_params
        self.is_data_valid, self.is_model_valid = is_data_valid, is_model_valid
        self.model_kwargs = dict(model_kwargs or {})
        self._manifold = Euclidean(self.n_params, tangent_weights)

    def __repr__(self) -> str:
        return f"SkimageModelSpace({self.model_class.__name__}, {self.min_samples})"

    @property
    def manifold(self) -> Euclidean:
        return self._manifold

    # -------------------------------------------------------------- the data
    def check_data(self, data) -> np.ndarray:
        """One ``(N, k)`` array (a 1-D array is one column), or the ``widths`` arrays
        side by side."""
        if self.widths is not None and isinstance(data, (tuple, list)):
            if len(data) != len(self.widths):
                raise ValueError(f"data: expected {len(self.widths)} arrays, got {len(data)}")
            parts = [check_array(d, "data", shape=(None, w))
                     for d, w in zip(data, self.widths, strict=True)]
            if len({len(p) for p in parts}) != 1:
                raise ValueError(f"data: the arrays differ in length: {[len(p) for p in parts]}")
            arr = np.concatenate(parts, axis=1)
        else:
            arr = check_array(data, "data")
            if arr.ndim == 1:
                arr = arr[:, None]
            width = None if self.widths is None else sum(self.widths)
            if arr.ndim != 2 or (width is not None and arr.shape[1] != width):
                raise ValueError(f"data: expected shape (N, {width or 'k'}), got {arr.shape}")
        if len(arr) < self.min_samples:
            raise ValueError(f"data: need at least {self.min_samples} rows, got {len(arr)}")
        return arr

    def split(self, data) -> tuple:
        """The arguments the model's methods take: ``data`` cut into the ``widths`` arrays."""
        if self.widths is None:
            return (data,)
        return tuple(np.split(data, np.cumsum(self.widths)[:-1], axis=1))

    # ------------------------------------------------------------ the models
    def to_model(self, params):
        """The model object of a parameter vector (e.g. ``res.model``)."""
        return self._from_params(np.asarray(params, dtype=float).reshape(self.n_params))

    def estimate(self, data):
        """The class's estimate from ``data`` (checked, as :meth:`check_data` returns),
        or ``None`` when it fails."""
        args = self.split(data)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # a failed estimate is None, not a warning
            if callable(getattr(self.model_class, "from_estimate", None)):
                model = self.model_class.from_estimate(*args, **self.model_kwargs)
                return model if model else None
            model = self.model_class(**self.model_kwargs)
            return model if model.estimate(*args) else None

    def params_of(self, model):
        """The parameter vector of a model object (``None`` when not finite)."""
        p = np.asarray(self._to_params(model), dtype=float).ravel()
        if p.shape != (self.n_params,):
            raise ValueError(f"n_params: a {self.model_class.__name__} has {p.size} parameters, "
                             f"the space was told {self.n_params}")
        return p if np.all(np.isfinite(p)) else None

    def _valid(self, model, args) -> bool:
        return self.is_model_valid is None or bool(self.is_model_valid(model, *args))

    def solve_minimal(self, data, samples):
        models, owner = [], []
        for s, sample in enumerate(np.asarray(samples)):
            args = self.split(data[sample])
            if self.is_data_valid is not None and not self.is_data_valid(*args):
                continue
            model = self.estimate(data[sample])
            if model is None or not self._valid(model, args):
                continue
            p = self.params_of(model)
            if p is not None:
                models.append(p)
                owner.append(s)
        return (np.array(models, dtype=float).reshape(-1, self.n_params),
                np.array(owner, dtype=int))

    def residuals(self, models, data) -> np.ndarray:
        models = np.asarray(models, dtype=float).reshape(-1, self.n_params)
        args = self.split(data)
        out = np.empty((len(models), len(data)))
        for h, p in enumerate(models):
            out[h] = np.abs(np.asarray(self.to_model(p).residuals(*args), dtype=float))
        return out

    def refit(self, data, weights=None, initial=None):
        data = np.asarray(data, dtype=float)
        if weights is not None:
            data = data[np.asarray(weights, dtype=float) > 0]
        if len(data) < self.min_samples:
            return None
        model = self.estimate(data)
        if model is None or not self._valid(model, self.split(data)):
            return None
        return self.params_of(model)

    def model_to_dict(self, model) -> dict:
        return {"class": self.model_class.__name__,
                "params": np.asarray(model, dtype=float).tolist()}
