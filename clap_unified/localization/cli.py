"""``clap-unified localize2d OBS.json --field adult``: one-frame pose on a RoboCup field."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..io import read_json_list
from ..maps.field import FIELD_DIMENSIONS, load_field
from ..registry import strategy_names
from ..spaces.landmarks2d import Landmark2DSpace
from .localize2d import localize2d, observation_data

__all__ = ["register", "read_observations"]


def read_observations(path):
    """Observations ``(N, 3)`` from a JSON list of ``{"type", "x", "y"}`` (robot frame, metres).

    Raises
    ------
    ValueError
        Missing or unreadable file, invalid JSON, not a list, unknown types,
        missing or non-finite coordinates; the message names the file.
    """
    path = Path(path)
    doc = read_json_list(path)
    try:
        data = observation_data(doc)
    except ValueError as exc:
        raise ValueError(f"{path}: {exc}") from None
    if not np.all(np.isfinite(data)):
        raise ValueError(f"{path}: observation coordinates must be finite numbers")
    return data


def _prior(text):
    try:
        x, y, theta = (float(v) for v in text.split(","))
    except ValueError:
        raise ValueError(f"--prior: expected X,Y,THETA (metres, metres, radians), got {text!r}") \
            from None
    return x, y, theta


def _space(field: str) -> Landmark2DSpace:
    return Landmark2DSpace(load_field(field))


def _localize2d(args) -> dict:
    data = read_observations(args.observations)
    prior = None if args.prior is None else _prior(args.prior)
    res = localize2d(data, space=_space(args.field), method=args.method, prior=prior,
                     rng=args.seed)
    return {**res.to_dict(), "candidates": int(res.diagnostics.get("hypotheses", 0)),
            "field": args.field}


def register(sub) -> None:
    """Add ``localize2d`` to the ``clap-unified`` command."""
    p = sub.add_parser(
        "localize2d", help="robot pose on a RoboCup field from landmark detections",
        description="Pose of the robot on the field (origin at the centre spot, x towards the "
                    "opponent goal) from OBS.json: a list of {\"type\", \"x\", \"y\"} detections "
                    "in the robot frame (metres, x forward, y left).")
    p.add_argument("observations", metavar="OBS.json")
    p.add_argument("--field", choices=sorted(FIELD_DIMENSIONS), default="adult")
    p.add_argument("--method", choices=list(strategy_names(_space("adult"))), default="clap")
    p.add_argument("--prior", metavar="X,Y,THETA", default=None,
                   help="previous estimate: CLAP's local mode; the other methods see only the "
                        "candidates near it")
    p.add_argument("--seed", type=int, default=0, help="random seed (pair sampling only)")
    p.set_defaults(run=_localize2d)
