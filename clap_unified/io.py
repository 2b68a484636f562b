"""Reading user data files and command-line values with clear errors.

Every reader refuses, with a ``ValueError`` naming the file and the reason, what is not a
regular readable file (a folder, a device, a pipe: reading one could hang), a file larger
than :data:`MAX_FILE_BYTES`, and more rows or items than its limit: the command line answers
absurd inputs within seconds instead of running for minutes.
"""

from __future__ import annotations

import argparse
import csv
import json
import math
from pathlib import Path

import numpy as np

__all__ = ["MAX_FILE_BYTES", "MAX_HYPOTHESES", "MAX_ITEMS", "MAX_MAGNITUDE", "MAX_ROWS",
           "MAX_WORK", "check_budget", "check_input_file",
           "float_option", "int_option", "read_json_list", "read_points_csv",
           "read_typed_points"]

#: Input files larger than this (bytes) are refused.
MAX_FILE_BYTES = 256 * 2**20
#: CSV rows at most (:func:`read_points_csv`).
MAX_ROWS = 1_000_000
#: JSON list items at most (:func:`read_json_list`).
MAX_ITEMS = 100_000
#: Largest magnitude of a number read from a file: beyond it, squares and products of
#: coordinates overflow double precision.
MAX_MAGNITUDE = 1e150


def check_input_file(path, what: str = "") -> Path:
    """``path`` as a ``Path`` when it is a regular file of at most :data:`MAX_FILE_BYTES`.

    Raises
    ------
    ValueError
        Naming the file: an empty path, missing, a folder or another non-regular file, too
        large.

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     try:
    ...         check_input_file(d, "map")
    ...     except ValueError as exc:
    ...         print(str(exc).split(": ", 1)[1])
    is a folder; expected the map file
    """
    kind = f"{what} file" if what else "file"
    if not str(path):  # Path("") is ".", the current folder
        raise ValueError(f"'': an empty path; expected the {kind}")
    path = Path(path)
    if not path.exists():
        raise ValueError(f"{path}: no such {kind}")
    if path.is_dir():
        raise ValueError(f"{path}: is a folder; expected the {kind}")
    if not path.is_file():
        raise ValueError(f"{path}: not a regular file")
    size = path.stat().st_size
    if size > MAX_FILE_BYTES:
        raise ValueError(f"{path}: too large ({size / 2**20:.0f} MiB; at most "
                         f"{MAX_FILE_BYTES // 2**20} MiB)")
    return path


def _read_text(path: Path) -> str:
    try:
        return path.read_text(encoding="utf-8-sig")  # a byte-order mark (Excel) is dropped
    except (OSError, UnicodeDecodeError) as exc:
        raise ValueError(f"{path}: cannot read ({exc})") from None


def int_option(minimum: int = 0, maximum: int | None = 2**63 - 1):
    """An argparse ``type=``: a whole number from ``minimum`` to ``maximum``.

    argparse names the option in the message (``argument --seed: expected ...``).

    Examples
    --------
    >>> int_option(1, 100)("7")
    7
    >>> int_option(1, 100)("1000")
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: expected at most 100, got 1000
    """
    def convert(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
        if value < minimum:
            raise argparse.ArgumentTypeError(f"expected at least {minimum}, got {value}")
        if maximum is not None and value > maximum:
            raise argparse.ArgumentTypeError(f"expected at most {maximum}, got {value}")
        return value

    convert.__name__ = "whole number"
    return convert


def float_option(low: float = 0.0, high: float = math.inf, *, closed: bool = False):
    """An argparse ``type=``: a finite number above ``low`` (at least, with ``closed``) and at
    most ``high``.

    Examples
    --------
    >>> float_option()("0.5")
    0.5
    >>> float_option()("nan")
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: expected a finite number above 0.0, got 'nan'
    """
    where = f"{'at least' if closed else 'above'} {low}" + \
        ("" if math.isinf(high) else f" and at most {high}")

    def convert(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            value = math.nan
        if not (math.isfinite(value) and (value >= low if closed else value > low)
                and value <= high):
            raise argparse.ArgumentTypeError(f"expected a finite number {where}, got {text!r}")
        return value

    convert.__name__ = "number"
    return convert


def read_points_csv(path, *, columns: int = 2, min_rows: int = 1, max_rows: int = MAX_ROWS,
                    what: str = "") -> np.ndarray:
    """Read a CSV of numeric rows (``x,y``), with or without a header line.

    Parameters
    ----------
    path : str or Path
    columns : int
        Values per row.
    min_rows, max_rows : int
        How many rows the file must have.
    what : str
        What the file is (``"POINTS.csv"``), for the messages.

    Raises
    ------
    ValueError
        The message names the file and, for bad values, the line: missing file, a folder,
        wrong column count, non-numeric or non-finite values, magnitudes beyond
        :data:`MAX_MAGNITUDE`, too few or too many rows.

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
    path = check_input_file(path, what)
    text = _read_text(path)
    rows = []
    try:
        for lineno, row in enumerate(csv.reader(text.splitlines()), start=1):
            _add_row(rows, row, lineno, path, columns, max_rows)
    except csv.Error as exc:
        raise ValueError(f"{path}: not a CSV file ({exc})") from None
    if not rows and min_rows > 0:
        raise ValueError(f"{path}: no data: expected rows of {columns} comma-separated "
                         "numbers")
    if len(rows) < min_rows:
        raise ValueError(f"{path}: need at least {min_rows} rows of {columns} numbers, "
                         f"got {len(rows)}")
    return np.array(rows, dtype=float).reshape(-1, columns)


def _add_row(rows: list, row: list, lineno: int, path: Path, columns: int, max_rows: int):
    """Append the numbers of one CSV row to ``rows`` (blank lines and a header are skipped)."""
    if not row or all(not c.strip() for c in row):
        return
    if len(row) != columns:
        raise ValueError(f"{path}: line {lineno}: expected {columns} values, got {len(row)}"
                         + _separator_hint(row, columns))
    try:
        values = [float(c) for c in row]
    except ValueError:
        if lineno == 1 and not rows:
            return  # header
        raise ValueError(f"{path}: line {lineno}: non-numeric value in "
                         f"{_short(row)}") from None
    if not all(math.isfinite(v) for v in values):
        raise ValueError(f"{path}: line {lineno}: non-finite value (NaN or inf) in "
                         f"{_short(row)}")
    if any(abs(v) > MAX_MAGNITUDE for v in values):
        raise ValueError(f"{path}: line {lineno}: value beyond +-{MAX_MAGNITUDE:.0e} in "
                         f"{_short(row)}")
    if len(rows) >= max_rows:
        raise ValueError(f"{path}: more than {max_rows} rows")
    rows.append(values)


#: Separators other than the comma that a points file is often written with, by name.
_OTHER_SEPARATORS = ((";", "semicolons"), ("\t", "tabs"), ("|", "vertical bars"))


def _separator_hint(row: list, columns: int) -> str:
    """A hint for a row that holds one value where ``columns`` were expected: the separator
    the file seems to use instead of the comma ("" when there is none to name).

    Examples
    --------
    >>> _separator_hint(["1.0;2.0"], 2)
    "; the values seem to be separated by semicolons (';'): write them comma-separated, as 'x,y'"
    >>> _separator_hint(["1.0 2.0"], 2)
    "; the values seem to be separated by spaces: write them comma-separated, as 'x,y'"
    >>> _separator_hint(["1", "2", "3"], 2)
    ''
    """
    if len(row) != 1 or columns < 2:
        return ""
    cell = row[0].strip()
    example = "x,y" if columns == 2 else ",".join(f"v{i + 1}" for i in range(columns))
    advice = f": write them comma-separated, as {example!r}"
    for sep, name in _OTHER_SEPARATORS:
        if sep in cell:
            return f"; the values seem to be separated by {name} ({sep!r}){advice}"
    if len(cell.split()) > 1:
        return f"; the values seem to be separated by spaces{advice}"
    return ""


def _short(value, limit: int = 80) -> str:
    text = repr(value)
    return text if len(text) <= limit else text[:limit - 3] + "..."


def read_json_list(path, *, what: str = "", item: str = '{"type", "x", "y"}',
                   max_items: int = MAX_ITEMS) -> list:
    """The JSON list in ``path``, or a ``ValueError`` naming the file and the problem.

    Parameters
    ----------
    path : str or Path
    what : str
        What the file is ("map", "observations"), for the missing-file message.
    item : str
        What each element should be, for the not-a-list message.
    max_items : int
        Longer lists are refused.

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
    path = check_input_file(path, what)
    text = _read_text(path)
    try:
        doc = json.loads(text)
    except RecursionError:
        raise ValueError(f"{path}: not valid JSON (nested too deeply)") from None
    except json.JSONDecodeError as exc:
        raise ValueError(f"{path}: not valid JSON ({exc})") from None
    if not isinstance(doc, list):
        raise ValueError(f"{path}: expected a JSON list of {item} objects")
    if len(doc) > max_items:
        raise ValueError(f"{path}: {len(doc)} items, at most {max_items}")
    return doc


def read_typed_points(path, coords: str = "xy", *, what: str = "", max_items: int = MAX_ITEMS,
                      types=None) -> tuple[list[str], np.ndarray]:
    """Types and coordinates from a JSON list of ``{"type", "x", "y"[, "z"]}`` objects.

    Strict: ``type`` a non-empty string, each coordinate a JSON number (not a string, not
    ``true``), finite and within :data:`MAX_MAGNITUDE`; other keys are ignored.

    Parameters
    ----------
    path : str or Path
    coords : str
        The coordinate keys, ``"xy"`` or ``"xyz"``.
    what : str
        What the file is (``"observations"``, ``"map"``), for the messages.
    max_items : int
        Longer lists are refused.
    types : sequence of str, optional
        The known types: another is refused.

    Returns
    -------
    types : list of str
    positions : ndarray of shape (N, len(coords))

    Raises
    ------
    ValueError
        Naming the file and, for a bad entry, its index (``entry 3``) and key.

    Examples
    --------
    >>> import tempfile, os
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = os.path.join(d, "obs.json")
    ...     with open(p, "w") as f:
    ...         _ = f.write('[{"type": "L", "x": 1, "y": "2"}]')
    ...     try:
    ...         read_typed_points(p)
    ...     except ValueError as exc:
    ...         print(str(exc).split(": ", 1)[1])
    entry 0: "y" must be a number, got '2'
    """
    item = "{" + ", ".join(f'"{k}"' for k in ("type", *coords)) + "}"
    path = Path(path)
    doc = read_json_list(path, what=what, item=item, max_items=max_items)
    kinds, rows = [], []
    for i, entry in enumerate(doc):
        if not isinstance(entry, dict):
            raise ValueError(f"{path}: entry {i}: expected a {item} object, got "
                             f"{_short(entry)}")
        missing = [k for k in ("type", *coords) if k not in entry]
        if missing:
            raise ValueError(f"{path}: entry {i}: missing " + ", ".join(f'"{k}"' for k in missing)
                             + f" (expected a {item} object)")
        kind = entry["type"]
        if not isinstance(kind, str) or not kind:
            raise ValueError(f"{path}: entry {i}: \"type\" must be a non-empty string, got "
                             f"{_short(kind)}")
        if types is not None and kind not in types:
            raise ValueError(f"{path}: entry {i}: unknown type {kind!r}; expected one of "
                             f"{list(types)}")
        row = []
        for k in coords:
            v = entry[k]
            if isinstance(v, bool) or not isinstance(v, int | float):
                raise ValueError(f"{path}: entry {i}: \"{k}\" must be a number, got "
                                 f"{_short(v)}")
            v = float(v) if abs(v) <= MAX_MAGNITUDE else math.inf  # int beyond float: inf
            if not math.isfinite(v):
                raise ValueError(f"{path}: entry {i}: \"{k}\" must be finite and within "
                                 f"+-{MAX_MAGNITUDE:.0e}, got {_short(entry.get(k))}")
            row.append(v)
        kinds.append(kind)
        rows.append(row)
    return kinds, np.array(rows, dtype=float).reshape(-1, len(coords))


#: ``--hypotheses`` at most (``bench/bench_cli_limits.py`` times the commands at the limits).
MAX_HYPOTHESES = 1_000_000
#: ``--hypotheses`` times the number of data at most (RANSAC scores every hypothesis on every
#: datum; ``bench/bench_cli_limits.py`` times the commands at the limits).
MAX_WORK = 200_000_000


def check_budget(method: str, n_hypotheses: int, n_data: int) -> None:
    """Refuse a budget that would run for minutes or exhaust memory, before any work.

    Raises
    ------
    ValueError
        Naming ``--hypotheses``, the limit and why.
    """
    if n_hypotheses * n_data > MAX_WORK:
        raise ValueError(f"--hypotheses: {n_hypotheses} hypotheses on {n_data} data exceed "
                         f"the limit of {MAX_WORK:.0e} hypothesis-datum pairs; use fewer "
                         "hypotheses or fewer data")
