"""Typed 3D landmark maps: the RoboCup field, the MoCap lab scenario's map, the JSON format.

The field map (:func:`field_map`) is the whole RoboCup field of the
predecessor paper: both halves, the ground features and goal posts at
``z = 0`` and the crossbar corners of both goals. It is symmetric under the
180 degree rotation about the vertical axis through the centre spot, so
every set of detections fits the true pose and its mirror image equally well
(and a triplet of ground features fits four poses: those two and the two
with the camera upside down below the floor).

The lab map is one half of a RoboCup field (the MoCap volume covers the
attacking half): the field's ground features (``z = 0``) from
:func:`~clap_unified.maps.field.field_landmarks`, the goal posts at
their feet, the crossbar corners at the goal height, and a few typed wall
markers at different heights. The elevated landmarks matter: the ground
features alone are coplanar and symmetric about the field's long axis, so a
triplet of them also fits a camera flipped upside down below the floor.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._validation import check_points
from ..io import MAX_ITEMS, read_typed_points
from ..maps.field import FIELD_DIMENSIONS, field_landmarks

__all__ = ["LandmarkMap3D", "field_map", "lab_map", "read_landmarks_json", "GOAL_HEIGHT",
           "FIELD_MIRROR"]

#: Crossbar height above the ground (metres) by field size.
GOAL_HEIGHT = {"adult": 1.8, "kid": 1.2}

#: The field's symmetry: the 180 degree rotation about the vertical axis through the centre
#: spot, as a 4 x 4 world transform (``FIELD_MIRROR @ T`` is the mirror image of pose ``T``).
FIELD_MIRROR = np.diag([-1.0, -1.0, 1.0, 1.0])

#: Wall markers of the lab (x, y, z in metres), deliberately asymmetric.
LAB_MARKERS = ((7.9, 3.1, 1.2), (7.9, -2.4, 2.1), (5.2, -5.4, 1.6), (2.3, 5.4, 0.9))


@dataclass(frozen=True)
class LandmarkMap3D:
    """Typed landmarks in the world frame.

    Attributes
    ----------
    types : ndarray of str, shape (M,)
    positions : ndarray of shape (M, 3)
        Metres.
    name : str
    """

    types: np.ndarray
    positions: np.ndarray
    name: str = "map"

    def __post_init__(self):
        pos = check_points(self.positions, "positions", dim=3, min_count=3)
        types = np.asarray([str(t) for t in self.types])
        if types.shape != (len(pos),):
            raise ValueError(f"types: expected one type per landmark ({len(pos)}), "
                             f"got {types.shape}")
        object.__setattr__(self, "positions", pos)
        object.__setattr__(self, "types", types)

    def __len__(self) -> int:
        return len(self.positions)

    def to_json(self) -> list[dict]:
        """The map as the command line reads it: ``[{"type", "x", "y", "z"}, ...]``."""
        return [{"type": str(k), "x": float(x), "y": float(y), "z": float(z)}
                for k, (x, y, z) in zip(self.types, self.positions, strict=True)]

    def space(self, **kwargs):
        """A :class:`~clap_unified.spaces.landmarks3d.Landmark3DSpace` on this map."""
        from ..spaces.landmarks3d import Landmark3DSpace

        return Landmark3DSpace(self.positions, self.types, **kwargs)


def _check_size(size: str) -> dict:
    if size not in FIELD_DIMENSIONS:
        raise ValueError(f"size: expected one of {sorted(FIELD_DIMENSIONS)}, got {size!r}")
    return FIELD_DIMENSIONS[size]


def _crossbars(dims: dict, size: str, ends=(1,)) -> list:
    """Crossbar corners (goal post tops) of the goals at ``x = end * length / 2``."""
    hl, hg = dims["length"] / 2, dims["goal_width"] / 2
    return [[sx * hl, sy * hg, GOAL_HEIGHT[size]] for sx in ends for sy in (-1, 1)]


def field_map(size: str = "adult") -> LandmarkMap3D:
    """The whole RoboCup field in 3D: the predecessor paper's setup, symmetric by design.

    Every ground feature of :func:`~clap_unified.maps.field.field_landmarks`
    (L, T and X junctions, penalty marks, centre mark, goal posts' feet) at
    ``z = 0``, and the four crossbar corners (type ``"crossbar"``) of both goals
    at ``GOAL_HEIGHT``. No other markers: the map is invariant under
    ``FIELD_MIRROR``, so a pose and its mirror image explain any detections
    equally well.

    Parameters
    ----------
    size : {"adult", "kid"}

    Examples
    --------
    >>> m = field_map()
    >>> len(m), sorted(set(m.types.tolist()))
    (35, ['L', 'T', 'X', 'center_mark', 'crossbar', 'goal_post', 'penalty_mark'])
    >>> turned = m.positions @ FIELD_MIRROR[:3, :3].T        # the 180 degree rotation
    >>> all(np.any(np.all(np.isclose(turned[i], m.positions[m.types == t]), axis=1))
    ...     for i, t in enumerate(m.types))
    True
    """
    dims = _check_size(size)
    marks = field_landmarks(dims)
    types = [m["type"] for m in marks] + ["crossbar"] * 4
    pos = [[m["x"], m["y"], 0.0] for m in marks] + _crossbars(dims, size, ends=(-1, 1))
    return LandmarkMap3D(np.array(types), np.array(pos), name=f"field-{size}")


def lab_map(size: str = "adult", *, markers: bool = True) -> LandmarkMap3D:
    """The simulated MoCap lab: half a RoboCup field, its goal, and wall markers.

    Parameters
    ----------
    size : {"adult", "kid"}
    markers : bool
        Add the wall markers (type ``"marker"``).

    Examples
    --------
    >>> m = lab_map()
    >>> len(m), sorted(set(m.types.tolist()))
    (24, ['L', 'T', 'X', 'center_mark', 'crossbar', 'goal_post', 'marker', 'penalty_mark'])
    """
    dims = _check_size(size)
    types, pos = [], []
    for m in field_landmarks(dims):
        if m["x"] >= 0:
            types.append(m["type"])
            pos.append([m["x"], m["y"], 0.0])
    for xyz in _crossbars(dims, size):
        types.append("crossbar")
        pos.append(xyz)
    if markers:
        for xyz in LAB_MARKERS:
            types.append("marker")
            pos.append(list(xyz))
    return LandmarkMap3D(np.array(types), np.array(pos), name=f"lab-{size}")


def read_landmarks_json(path, what: str = "map", *, max_items: int = MAX_ITEMS,
                        types=None) -> tuple[np.ndarray, np.ndarray]:
    """Types ``(M,)`` and positions ``(M, 3)`` from a JSON list of ``{"type", "x", "y", "z"}``.

    Raises
    ------
    ValueError
        Missing or unreadable file, a folder, invalid JSON, not a list, more than
        ``max_items`` entries, a missing, non-numeric or non-finite coordinate, a type that
        is not a string or not one of ``types`` (if given); the message names the file and
        the entry.
    """
    names, pos = read_typed_points(path, "xyz", what=what, max_items=max_items, types=types)
    return np.array(names, dtype=str), pos
