"""Command line: ``clap-unified <command> ...`` (also ``python -m clap_unified``).

Every command prints one JSON object on standard output (:data:`OUTPUT`) and exits with one
of three statuses (:data:`EXIT_STATUS`, shown in every command's ``--help``; 130 when
interrupted, 74 when the result cannot be written, 141 when a pipe closed standard output):

* 0: success;
* 1: the estimate failed; the JSON has ``"success": false`` and a ``reason``;
* 2: bad input (a missing, unreadable or malformed file, a bad option value, a size beyond
  the command's limits); one line on standard error names the argument and the reason,
  nothing is printed on standard output and no output file is written.

Absurd sizes are refused before any work (:data:`~clap_unified.io.MAX_HYPOTHESES`,
:data:`~clap_unified.io.MAX_WORK`; the
readers' limits are in
:mod:`clap_unified.io`). While a command runs, a progress bar on standard error names its
stage; it is off with ``--quiet`` or when standard error is not a terminal.

Commands live next to the code they drive; each module in :data:`COMMANDS` provides
``register(subparsers)``, which adds its parser and sets ``run=callable(args) -> dict`` as a
default. ``run`` may call ``args.progress.stage(name)`` as it goes.
"""

from __future__ import annotations

import argparse
import importlib
import json
import os
import sys
import textwrap

from . import __version__
from .fitting import fit_line
from .io import (
    MAX_HYPOTHESES,
    MAX_ROWS,
    MAX_WORK,
    check_budget,
    float_option,
    int_option,
    read_points_csv,
)
from .registry import strategy_names
from .result import ConsensusResult
from .spaces import LineSpace

__all__ = ["COMMANDS", "EXIT_BAD_INPUT", "EXIT_FAILED", "EXIT_OK", "EXIT_STATUS", "OUTPUT",
           "build_parser", "main"]

#: Modules that add commands (each has ``register(subparsers)``).
COMMANDS = [
    "clap_unified.cli",
    "clap_unified.localization.cli",
    "clap_unified.localization.cli3d",
    "clap_unified.imaging.cli",
    "clap_unified.segment_cli",
    "clap_unified.reproduce.cli",
]

#: Exit statuses, the same for every command.
EXIT_OK, EXIT_FAILED, EXIT_BAD_INPUT = 0, 1, 2
#: The result could not be written (a full disk); a closed pipe on standard output.
EXIT_WRITE, EXIT_PIPE = 74, 141

#: What the estimating commands print, as their ``--help`` shows it.
OUTPUT = """\
output:
  one JSON object on standard output: method, success, reason, model, inliers, data,
  threshold, score, clusters (each with model, support, spread), seconds, plus the
  command's own keys."""

#: The exit-status convention, as every command's ``--help`` shows it.
EXIT_STATUS = """\
exit status:
  0    success
  1    the estimate failed: the JSON has "success": false and a "reason"
  2    bad input (missing, unreadable or malformed file, bad option value, size beyond the
       limits): one line on standard error names the argument and the reason; nothing on
       standard output, no output file written
  74   the result could not be written to standard output (e.g. a full disk)
  130  interrupted (Ctrl-C)
  141  standard output was closed by its reader (a pipe), nothing more is written

A progress bar on standard error names the running stage (off with --quiet or when standard
error is not a terminal)."""

#: Commands whose output is not the common JSON form (their description or their own
#: ``output:`` epilog says what it is).
_OWN_OUTPUT = {"clap-unified reproduce"}



class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, status 2
        self.exit(EXIT_BAD_INPUT, f"{self.prog}: error: {message}\n")


class _Progress:
    """The stages of one command as a tqdm bar on standard error (disabled: no output).

    The bar names the running stage and its elapsed time, redrawn twice a second by a
    background thread, so a long stage shows that the command is alive.
    """

    def __init__(self, command: str, enabled: bool):
        self.command, self.enabled, self._bar = command, enabled, None
        self._stop = None

    def stage(self, name: str) -> None:
        """Show that the command has reached stage ``name``."""
        if not self.enabled:
            return
        if self._bar is None:
            import threading

            from tqdm import tqdm

            self._bar = tqdm(desc=self.command, file=sys.stderr, leave=False, unit="stage",
                             bar_format="{desc} [{elapsed}]")
            self._stop = threading.Event()
            threading.Thread(target=self._tick, daemon=True).start()
        self._bar.update(1)
        self._bar.set_description_str(f"{self.command}: {name}", refresh=True)  # while it runs

    def _tick(self) -> None:
        bar, stop = self._bar, self._stop
        while not stop.wait(0.5):
            bar.refresh()

    def close(self) -> None:
        if self._bar is not None:
            self._stop.set()
            self._bar.close()
            self._bar = None


def register(sub) -> None:
    """Add ``fit line``."""
    fit = sub.add_parser("fit", help="fit a model to data (line, homography)",
                         description="Fit a model to the data of a CSV file.")
    kinds = fit.add_subparsers(dest="kind", required=True, parser_class=_Parser,
                               metavar="{line,homography}")
    line = kinds.add_parser(
        "line", help="fit a 2D line to POINTS.csv (rows x,y)",
        description="Fit a 2D line a*x + b*y = c (unit normal (a, b)) to the points of "
                    "POINTS.csv. The JSON's model is {\"normal\": [a, b], \"offset\": c}.")
    line.add_argument("points", metavar="POINTS.csv",
                      help=f"CSV file, one point per row: x,y (header line optional; finite "
                           f"numbers; at most {MAX_ROWS} rows)")
    line.add_argument("--method", choices=list(strategy_names(LineSpace())), default="clap",
                      help="consensus strategy (default clap)")
    line.add_argument("--seed", type=int_option(), default=0, help="random seed (default 0)")
    line.add_argument("--threshold", type=float_option(), default=None,
                      help="inlier distance in data units (default 2%% of the data radius)")
    line.add_argument("--hypotheses", type=int_option(1, MAX_HYPOTHESES), default=1000,
                      metavar="H",
                      help=f"hypotheses (CLAP) or trials (RANSAC); default 1000, at most "
                           f"{MAX_HYPOTHESES}, and hypotheses x points at most {MAX_WORK:.0e}")
    line.set_defaults(run=_fit_line)
    from .imaging.cli import add_fit_homography

    add_fit_homography(kinds)


def _leaves(parser: argparse.ArgumentParser):
    """Every parser that runs a command (no sub-commands of its own)."""
    subs = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    if not subs:
        yield parser
    for action in subs:
        for child in dict.fromkeys(action.choices.values()):
            yield from _leaves(child)


def build_parser() -> argparse.ArgumentParser:
    """The ``clap-unified`` parser with every command (the CLI reference is built from it).

    Every command's parser has a description, a help text for each option and an epilog
    with the output and the exit statuses (:data:`OUTPUT`, :data:`EXIT_STATUS`).

    Examples
    --------
    >>> build_parser().parse_args(["fit", "line", "p.csv", "--hypotheses", "50"]).hypotheses
    50
    """
    p = _Parser(prog="clap-unified",
                description="Robust fitting by consensus: Hough, RANSAC and CLAP. Run\n"
                            "'clap-unified COMMAND --help' for a command's inputs and options.",
                epilog=f"{OUTPUT}\n\n{EXIT_STATUS}",
                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser,
                           metavar="COMMAND")
    for name in COMMANDS:
        importlib.import_module(name).register(sub)
    for leaf in _leaves(p):
        # the epilog keeps its layout, so the description is wrapped here
        leaf.formatter_class = argparse.RawDescriptionHelpFormatter
        if leaf.description and "\n" not in leaf.description:
            leaf.description = textwrap.fill(leaf.description, 92)
        own = leaf.prog in _OWN_OUTPUT or (leaf.epilog or "").startswith("output:")
        leaf.epilog = "\n\n".join(filter(None, [leaf.epilog, None if own else OUTPUT,
                                                 EXIT_STATUS]))
        if "--quiet" not in leaf._option_string_actions:
            leaf.add_argument("-q", "--quiet", action="store_true",
                              help="no progress bar on standard error")
    return p


def _fit_line(args) -> dict:
    args.progress.stage("reading points")
    points = read_points_csv(args.points, columns=2, min_rows=1, max_rows=MAX_ROWS)
    check_budget(args.method, args.hypotheses, len(points))
    if len(points) < LineSpace.min_samples:
        return ConsensusResult.failure(
            args.method, f"need at least {LineSpace.min_samples} points, got {len(points)}",
            n_data=len(points), space=LineSpace(), threshold=args.threshold).to_dict()
    args.progress.stage(f"fitting ({args.method}, {args.hypotheses} hypotheses)")
    return fit_line(points, args.method, n_hypotheses=args.hypotheses,
                    threshold=args.threshold, rng=args.seed).to_dict()


def _is_number_list(text: str) -> bool:
    """A value starting with ``-`` whose first comma-separated item is a number (``-1.2,3,0``;
    also ``-1.2,3,`` or ``-1,x``, which the option's own check then refuses, by name)."""
    if not text.startswith("-") or text == "-":
        return False
    try:
        float(text.split(",")[0])
    except ValueError:
        return False
    return True


def _join_negative_values(argv: list[str], options: set[str]) -> list[str]:
    """``--prior -1.2,3.4,0.1`` as ``--prior=-1.2,3.4,0.1``: argparse takes a value that starts
    with ``-`` (a pose on the negative half of the field) for an option otherwise.
    ``options`` are the option strings that take a value.

    Examples
    --------
    >>> _join_negative_values(["--prior", "-1.2,3.4,0.1", "--seed", "2"], {"--prior", "--seed"})
    ['--prior=-1.2,3.4,0.1', '--seed', '2']
    """
    out: list[str] = []
    for arg in argv:
        if out and out[-1] in options and _is_number_list(arg):
            out[-1] = f"{out[-1]}={arg}"
        else:
            out.append(arg)
    return out


def _value_options(parser) -> set[str]:
    return {s for leaf in _leaves(parser) for a in leaf._actions if a.nargs != 0
            for s in a.option_strings if s.startswith("--")}


def _one_line(exc: BaseException) -> str:
    return " ".join(str(exc).split()) or type(exc).__name__


def main(argv=None) -> int:
    """Run the ``clap-unified`` command on ``argv`` (default ``sys.argv[1:]``).

    Returns
    -------
    int
        The exit status (:data:`EXIT_STATUS`): also for ``--help`` and ``--version`` (0) and
        for options argparse refuses (2); nothing raises ``SystemExit``.
    """
    argv = sys.argv[1:] if argv is None else [str(a) for a in argv]
    parser = build_parser()
    try:
        args, unknown = parser.parse_known_args(_join_negative_values(argv, _value_options(parser)))
        command = " ".join(filter(None, [args.command, getattr(args, "kind", None)]))
        if unknown:  # said by the command's parser, which names the command
            leaf = next(p for p in _leaves(parser) if p.prog == f"clap-unified {command}")
            leaf.error(f"unrecognized arguments: {' '.join(unknown)}")
    except SystemExit as exc:  # --help, --version, or a usage error (already printed)
        return exc.code if isinstance(exc.code, int) else EXIT_BAD_INPUT
    quiet = args.quiet or getattr(args, "no_progress", False)
    args.progress = _Progress(command, enabled=not quiet and sys.stderr.isatty())
    try:
        out = args.run(args)
    except (ValueError, OSError, MemoryError) as exc:
        args.progress.close()
        reason = "out of memory; use smaller inputs" if isinstance(exc, MemoryError) else \
            _one_line(exc)
        print(f"clap-unified {command}: error: {reason}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except KeyboardInterrupt:  # Ctrl-C: no traceback, the shell's status for SIGINT
        args.progress.close()
        print(f"clap-unified {command}: interrupted", file=sys.stderr)
        return 130
    args.progress.close()
    try:
        print(json.dumps(out), flush=True)
    except BrokenPipeError:  # the reader went away (`... | head`): nothing more to say
        _silence_stdout()
        return EXIT_PIPE
    except OSError as exc:  # e.g. a full disk
        _silence_stdout()
        print(f"clap-unified {command}: error: cannot write the result ({_one_line(exc)})",
              file=sys.stderr)
        return EXIT_WRITE
    return EXIT_OK if out.get("success", True) else EXIT_FAILED


def _silence_stdout() -> None:
    """Point standard output at /dev/null, so that the interpreter's last flush cannot fail."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError, AttributeError):  # no file descriptor (captured output)
        pass


if __name__ == "__main__":
    sys.exit(main())
