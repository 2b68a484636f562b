"""``clap-unified reproduce``: regenerate every experiment, figure and claim of the paper."""

from __future__ import annotations

from pathlib import Path

__all__ = ["MAX_JOBS", "register"]

#: ``--jobs`` at most (each job is a process holding its own copy of the data).
MAX_JOBS = 64


def _jobs(text: str) -> int:
    import argparse

    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected at least 1, got {value}")
    if value > MAX_JOBS:
        raise argparse.ArgumentTypeError(f"expected at most {MAX_JOBS}, got {value}")
    return value


def _names(text: str) -> list[str]:
    """``--only``: comma-separated names, none empty (``a,,b``, ``,`` and ``""`` are refused)."""
    import argparse

    names = [s.strip() for s in text.split(",")]
    if not all(names):
        raise argparse.ArgumentTypeError(f"expected comma-separated experiment names, got "
                                         f"{text!r} (an empty name)")
    return names


def register(sub) -> None:
    """Add ``reproduce``."""
    p = sub.add_parser(
        "reproduce", help="regenerate the paper's experiments, figures and claims",
        description="Run every experiment of the paper and write into OUT: claims.json and "
                    "claims.md (one verdict per claim: reproduced, partly reproduced, not "
                    "reproduced, data unavailable), the figures (PNG and SVG, in figures/), "
                    "the tables (CSV, in tables/), timings.json, and the cache of "
                    "experiments (JSON, in experiments/). Prints a JSON summary "
                    "(out, claims, ran, reused, skipped, seconds, success). A missing data "
                    "set is bad input (exit 2; the line says where to put it) unless "
                    "--allow-missing.")
    p.add_argument("--quick", action="store_true",
                   help="fewer trials, same verdict rules (minutes instead of tens of minutes)")
    p.add_argument("--out", default="reproduction", help="output folder (default ./reproduction)")
    p.add_argument("--jobs", type=_jobs, default=1,
                   help=f"experiments in parallel, joblib processes (default 1, at most "
                        f"{MAX_JOBS})")
    p.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="run on an existing Dask distributed scheduler, e.g. tcp://host:8786")
    p.add_argument("--force", action="store_true", help="recompute cached experiments")
    p.add_argument("--allow-missing", action="store_true",
                   help="mark claims whose data set is missing 'data unavailable' instead of "
                        "stopping")
    p.add_argument("--only", type=_names, default=None, metavar="NAMES",
                   help="comma-separated experiments to run (the other claims become "
                        "'data unavailable')")
    p.add_argument("--no-progress", action="store_true", help="no progress bars")
    p.set_defaults(run=_run)


def _run(args) -> dict:
    from . import reproduce

    # bars and the expected / measured time on standard error only where they are
    # progress: a terminal, not --quiet or --no-progress (the summary is the JSON)
    shown = args.progress.enabled
    res = reproduce(Path(args.out), quick=args.quick, jobs=args.jobs, scheduler=args.scheduler,
                    force=args.force, allow_missing=args.allow_missing, only=args.only,
                    progress=shown, log=None if shown else (lambda s: None))
    return {"out": str(res.out), "claims": {c["key"]: c["verdict"] for c in res.claims},
            "ran": res.ran, "reused": res.reused, "skipped": res.skipped,
            "seconds": round(res.seconds, 1), "success": True}
