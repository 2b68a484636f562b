"""Reading user data files with clear errors."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

__all__ = ["read_points_csv"]


def read_points_csv(path, *, columns: int = 2, min_rows: int = 1) -> np.ndarray:
    """Read a CSV of numeric rows (``x,y``), with or without a header line.

    Raises
    ------
    ValueError
        The message names the file and, for bad values, the line: missing file,
        wrong column count, non-numeric or non-finite values, too few rows.

    Examples
    --------
    >>> import tempfile, os
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = os.path.join(d, "pts.csv")
    ...     with open(p, "w") as f:
    ...         _ = f.write("x,y\\n0,1\\n2,3\\n")
    ...     read_points_csv(p).tolist()
    [[0.0, 1.0], [2.0, 3.0]]
    """
    path = Path(path)
    if not path.is_file():
        raise ValueError(f"{path}: no such file")
    try:
        text = path.read_text()
    except (OSError, UnicodeDecodeError) as exc:
        raise ValueError(f"{path}: cannot read ({exc})") from None
    rows = []
    for lineno, row in enumerate(csv.reader(text.splitlines()), start=1):
        if not row or all(not c.strip() for c in row):
            continue
        if len(row) != columns:
            raise ValueError(f"{path}: line {lineno}: expected {columns} values, got {len(row)}")
        try:
            values = [float(c) for c in row]
        except ValueError:
            if lineno == 1 and not rows:
                continue  # header
            raise ValueError(f"{path}: line {lineno}: non-numeric value in {row!r}") from None
        if not all(np.isfinite(values)):
            raise ValueError(f"{path}: line {lineno}: non-finite value (NaN or inf) in {row!r}")
        rows.append(values)
    if len(rows) < min_rows:
        raise ValueError(f"{path}: need at least {min_rows} rows of {columns} numbers, "
                         f"got {len(rows)}")
    return np.array(rows, dtype=float)
