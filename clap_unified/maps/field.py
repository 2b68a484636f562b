"""RoboCup Humanoid soccer fields as typed landmark maps.

Field frame: origin at the centre spot, x towards the opponent goal, y to the
left, metres. The landmark files ``clap_unified/maps/fields/<name>.json`` (package data,
read with ``importlib.resources``, so an installed package finds them) are generated
from the rule dimensions by :func:`field_landmarks` and checked against it by the tests.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

import numpy as np

__all__ = ["LANDMARK_TYPES", "Field", "field_file", "field_landmarks", "load_field",
           "FIELD_DIMENSIONS"]

#: Landmark types, as used in observation files.
LANDMARK_TYPES = ("L", "T", "X", "goal_post", "penalty_mark", "center_mark")

#: Rule dimensions in metres (RoboCup Humanoid League).
FIELD_DIMENSIONS = {
    "adult": dict(length=14.0, width=9.0, goal_depth=0.6, goal_width=2.6, goal_area_length=1.0,
                  goal_area_width=4.0, penalty_mark=2.1, centre_circle_diameter=3.0, border=1.0,
                  penalty_area_length=3.0, penalty_area_width=6.0),
    "kid": dict(length=9.0, width=6.0, goal_depth=0.6, goal_width=2.6, goal_area_length=1.0,
                goal_area_width=3.0, penalty_mark=1.5, centre_circle_diameter=1.5, border=1.0,
                penalty_area_length=2.0, penalty_area_width=5.0),
}



def field_file(name: str):
    """The packaged landmark file of field ``name`` (a ``importlib.resources`` traversable).

    Examples
    --------
    >>> field_file("adult").name
    'adult.json'
    """
    if name not in FIELD_DIMENSIONS:
        raise ValueError(f"name: expected one of {sorted(FIELD_DIMENSIONS)}, got {name!r}")
    return resources.files(__package__).joinpath("fields", f"{name}.json")


def field_landmarks(dims: dict) -> list[dict]:
    """Typed landmarks of a field from its rule dimensions.

    Examples
    --------
    >>> marks = field_landmarks(FIELD_DIMENSIONS["adult"])
    >>> sorted({m["type"] for m in marks}) == sorted(LANDMARK_TYPES)
    True
    >>> len(marks)
    31
    """
    hl, hw = dims["length"] / 2, dims["width"] / 2
    ga_x, ga_y = hl - dims["goal_area_length"], dims["goal_area_width"] / 2
    pa_x, pa_y = hl - dims["penalty_area_length"], dims["penalty_area_width"] / 2
    r = dims["centre_circle_diameter"] / 2
    marks = []

    def add(kind, x, y):
        marks.append({"type": kind, "x": float(x), "y": float(y)})

    for sx in (-1, 1):
        for sy in (-1, 1):
            add("L", sx * hl, sy * hw)          # field corners
            add("L", sx * ga_x, sy * ga_y)      # goal area corners
            add("L", sx * pa_x, sy * pa_y)      # penalty area corners
            add("T", sx * hl, sy * ga_y)        # goal area line meets goal line
            add("T", sx * hl, sy * pa_y)        # penalty area line meets goal line
            add("goal_post", sx * hl, sy * dims["goal_width"] / 2)
    for sy in (-1, 1):
        add("T", 0.0, sy * hw)                  # halfway line meets touchline
        add("X", 0.0, sy * r)                   # centre circle crosses halfway line
    for sx in (-1, 1):
        add("penalty_mark", sx * (hl - dims["penalty_mark"]), 0.0)
    add("center_mark", 0.0, 0.0)
    return marks


@dataclass(frozen=True)
class Field:
    """A landmark map: names, dimensions, and typed landmark positions.

    Attributes
    ----------
    name : str
    dimensions : dict
    types : ndarray of str, shape (M,)
    positions : ndarray of shape (M, 2)
    """

    name: str
    dimensions: dict
    types: np.ndarray
    positions: np.ndarray

    def of_type(self, kind: str) -> np.ndarray:
        """Positions of every landmark of one type, shape ``(K, 2)``."""
        return self.positions[self.types == kind]


def load_field(name: str = "adult", path=None) -> Field:
    """Load a field's landmark map: the packaged ``fields/<name>.json`` (or the file ``path``).

    Examples
    --------
    >>> f = load_field("kid")
    >>> f.of_type("goal_post").tolist()[:2]
    [[-4.5, -1.3], [-4.5, 1.3]]
    """
    path = field_file(name) if path is None else Path(path)
    try:
        doc = json.loads(path.read_text())
        marks = doc["landmarks"]
        types = np.array([m["type"] for m in marks])
        positions = np.array([[float(m["x"]), float(m["y"])] for m in marks])
    except FileNotFoundError:
        raise ValueError(f"{path}: no such field file") from None
    except (json.JSONDecodeError, KeyError, TypeError, ValueError) as exc:
        raise ValueError(f"{path}: not a valid field file ({exc})") from None
    unknown = set(types.tolist()) - set(LANDMARK_TYPES)
    if unknown:
        raise ValueError(f"{path}: unknown landmark types {sorted(unknown)}")
    if not np.all(np.isfinite(positions)):
        raise ValueError(f"{path}: non-finite landmark position")
    return Field(doc.get("name", name), doc.get("dimensions", {}), types, positions)
