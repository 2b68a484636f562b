"""What an estimator may see, kept apart from what scores it.

Every loader and every scene generator of the package returns a frozen object
with two parts:

* ``input``: what the public data set defines as the estimator's input (the
  tentative matches, the detections, the noisy points) and nothing else;
* ``truth``: evaluation data (ground-truth models and poses, inlier labels,
  validation points, noise-free copies), for scoring only.

Both parts are frozen dataclasses whose arrays are read-only copies, so an
experiment can neither pass one for the other by accident nor edit either in
place. :func:`readonly` and :func:`freeze_arrays` are the two helpers the
loaders use to get there.

Examples
--------
>>> from dataclasses import dataclass
>>> import numpy as np
>>> @dataclass(frozen=True)
... class Points:
...     points: np.ndarray
...     def __post_init__(self):
...         freeze_arrays(self)
>>> p = Points(np.zeros((2, 2)))
>>> p.points.flags.writeable
False
"""

from __future__ import annotations

import dataclasses

import numpy as np

__all__ = ["ReadOnlyDict", "freeze_arrays", "readonly"]


def readonly(array, dtype=None) -> np.ndarray:
    """A read-only copy of ``array`` (``None`` stays ``None``).

    Examples
    --------
    >>> a = readonly([1.0, 2.0])
    >>> a.flags.writeable
    False
    """
    if array is None:
        return None
    out = np.array(array, dtype=dtype, copy=True)
    out.flags.writeable = False
    return out


def freeze_arrays(obj) -> None:
    """Replace every ndarray field of the frozen dataclass ``obj`` by a read-only copy."""
    for f in dataclasses.fields(obj):
        value = getattr(obj, f.name)
        if isinstance(value, np.ndarray):
            object.__setattr__(obj, f.name, readonly(value))


class ReadOnlyDict(dict):
    """A dict that refuses changes (and still pickles, unlike ``MappingProxyType``).

    Examples
    --------
    >>> d = ReadOnlyDict(seconds=0.5)
    >>> d["seconds"] = 1.0
    Traceback (most recent call last):
    ...
    TypeError: read-only: a frozen result's diagnostics cannot change; use result.replace()
    """

    def _refuse(self, *args, **kwargs):
        raise TypeError("read-only: a frozen result's diagnostics cannot change; "
                        "use result.replace()")

    __setitem__ = __delitem__ = _refuse
    clear = pop = popitem = setdefault = update = __ior__ = _refuse

    def __reduce__(self):
        return (ReadOnlyDict, (dict(self),))
