"""``clap-unified localize3d OBS.json --map MAP.json``: one-frame 6-DoF pose."""

from __future__ import annotations

import time

import numpy as np

from .cli import result_summary
from .localize3d import LOCALIZE3D_METHODS, localize3d
from .map3d import LandmarkMap3D, read_landmarks_json

__all__ = ["register"]


def _pose(T) -> dict:
    T = np.asarray(T, dtype=float)
    return {"rotation": T[:3, :3].tolist(), "translation": T[:3, 3].tolist()}


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
    t0 = time.perf_counter()
    res = localize3d(data, landmarks, method=args.method, space=space, rng=args.seed)
    seconds = time.perf_counter() - t0
    out = {
        **(_pose(res.model) if res.success else {"rotation": None, "translation": None}),
        "clusters": [{**_pose(c.model), "support": int(c.support), "spread": float(c.spread)}
                     for c in res.clusters],
        **result_summary(res, len(data), args.method, seconds),
    }
    return out


def register(sub) -> None:
    """Add ``localize3d`` to the ``clap-unified`` command."""
    p = sub.add_parser(
        "localize3d", help="6-DoF pose from typed 3D landmark detections and a map",
        description="Pose T_world_body (a body point p is at R p + t in the world) from "
                    "OBS.json, a list of {\"type\", \"x\", \"y\", \"z\"} detections in the body "
                    "frame (metres), and MAP.json, the same in the world frame.")
    p.add_argument("observations", metavar="OBS.json")
    p.add_argument("--map", required=True, metavar="MAP.json")
    p.add_argument("--method", choices=LOCALIZE3D_METHODS, default="clap")
    p.add_argument("--seed", type=int, default=0, help="random seed (triplet sampling)")
    p.set_defaults(run=_localize3d)
