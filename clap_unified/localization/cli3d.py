"""``clap-unified localize3d OBS.json --map MAP.json``: one-frame 6-DoF pose."""

from __future__ import annotations

import numpy as np

from ..io import MAX_HYPOTHESES, MAX_WORK, check_budget, int_option
from ..presets import get_preset
from ..registry import strategy_names
from ..spaces.landmarks3d import Landmark3DSpace
from .localize3d import localize3d
from .map3d import LandmarkMap3D, read_landmarks_json

__all__ = ["MAX_DETECTIONS", "MAX_LANDMARKS", "register"]

#: Detections in OBS.json at most.
MAX_DETECTIONS = 500
#: Landmarks in MAP.json at most: the candidates come from map triplets, whose number grows
#: as the cube (``bench/bench_cli_limits.py`` times the command and measures its memory at
#: these limits, every landmark of one type).
MAX_LANDMARKS = 100


def _localize3d(args) -> dict:
    args.progress.stage("reading the map")
    types, positions = read_landmarks_json(args.map, "map", max_items=MAX_LANDMARKS)
    try:
        landmarks = LandmarkMap3D(types, positions, name=str(args.map))
    except ValueError as exc:
        raise ValueError(f"{args.map}: {exc}") from None
    space = landmarks.space()
    args.progress.stage("reading detections")
    obs_types, obs_xyz = read_landmarks_json(args.observations, "observations",
                                             max_items=MAX_DETECTIONS, types=space.type_names)
    if not obs_types.size:
        raise ValueError(f"{args.observations}: no detections (an empty list)")
    ids = [space.type_id(t) for t in obs_types]
    data = np.c_[np.asarray(ids, dtype=float), obs_xyz].reshape(-1, 4)
    budget = {}
    if args.hypotheses is not None:  # open3d: its iteration cap
        check_budget(args.method, args.hypotheses, len(data))
        budget = {"n_hypotheses": args.hypotheses, "open3d_iterations": args.hypotheses}
    args.progress.stage(f"localizing ({args.method})")
    res = localize3d(data, landmarks, method=args.method, space=space, rng=args.seed,
                     **budget)
    diag = res.diagnostics  # candidate poses, or the pairs handed to Open3D
    return {**res.to_dict(), "candidates": int(diag.get("hypotheses") or diag.get("candidates", 0)),
            "map": str(args.map)}


def register(sub) -> None:
    """Add ``localize3d`` to the ``clap-unified`` command."""
    p = sub.add_parser(
        "localize3d", help="6-DoF pose from typed 3D landmark detections and a map",
        description="Pose T_world_body (a body point p is at R p + t in the world) from "
                    "OBS.json, a list of {\"type\", \"x\", \"y\", \"z\"} detections in the body "
                    "frame (metres), and MAP.json, the same in the world frame. The JSON's "
                    "model is {\"rotation\": 3 x 3 row-major, \"translation\": [x, y, z]}, "
                    "plus candidates and map. Fewer than three detections, or no triplet of "
                    "detections matching the map, is a failed estimate (exit 1).")
    p.add_argument("observations", metavar="OBS.json",
                   help="JSON list of detections {\"type\", \"x\", \"y\", \"z\"} in the "
                        "body frame: type a string the map has, x, y, z finite numbers "
                        f"(metres); 1 to {MAX_DETECTIONS} entries")
    p.add_argument("--map", required=True, metavar="MAP.json",
                   help="JSON list of landmarks {\"type\", \"x\", \"y\", \"z\"} in the "
                        f"world frame (metres); 3 to {MAX_LANDMARKS} entries")
    methods = strategy_names(Landmark3DSpace(np.eye(3), ["a", "b", "c"]))
    p.add_argument("--method", choices=list(methods), default="clap",
                   help="consensus strategy (default clap; open3d: Open3D's RANSAC)")
    p.add_argument("--seed", type=int_option(), default=0,
                   help="random seed (triplet sampling; default 0)")
    budget = get_preset("pose3d", None, task="localize").fit["n_hypotheses"]
    iterations = get_preset("pose3d", "open3d", task="localize").fit["n_hypotheses"]
    p.add_argument("--hypotheses", type=int_option(1, MAX_HYPOTHESES), default=None, metavar="H",
                   help=f"candidate poses (clap, ransac, randomized_hough: all detection "
                        f"triplets are enumerated while they are at most H, beyond H are "
                        f"sampled; default {budget}) or the iteration "
                        f"cap (open3d; default {iterations}); at most "
                        f"{MAX_HYPOTHESES}, and hypotheses x detections at most {MAX_WORK:.0e}")
    p.set_defaults(run=_localize3d)
