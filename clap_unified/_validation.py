"""Input checks shared by the whole library.

Every public function validates its arguments here so that bad input raises a
``ValueError`` naming the argument, instead of failing deep inside NumPy.
"""

from __future__ import annotations

import numbers
from dataclasses import dataclass

import numpy as np

__all__ = [
    "Checked",
    "as_generator",
    "check_array",
    "check_points",
    "check_positive",
    "check_fraction",
    "check_int",
    "check_choice",
    "unwrap_checked",
]


@dataclass(frozen=True)
class Checked:
    """Data a space's ``check_data`` has already returned, handed down unchecked.

    The entry a user calls (``fit``, ``estimate_homography``, ``fit_line``, a command)
    checks the data once and wraps the result; the code it calls with the data
    (``fit`` itself, a preset building its space with ``HomographySpace.for_data``)
    unwraps it instead of checking it again (:func:`unwrap_checked`). Internal: a
    user passes plain arrays.

    Examples
    --------
    >>> data = check_points([[0.0, 1.0], [2.0, 3.0]], "points")
    >>> unwrap_checked(Checked(data), lambda d: 1 / 0) is data
    True
    """

    data: np.ndarray


def unwrap_checked(data, check):
    """``data.data`` when ``data`` is :class:`Checked`, else ``check(data)``.

    Examples
    --------
    >>> unwrap_checked([[0, 1]], lambda d: check_points(d, "points")).tolist()
    [[0.0, 1.0]]
    """
    return data.data if isinstance(data, Checked) else check(data)


def as_generator(rng=None) -> np.random.Generator:
    """Return a :class:`numpy.random.Generator` from ``rng``.

    Parameters
    ----------
    rng : None, int or numpy.random.Generator
        ``None`` gives a fresh unseeded generator, an int seeds one, a
        ``Generator`` is returned unchanged. Global NumPy state is never used.

    Examples
    --------
    >>> g = as_generator(0)
    >>> float(g.random()) == float(as_generator(0).random())
    True
    """
    if rng is None:
        return np.random.default_rng()
    if isinstance(rng, np.random.Generator):
        return rng
    if isinstance(rng, numbers.Integral) and not isinstance(rng, bool):
        if rng < 0:
            raise ValueError(f"rng: a seed must be non-negative, got {rng}")
        return np.random.default_rng(int(rng))
    raise ValueError(
        "rng: expected None, a non-negative int or a numpy.random.Generator, "
        f"got {type(rng).__name__}"
    )


def check_array(value, name: str, *, shape: tuple | None = None, finite: bool = True,
                dtype=float) -> np.ndarray:
    """Convert ``value`` to an array and check its shape and finiteness.

    ``shape`` may contain ``None`` (any size) and may start with ``...``
    (any number of leading batch axes).
    """
    try:
        arr = np.asarray(value, dtype=dtype)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name}: expected a numeric array, could not convert ({exc})") from None
    if shape is not None:
        tail = shape[1:] if shape and shape[0] is Ellipsis else shape
        lead_ok = shape and shape[0] is Ellipsis
        ok = arr.ndim >= len(tail) if lead_ok else arr.ndim == len(tail)
        if ok and tail:
            got = arr.shape[arr.ndim - len(tail):]
            ok = all(want is None or want == g for want, g in zip(tail, got, strict=True))
        if not ok:
            want = ", ".join("..." if s is Ellipsis else ("N" if s is None else str(s))
                             for s in shape)
            raise ValueError(f"{name}: expected shape ({want}), got {arr.shape}")
    # dtype.kind instead of np.issubdtype(arr.dtype, np.number): same test, a hot path
    if finite and arr.dtype.kind in "iufc" and not np.isfinite(arr).all():
        bad = int(np.size(arr) - np.count_nonzero(np.isfinite(arr)))
        raise ValueError(f"{name}: contains {bad} non-finite value(s) (NaN or inf)")
    return arr


def check_points(value, name: str = "points", *, dim: int = 2, min_count: int = 1) -> np.ndarray:
    """Check an ``(N, dim)`` array of finite points with at least ``min_count`` rows."""
    arr = check_array(value, name, shape=(None, dim))
    if arr.shape[0] < min_count:
        raise ValueError(f"{name}: need at least {min_count} points, got {arr.shape[0]}")
    return arr


def check_positive(value, name: str, *, allow_zero: bool = False) -> float:
    """Check a finite positive (or non-negative) scalar."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name}: expected a number, got {value!r}") from None
    if not np.isfinite(v) or v < 0 or (v == 0 and not allow_zero):
        kind = "non-negative" if allow_zero else "positive"
        raise ValueError(f"{name}: expected a finite {kind} number, got {value!r}")
    return v


def check_fraction(value, name: str, *, low: float = 0.0, high: float = 1.0,
                   inclusive: tuple[bool, bool] = (True, False)) -> float:
    """Check a scalar in the interval [low, high) (bounds configurable)."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name}: expected a number, got {value!r}") from None
    lo_ok = v >= low if inclusive[0] else v > low
    hi_ok = v <= high if inclusive[1] else v < high
    if not (np.isfinite(v) and lo_ok and hi_ok):
        lb = "[" if inclusive[0] else "("
        rb = "]" if inclusive[1] else ")"
        raise ValueError(f"{name}: expected a number in {lb}{low}, {high}{rb}, got {value!r}")
    return v


def check_int(value, name: str, *, minimum: int = 0) -> int:
    """Check an integer at least ``minimum``."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise ValueError(f"{name}: expected an integer, got {value!r}")
    if value < minimum:
        raise ValueError(f"{name}: expected an integer >= {minimum}, got {value}")
    return int(value)


def check_choice(value, name: str, choices) -> str:
    """Check that ``value`` is one of ``choices``."""
    if value not in choices:
        raise ValueError(f"{name}: expected one of {sorted(choices)}, got {value!r}")
    return value
