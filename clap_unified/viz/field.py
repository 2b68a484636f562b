"""Drawing a RoboCup field, its landmarks, robot poses and detections."""

from __future__ import annotations

import numpy as np
from matplotlib.patches import Circle, Polygon, Rectangle

__all__ = ["LANDMARK_STYLE", "draw_field", "draw_pose", "draw_detections"]

#: Marker and colour of each landmark type.
LANDMARK_STYLE = {
    "L": dict(marker="s", color="#1f77b4"),
    "T": dict(marker="^", color="#ff7f0e"),
    "X": dict(marker="X", color="#9467bd"),
    "goal_post": dict(marker="o", color="#d62728"),
    "penalty_mark": dict(marker="P", color="#8c564b"),
    "center_mark": dict(marker="*", color="#e377c2"),
}


def draw_field(ax, field, *, landmarks: bool = True, legend: bool = False, lines="0.55",
               carpet="#e8f3e8", label_size: float = 30):
    """Field lines (from the rule dimensions) and, optionally, the typed landmarks.

    Parameters
    ----------
    ax : matplotlib Axes
    field : Field
    landmarks : bool
        Draw each landmark with its type's marker (:data:`LANDMARK_STYLE`).
    legend : bool
        Add a legend of the landmark types.
    lines, carpet : colour
    label_size : float
        Marker size of the landmarks.
    """
    d = field.dimensions
    hl, hw, border = d["length"] / 2, d["width"] / 2, d.get("border", 1.0)
    ax.add_patch(Rectangle((-hl - border, -hw - border), 2 * (hl + border), 2 * (hw + border),
                           color=carpet, zorder=0))
    kw = dict(fill=False, lw=1.2, ec=lines, zorder=1)
    ax.add_patch(Rectangle((-hl, -hw), 2 * hl, 2 * hw, **kw))
    ax.plot([0, 0], [-hw, hw], color=lines, lw=1.2, zorder=1)
    ax.add_patch(Circle((0, 0), d["centre_circle_diameter"] / 2, **kw))
    for sx in (-1, 1):
        ga_l, ga_w = d["goal_area_length"], d["goal_area_width"] / 2
        pa_l, pa_w = d["penalty_area_length"], d["penalty_area_width"] / 2
        for length, width in ((ga_l, ga_w), (pa_l, pa_w)):
            x0 = hl - length if sx > 0 else -hl
            ax.add_patch(Rectangle((x0, -width), length, 2 * width, **kw))
        gw, gd = d["goal_width"] / 2, d["goal_depth"]
        x0 = hl if sx > 0 else -hl - gd
        ax.add_patch(Rectangle((x0, -gw), gd, 2 * gw, fill=False, lw=2.0, ec="0.3", zorder=1))
    if landmarks:
        for kind, style in LANDMARK_STYLE.items():
            pts = field.of_type(kind)
            if len(pts):
                ax.scatter(pts[:, 0], pts[:, 1], s=label_size, zorder=3, label=kind,
                           edgecolors="k", linewidths=0.4, **style)
    ax.set_xlim(-hl - border, hl + border)
    ax.set_ylim(-hw - border, hw + border)
    ax.set_aspect("equal")
    ax.set_xticks([])
    ax.set_yticks([])
    if legend:
        ax.legend(loc="upper center", ncol=6, fontsize=8, bbox_to_anchor=(0.5, -0.01),
                  frameon=False)
    return ax


def draw_pose(ax, poses, *, color="k", size: float = 0.5, label=None, alpha: float = 1.0,
              zorder: int = 4, fov=None, fov_range: float = 6.0):
    """Robot poses as arrowheads (triangles pointing along the heading).

    Parameters
    ----------
    poses : ndarray of shape (3, 3) or (K, 3, 3), or (x, y, theta) rows
    fov : float, optional
        Draw the camera's field of view (radians) of the first pose as a wedge
        of radius ``fov_range``.
    """
    P = np.asarray(poses, dtype=float)
    if P.shape[-2:] == (3, 3):
        P = P.reshape(-1, 3, 3)
        xyt = np.stack([P[:, 0, 2], P[:, 1, 2], np.arctan2(P[:, 1, 0], P[:, 0, 0])], -1)
    else:
        xyt = P.reshape(-1, 3)
    corners = []
    for k, (x, y, t) in enumerate(xyt):
        c, s = np.cos(t), np.sin(t)
        tri = np.array([[size, 0.0], [-0.5 * size, 0.45 * size], [-0.5 * size, -0.45 * size]])
        pts = tri @ np.array([[c, s], [-s, c]]) + (x, y)
        corners.append(pts)
        ax.add_patch(Polygon(pts, closed=True, fc=color, ec="k", lw=0.5, alpha=alpha,
                             zorder=zorder, label=label if k == 0 else None))
    if corners:  # widen the view (never narrow it) so that no marker is cut at its edge
        lo, hi = np.min(np.vstack(corners), 0) - 0.1 * size, np.max(np.vstack(corners), 0)
        hi = hi + 0.1 * size
        (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
        ax.set_xlim(min(x0, lo[0]), max(x1, hi[0]))
        ax.set_ylim(min(y0, lo[1]), max(y1, hi[1]))
    if fov is not None and len(xyt):
        x, y, t = xyt[0]
        angles = np.linspace(t - fov / 2, t + fov / 2, 30)
        wedge = np.r_[[[x, y]], np.c_[x + fov_range * np.cos(angles),
                                       y + fov_range * np.sin(angles)]]
        ax.add_patch(Polygon(wedge, closed=True, fc=color, alpha=0.08, ec="none", zorder=2))
    return ax


def draw_detections(ax, pose, data, *, is_false=None, size: float = 40):
    """Detections ``(N, 3)`` (type_id, x, y in the robot frame) placed on the field by ``pose``.

    False detections (``is_false``) get a red outline.
    """
    from ..maps.field import LANDMARK_TYPES

    data = np.asarray(data, dtype=float).reshape(-1, 3)
    T = np.asarray(pose, dtype=float)
    world = data[:, 1:] @ T[:2, :2].T + T[:2, 2]
    bad = np.zeros(len(data), bool) if is_false is None else np.asarray(is_false, bool)
    for k, (tid, (x, y)) in enumerate(zip(data[:, 0].astype(int), world, strict=True)):
        style = LANDMARK_STYLE[LANDMARK_TYPES[tid]]
        ax.scatter([x], [y], s=size, marker=style["marker"], facecolors="none",
                   edgecolors="red" if bad[k] else style["color"], linewidths=1.6, zorder=5)
        ax.plot([T[0, 2], x], [T[1, 2], y], color="red" if bad[k] else "0.4", lw=0.6,
                ls=":" if bad[k] else "-", zorder=2)
    return ax
