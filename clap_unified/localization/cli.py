"""``clap-unified localize2d OBS.json --field adult``: one-frame pose on a RoboCup field."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..io import MAX_HYPOTHESES, MAX_WORK, check_budget, int_option, read_typed_points
from ..maps.field import FIELD_DIMENSIONS, LANDMARK_TYPES, load_field
from ..presets import get_preset
from ..registry import strategy_names
from ..spaces.landmarks2d import Landmark2DSpace
from .localize2d import localize2d, observation_data

__all__ = ["MAX_DETECTIONS", "register", "read_observations"]

#: Detections in one frame at most (a robot sees a few dozen): the candidate poses grow as
#: the square of their number (``bench/bench_cli_limits.py`` times the command at this
#: limit, all detections of one type).
MAX_DETECTIONS = 100


def read_observations(path):
    """Observations ``(N, 3)`` from a JSON list of ``{"type", "x", "y"}`` (robot frame, metres).

    Raises
    ------
    ValueError
        Missing or unreadable file, a folder, invalid JSON, not a list, an empty list, more
        than :data:`MAX_DETECTIONS` entries, unknown types, missing, non-numeric or
        non-finite coordinates; the message names the file.
    """
    path = Path(path)
    types, xy = read_typed_points(path, "xy", what="observations", max_items=MAX_DETECTIONS,
                                  types=LANDMARK_TYPES)
    if not types:
        raise ValueError(f"{path}: no detections (an empty list)")
    return observation_data([{"type": t, "x": x, "y": y}
                             for t, (x, y) in zip(types, xy, strict=True)])


def _prior(text):
    """``--prior X,Y,THETA``: three finite numbers (metres, metres, radians)."""
    import argparse

    try:
        x, y, theta = (float(v) for v in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"expected X,Y,THETA: three comma-separated numbers (metres, metres, radians), "
            f"got {text!r}") from None
    if not np.all(np.isfinite([x, y, theta])):
        raise argparse.ArgumentTypeError(f"expected finite numbers, got {text!r}")
    return x, y, theta


def _space(field: str) -> Landmark2DSpace:
    return Landmark2DSpace(load_field(field))


def _localize2d(args) -> dict:
    args.progress.stage("reading detections")
    data = read_observations(args.observations)
    budget = {}
    if args.hypotheses is not None:
        check_budget(args.method, args.hypotheses, len(data))
        budget = {"n_hypotheses": args.hypotheses}
    args.progress.stage(f"localizing ({args.method})")
    res = localize2d(data, space=_space(args.field), method=args.method, prior=args.prior,
                     rng=args.seed, **budget)
    return {**res.to_dict(), "candidates": int(res.diagnostics.get("hypotheses", 0)),
            "field": args.field}


def register(sub) -> None:
    """Add ``localize2d`` to the ``clap-unified`` command."""
    p = sub.add_parser(
        "localize2d", help="robot pose on a RoboCup field from landmark detections",
        description="Pose of the robot on the field (origin at the centre spot, x towards the "
                    "opponent goal) from OBS.json: a list of {\"type\", \"x\", \"y\"} detections "
                    "in the robot frame (metres, x forward, y left). The JSON's model is "
                    "{\"x\", \"y\", \"theta\"} (metres, radians), plus candidates and field. "
                    "Fewer than two detections, or nothing near the prior, is a failed "
                    "estimate (exit 1).")
    p.add_argument("observations", metavar="OBS.json",
                   help=f"JSON list of detections {{\"type\", \"x\", \"y\"}}, type one of "
                        f"{', '.join(LANDMARK_TYPES)}, x and y finite numbers (metres); "
                        f"1 to {MAX_DETECTIONS} entries")
    p.add_argument("--field", choices=sorted(FIELD_DIMENSIONS), default="adult",
                   help="RoboCup Humanoid field the robot is on: adult (AdultSize, 14 x 9 m; "
                        "default) or kid (KidSize, 9 x 6 m)")
    p.add_argument("--method", choices=list(strategy_names(_space("adult"))), default="clap",
                   help="consensus strategy (default clap)")
    p.add_argument("--prior", metavar="X,Y,THETA", type=_prior, default=None,
                   help="previous estimate, e.g. --prior -1.2,3.4,0.1 (metres, metres, "
                        "radians): CLAP's local mode; the other methods see only the "
                        "candidates near it")
    p.add_argument("--seed", type=int_option(), default=0,
                   help="random seed (pair sampling only; default 0)")
    default = get_preset("pose2d", None, task="localize").fit["n_hypotheses"]
    p.add_argument("--hypotheses", type=int_option(1, MAX_HYPOTHESES), default=None, metavar="H",
                   help=f"observation pairs: all are enumerated while they are at most H, "
                        f"beyond H are sampled; every candidate pose they give is used "
                        f"(default {default}); at most {MAX_HYPOTHESES}, and hypotheses x "
                        f"detections at most {MAX_WORK:.0e}")
    p.set_defaults(run=_localize2d)
