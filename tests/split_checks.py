"""Checks shared by the per-loader tests: evaluation data never reaches an estimator."""

from __future__ import annotations

import dataclasses

import numpy as np


def assert_rows_disjoint(input_rows, evaluation_rows, *, atol: float = 0.0) -> None:
    """No row of ``evaluation_rows`` occurs (within ``atol``) among ``input_rows``."""
    a = np.asarray(input_rows, dtype=float)
    b = np.asarray(evaluation_rows, dtype=float)
    assert a.ndim == b.ndim == 2 and a.shape[1] == b.shape[1], (a.shape, b.shape)
    if len(a) == 0 or len(b) == 0:
        return
    close = np.all(np.abs(a[:, None, :] - b[None, :, :]) <= atol, axis=2)
    hits = np.argwhere(close)
    assert not len(hits), f"evaluation rows found in the input: {hits[:5].tolist()}"


def assert_split(sample) -> None:
    """``sample`` has a frozen ``input`` and a frozen ``truth`` with read-only arrays."""
    for part in (sample.input, sample.truth):
        assert dataclasses.is_dataclass(part) and part.__dataclass_params__.frozen
        for f in dataclasses.fields(part):
            value = getattr(part, f.name)
            if isinstance(value, np.ndarray):
                assert not value.flags.writeable, f"{type(part).__name__}.{f.name} is writeable"
    assert dataclasses.is_dataclass(sample) and sample.__dataclass_params__.frozen
