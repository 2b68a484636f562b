"""The one switch and decorator of the library's compiled kernels (numba).

A few hot loops (the homography polish, the 4-point solver on thousands of
samples, the anchor-transfer embedding of thousands of candidates) have a
numba kernel beside their numpy code. The numpy code is the reference: every
kernel is tested against it (``tests/test_homography_compiled.py``), and it
runs wherever numba cannot be imported.

:data:`AVAILABLE` says whether the kernels are used. It is read at each call,
so setting it to False runs the numpy reference everywhere (the benchmarks
time both paths that way). The first call of a kernel compiles it; the
machine code is cached beside the module, compiled for the CPU
it runs on, without ``fastmath``: IEEE arithmetic, the same on every machine.

Examples
--------
>>> from clap_unified import _compiled
>>> isinstance(_compiled.AVAILABLE, bool)
True
"""

from __future__ import annotations

try:
    from numba import njit
except ImportError:  # pragma: no cover - numba is a dependency; the numpy paths remain
    njit = None

__all__ = ["AVAILABLE", "jit"]

#: True when numba is importable and the compiled kernels are used; False runs numpy.
AVAILABLE = njit is not None


def jit(fn):
    """Compile ``fn`` with numba (cached, no GIL, numpy's error model); ``fn`` without numba."""
    return njit(cache=True, nogil=True, error_model="numpy")(fn) if njit is not None else fn
