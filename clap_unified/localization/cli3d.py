"""``clap-unified localize3d OBS.json --map MAP.json``: one-frame 6-DoF pose."""

from __future__ import annotations

import numpy as np

from ..registry import strategy_names
from ..spaces.landmarks3d import Landmark3DSpace
from .localize3d import localize3d
from .map3d import LandmarkMap3D, read_landmarks_json

__all__ = ["register"]


def _localize3d(args) -> dict:
    types, positions = read_landmarks_json(args.map, "map")
    try:
        landmarks = LandmarkMap3D(types, positions, name=str(args.map))
    except ValueError as exc:
        raise ValueError(f"{args.map}: {exc}") from None
    space = landmarks.space()
    obs_types, obs_xyz = read_landmarks_json(args.observations, "observations")
    try:
        ids = [space.type_id(t) for t in obs_types]
    except ValueError as exc:
        raise ValueError(f"{args.observations}: {exc}") from None
    data = np.c_[np.asarray(ids, dtype=float), obs_xyz].reshape(-1, 4)
    res = localize3d(data, landmarks, method=args.method, space=space, rng=args.seed)
    diag = res.diagnostics  # candidate poses, or the pairs handed to Open3D
    return {**res.to_dict(), "candidates": int(diag.get("hypotheses") or diag.get("candidates", 0)),
            "map": str(args.map)}


def register(sub) -> None:
    """Add ``localize3d`` to the ``clap-unified`` command."""
    p = sub.add_parser(
        "localize3d", help="6-DoF pose from typed 3D landmark detections and a map",
        description="Pose T_world_body (a body point p is at R p + t in the world) from "
                    "OBS.json, a list of {\"type\", \"x\", \"y\", \"z\"} detections in the body "
                    "frame (metres), and MAP.json, the same in the world frame.")
    p.add_argument("observations", metavar="OBS.json")
    p.add_argument("--map", required=True, metavar="MAP.json")
    methods = strategy_names(Landmark3DSpace(np.eye(3), ["a", "b", "c"]))
    p.add_argument("--method", choices=list(methods), default="clap")
    p.add_argument("--seed", type=int, default=0, help="random seed (triplet sampling)")
    p.set_defaults(run=_localize3d)
