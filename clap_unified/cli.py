"""Command line: ``clap-unified <command> ...``.

Every command prints one JSON object on standard output and exits with
status 0 on success, 1 when the estimate failed (the JSON says why) and 2
for bad input (one line on standard error naming the problem).

Commands live next to the code they drive; each module in :data:`COMMANDS`
provides ``register(subparsers)``, which adds its parser and sets
``run=callable(args) -> dict`` as a default.
"""

from __future__ import annotations

import argparse
import importlib
import json
import re
import sys

from .fitting import fit_line
from .io import read_points_csv
from .registry import strategy_names
from .spaces import LineSpace

__all__ = ["main", "COMMANDS"]

#: Modules that add commands (each has ``register(subparsers)``).
COMMANDS = [
    "clap_unified.cli",
    "clap_unified.localization.cli",
    "clap_unified.localization.cli3d",
    "clap_unified.imaging.cli",
    "clap_unified.reproduce.cli",
]


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, status 2
        self.exit(2, f"{self.prog}: error: {message}\n")


def register(sub) -> None:
    """Add ``fit line``."""
    fit = sub.add_parser("fit", help="fit a model to data")
    kinds = fit.add_subparsers(dest="kind", required=True, parser_class=_Parser)
    line = kinds.add_parser("line", help="fit a 2D line to POINTS.csv (rows x,y)")
    line.add_argument("points", help="CSV file, one point per row: x,y (header optional)")
    line.add_argument("--method", choices=list(strategy_names(LineSpace())), default="clap",
                      help="consensus strategy (default clap)")
    line.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    line.add_argument("--threshold", type=float, default=None,
                      help="inlier distance in data units (default 2%% of the data radius)")
    line.add_argument("--hypotheses", type=int, default=1000,
                      help="hypotheses (CLAP) or trials (RANSAC); default 1000")
    line.set_defaults(run=_fit_line)
    from .imaging.cli import add_fit_homography

    add_fit_homography(kinds)


def _parser() -> argparse.ArgumentParser:
    p = _Parser(prog="clap-unified",
                description="Robust fitting by consensus: Hough, RANSAC and CLAP.")
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)
    for name in COMMANDS:
        importlib.import_module(name).register(sub)
    return p


def _fit_line(args) -> dict:
    points = read_points_csv(args.points, columns=2, min_rows=2)
    return fit_line(points, args.method, n_hypotheses=args.hypotheses,
                    threshold=args.threshold, rng=args.seed).to_dict()


def _join_negative_values(argv: list[str]) -> list[str]:
    """``--prior -3,-1,0.2`` as ``--prior=-3,-1,0.2``: argparse takes a value that starts with
    ``-`` (a pose on the negative half of the field) for an option otherwise."""
    out = []
    for arg in argv:
        if out and out[-1].startswith("--") and "=" not in out[-1] and _NUMBERS.match(arg):
            out[-1] = f"{out[-1]}={arg}"
        else:
            out.append(arg)
    return out


#: A comma-separated list of numbers starting with a minus sign.
_NUMBERS = re.compile(r"^-[0-9.]+([eE][-+]?[0-9]+)?(,[-+]?[0-9.]+([eE][-+]?[0-9]+)?)+$")


def main(argv=None) -> int:
    """Entry point of the ``clap-unified`` command."""
    argv = sys.argv[1:] if argv is None else list(argv)
    args = _parser().parse_args(_join_negative_values(argv))
    try:
        out = args.run(args)
    except (ValueError, OSError) as exc:
        print(f"clap-unified: error: {exc}", file=sys.stderr)
        return 2
    print(json.dumps(out))
    return 0 if out.get("success", True) else 1


if __name__ == "__main__":
    sys.exit(main())
