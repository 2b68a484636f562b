"""``clap-unified localize2d OBS.json --field adult``: one-frame pose on a RoboCup field."""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from ..geometry.se2 import SE2
from ..io import read_json_list
from ..maps.field import FIELD_DIMENSIONS
from .localize2d import LOCALIZE_METHODS, localize2d, observation_data

__all__ = ["register", "read_observations", "result_summary"]


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


def _pose_dict(T) -> dict:
    x, y, theta = SE2.to_xytheta(T)
    return {"x": float(x), "y": float(y), "theta": float(theta)}


def _localize2d(args) -> dict:
    data = read_observations(args.observations)
    prior = None if args.prior is None else _prior(args.prior)
    t0 = time.perf_counter()
    res = localize2d(data, args.field, method=args.method, prior=prior, rng=args.seed)
    seconds = time.perf_counter() - t0
    out = {
        "pose": _pose_dict(res.model) if res.success else None,
        "clusters": [{"pose": _pose_dict(c.model), "support": int(c.support),
                      "spread": float(c.spread)} for c in res.clusters],
        **result_summary(res, len(data), args.method, seconds),
        "field": args.field,
    }
    return out


def result_summary(res, n_observations: int, method: str, seconds: float) -> dict:
    """The JSON fields every ``localize*`` command prints besides the pose and clusters."""
    out = {
        "success": bool(res.success),
        "inliers": res.n_inliers,
        "observations": n_observations,
        "candidates": int(res.diagnostics.get("candidates", 0)),
        "method": method,
        "seconds": round(seconds, 6),
    }
    if not res.success:
        out["reason"] = res.reason
    return out


def register(sub) -> None:
    """Add ``localize2d`` to the ``clap-unified`` command."""
    p = sub.add_parser(
        "localize2d", help="robot pose on a RoboCup field from landmark detections",
        description="Pose of the robot on the field (origin at the centre spot, x towards the "
                    "opponent goal) from OBS.json: a list of {\"type\", \"x\", \"y\"} detections "
                    "in the robot frame (metres, x forward, y left).")
    p.add_argument("observations", metavar="OBS.json")
    p.add_argument("--field", choices=sorted(FIELD_DIMENSIONS), default="adult")
    p.add_argument("--method", choices=LOCALIZE_METHODS, default="clap")
    p.add_argument("--prior", metavar="X,Y,THETA", default=None,
                   help="previous estimate: CLAP's local mode; RANSAC and Hough gate around it")
    p.add_argument("--seed", type=int, default=0, help="random seed (pair sampling only)")
    p.set_defaults(run=_localize2d)
