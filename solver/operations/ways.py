"""The way a hand (or a carried object's middle) takes between two points: ONE call site for the path planner,
:func:`solver.planning.find_way` (RRT-Connect in the workspace of the hand or the carried box, shortened and
smoothed; the straight line when that is free). A way that cannot be found comes back as one line naming what
blocks it ("blocked by bench: ..."), which the operation reports.

The whole body along the way is not followed here (:func:`solver.planning.follow`): every frame of the motion is
solved anyway, warm-started from the frame before, and the swept check between frames
(:mod:`solver.motion.between_frames`) is the same check ``follow`` makes, so following first would solve each
posture twice for the same answer.
"""

from __future__ import annotations

import numpy as np

from ..collision import Obstacle
from ..planning import CarriedBox, find_way


def way(start: np.ndarray, goal: np.ndarray, carried: CarriedBox | None,
        obstacles: list[Obstacle]) -> list[np.ndarray] | str:  # fmt: skip
    """Points from ``start`` to ``goal`` (m, both included), or "blocked by NAME: why". ``carried``: the box the
    hands carry, its centre on the way (None: a hand alone, its TCP on the way)."""
    found = find_way(np.asarray(start, dtype=float), np.asarray(goal, dtype=float), carried, obstacles)
    if not found.found:
        return found.blocked
    return [np.asarray(p, dtype=float) for p in found.points]


def polyline_at(points: list[np.ndarray], share: float) -> np.ndarray:
    """The point ``share`` (0..1) of the way along the polyline ``points`` by length."""
    legs = np.array([np.linalg.norm(b - a) for a, b in zip(points[:-1], points[1:], strict=True)])
    total = float(legs.sum())
    if total <= 1e-12:
        return np.asarray(points[-1], dtype=float)
    at = float(np.clip(share, 0.0, 1.0)) * total
    for (a, b), leg in zip(zip(points[:-1], points[1:], strict=True), legs, strict=True):
        if at <= leg or leg == legs[-1]:
            return a + (b - a) * (at / leg if leg > 0 else 1.0)
        at -= leg
    return np.asarray(points[-1], dtype=float)


def length(points: list[np.ndarray]) -> float:
    """The polyline's length, m."""
    return float(sum(np.linalg.norm(b - a) for a, b in zip(points[:-1], points[1:], strict=True)))
