"""The way a hand (or a carried object's middle) takes between two points: ONE call site for the path planner.

Until the collision-free planner (:mod:`solver.planning`, being built) lands, a way is the straight line, lifted
over what is in between: when the segment between the points passes through an obstacle (the carried object's
half size as clearance), it goes up over the obstacle's top and down again (three legs). A way that still passes
through something comes back as "blocked by NAME", which the operation reports.
"""

from __future__ import annotations

import numpy as np

from ..collision import Obstacle

CLEAR = 0.03  # m kept above an obstacle's top on a lifted way
DEPTH = 0.01  # m: a way may graze (an object set down on its support touches it)


def way(start: np.ndarray, goal: np.ndarray, carried: np.ndarray | None,
        obstacles: list[Obstacle]) -> list[np.ndarray] | str:  # fmt: skip
    """Points from ``start`` to ``goal`` (m, both included), or "blocked by NAME". ``carried``: the carried
    object's half size (3,) m around the points (None: a hand alone, kept 5 cm clear)."""
    start, goal = np.asarray(start, dtype=float), np.asarray(goal, dtype=float)
    # a carried object as a ball of its half height about its middle: right below and above it, short at its sides
    below = reach = 0.05 if carried is None else float(np.asarray(carried)[2])
    hit = _first_hit([start, goal], reach, obstacles)
    if hit is None:
        return [start, goal]
    top = max(float(hit.bounds()[1][2]), start[2] - below, goal[2] - below) + below + CLEAR
    over = [start, np.array([*start[:2], top]), np.array([*goal[:2], top]), goal]
    blocker = _first_hit(over, reach, obstacles)
    return over if blocker is None else f"blocked by {blocker.name}"


def _first_hit(points: list[np.ndarray], radius: float, obstacles: list[Obstacle]) -> Obstacle | None:
    """The first obstacle a capsule of ``radius`` m along the polyline ``points`` enters, else None."""
    for a, b in zip(points[:-1], points[1:], strict=True):
        if np.allclose(a, b):
            continue
        for ob in obstacles:
            found = ob.distance(a[None], b[None], np.array([radius]))
            if float(np.min(found.distance)) < -DEPTH:
                return ob
    return None


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
