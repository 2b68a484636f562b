"""Reading user data files with clear errors."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np

__all__ = ["read_json_list", "read_points_csv"]


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
    if not path.exists():
        raise ValueError(f"{path}: no such file")
    if not path.is_file():
        raise ValueError(f"{path}: not a regular file")
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


def read_json_list(path, *, what: str = "", item: str = '{"type", "x", "y"}') -> list:
    """The JSON list in ``path``, or a ``ValueError`` naming the file and the problem.

    Parameters
    ----------
    path : str or Path
    what : str
        What the file is ("map", "observations"), for the missing-file message.
    item : str
        What each element should be, for the not-a-list message.

    Examples
    --------
    >>> import tempfile, os
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = os.path.join(d, "obs.json")
    ...     with open(p, "w") as f:
    ...         _ = f.write('{"type": "L"}')
    ...     try:
    ...         read_json_list(p)
    ...     except ValueError as exc:
    ...         print(str(exc).split(": ", 1)[1])
    expected a JSON list of {"type", "x", "y"} objects
    """
    path = Path(path)
    try:
        doc = json.loads(path.read_text())
    except FileNotFoundError:
        raise ValueError(f"{path}: no such {what + ' ' if what else ''}file") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise ValueError(f"{path}: cannot read ({exc})") from None
    except json.JSONDecodeError as exc:
        raise ValueError(f"{path}: not valid JSON ({exc})") from None
    if not isinstance(doc, list):
        raise ValueError(f"{path}: expected a JSON list of {item} objects")
    return doc
