"""Stick figures on matplotlib axes, shared by the pictures that draw a body (validation runs, job reports): the
views (which world axes go right and up) and the drawing of segments and points in one view. Only numpy here; the
caller owns the figure (Agg or not). World frame: m, z up, the manikin facing -y, its left at +x."""

from __future__ import annotations

from collections.abc import Iterable, Sequence

import numpy as np

# view -> (world axis pointing right in the picture, world axis pointing up, label of the horizontal axis)
VIEWS = {
    "side": ((0.0, -1.0, 0.0), (0.0, 0.0, 1.0), "forward (m)"),  # seen from the manikin's right
    "front": ((1.0, 0.0, 0.0), (0.0, 0.0, 1.0), "to the manikin's left (m)"),  # seen from in front of it
}


def project(points: Sequence | np.ndarray, view: str, shift: float = 0.0) -> np.ndarray:
    """(N, 2) picture coordinates (m) of world ``points`` (N, 3) in ``view``, moved right by ``shift`` m."""
    right, up, _ = VIEWS[view]
    p = np.asarray(points, dtype=float).reshape(-1, 3)
    return np.stack([p @ np.array(right) + shift, p @ np.array(up)], axis=-1)


def draw_segments(ax, segments: Iterable[tuple], view: str, colour: str, shift: float = 0.0, **style) -> None:
    """Each (start, end) world segment as a line in ``view``; ``style`` goes to ``ax.plot`` (default: solid, 1.6)."""
    style = {"linestyle": "-", "linewidth": 1.6} | style
    for a, b in segments:
        (x0, y0), (x1, y1) = project([a, b], view, shift)
        ax.plot([x0, x1], [y0, y1], color=colour, **style)


def draw_points(ax, points: Iterable, view: str, colour: str, shift: float = 0.0, size: float = 3.0) -> None:
    """Each world point as a dot in ``view``."""
    xy = project(list(points), view, shift)
    if len(xy):
        ax.plot(xy[:, 0], xy[:, 1], "o", color=colour, markersize=size)
