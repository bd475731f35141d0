"""Where the feet go for a ``step``: ONE call site for the stance finder, and the steps between two stances.

Until ``solver.stance.find_stance`` (being built) lands, a step's stance is the one the operation gives (the
middle between the feet, ``to = [x, y]``), the feet kept at their spacing and facing. The way there is a walk:
paces of at most :data:`PACE` m, one foot at a time (the other the only support), each foot lifted
:data:`LIFT` m at mid-swing on a minimum-jerk path, MTM-1 W-P (15 TMU) a pace.
"""

from __future__ import annotations

import math

import numpy as np

PACE = 0.45  # m: the longest pace (a foot's travel)
LIFT = 0.05  # m: a swinging foot's height at mid-swing


def stance_for(feet: dict[str, np.ndarray], to: np.ndarray) -> dict[str, np.ndarray]:
    """The feet's positions (3,) m for a step to ``to`` (x, y of their middle): the call site for find_stance."""
    middle = sum(feet.values()) / len(feet)
    shift = np.array([to[0] - middle[0], to[1] - middle[1], 0.0])
    return {tcp: p + shift for tcp, p in feet.items()}


def paces(start: dict[str, np.ndarray], goal: dict[str, np.ndarray]) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """The swings from ``start`` to ``goal`` feet: (foot TCP, from (3,), to (3,)), alternating, the leading foot
    (the one on the side the stance moves to) first, each at most :data:`PACE` m (step-to gait)."""
    travel = max(float(np.linalg.norm(goal[t] - start[t])) for t in goal)
    if travel < 1e-3:
        return []
    count = max(1, math.ceil(travel / PACE))
    direction = sum(goal.values()) / len(goal) - sum(start.values()) / len(start)
    order = sorted(goal, key=lambda t: -float((start[t] - sum(start.values()) / len(start)) @ direction))
    out = []
    for j in range(1, count + 1):  # step-to: each foot in turn to the same share of the way
        for foot in order:
            out.append((foot, start[foot] + (goal[foot] - start[foot]) * (j - 1) / count,
                        start[foot] + (goal[foot] - start[foot]) * j / count))
    return out


def swing_at(start: np.ndarray, goal: np.ndarray, share: float) -> np.ndarray:
    """A swinging foot at ``share`` (0..1, already min-jerk shaped) of its way: lifted at mid-swing."""
    p = start + (goal - start) * share
    return p + np.array([0.0, 0.0, LIFT * math.sin(math.pi * share)])
