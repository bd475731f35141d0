"""Walking as a person does with a load, and a step first to a stance found for an operation's hands (the
stance finder: :class:`.stance.StanceFinder`). Units: m, s."""

from __future__ import annotations

import numpy as np

from ..collision import Box
from . import timing
from .schema import Operation
from .stance import beyond_comfort, paces
from .timeline import Now, Segment, segment

BACK_STEP, BACK_MOST = 0.05, 0.5  # m: a found stance moved back this much at a time so the held object is clear
HELD_ROOM = 0.03  # m: ... by this much
SHIFT_SHARE = 1.0 / 3.0  # of a pace's time: the weight shift before the foot lifts (the rest: its swing)


def walk(now: Now, label: str, goal: dict[str, np.ndarray]) -> list[Segment]:
    """Paces from the feet now to ``goal`` (tcp -> (3,) m): before a foot lifts the weight is shifted over the other
    (the held object and targeted hands go over it, both feet on the floor), then the foot swings; at the end the
    body comes back over the feet's middle. [] when the feet are there already."""
    out = []
    over = sum(now.feet.values()) / len(now.feet)  # the point the body is over (the hands go along)
    pace = timing.walk_time(1)
    for foot, start, end in paces(dict(now.feet), goal):
        pace = pace_time(end - start)
        stance = next(p for t, p in now.feet.items() if t != foot)
        out.append(shift(now, label, over, stance, pace * SHIFT_SHARE))
        over = stance
        out.append(segment(now, label, pace * (1.0 - SHIFT_SHARE), None, {foot: end}))
    if out:
        out.append(shift(now, label, over, sum(now.feet.values()) / len(now.feet), pace * SHIFT_SHARE))
    return out


def pace_time(travel: np.ndarray) -> float:
    """A foot's pace of ``travel`` (3,) m, in s: mostly sideways (across the facing, -y) half an MTM-1 side step
    SS-C2 of that length (the lead and the lagging foot each take half), else a W-P pace."""
    if abs(float(travel[0])) > abs(float(travel[1])):
        return timing.side_step_time(float(np.hypot(travel[0], travel[1]))) / 2.0
    return timing.walk_time(1)


def shift(now: Now, label: str, before: np.ndarray, after: np.ndarray, duration: float) -> Segment:
    """A weight shift (both feet down): the targeted hands moved by ``after`` - ``before`` along the floor."""
    move = np.array([after[0] - before[0], after[1] - before[1], 0.0])
    moves = {tcp: ([p, p + move], r, lock, pr) for tcp, (p, r, lock, pr) in now.hands.items() if tcp not in now.free}
    return segment(now, label, duration, moves)


def step_first(op: Operation, now: Now, hands: dict[str, np.ndarray], mass: float, others: list) -> list[Segment]:
    """When ``hands`` (tcp -> target (3,) m) are beyond a comfortable planted reach: the paces to the stance the
    stance finder finds for them (holding ``mass`` kg, clear of ``others``), noted; else []."""
    if now.finder is None or not beyond_comfort(now.feet, list(hands.values())):
        return []
    goal, line = now.finder(now.feet, hands, mass, others)
    goal, back = _held_clear(now, goal, others)
    if back > 0:
        line += f"; then {back:.2f} m back, so the {now.holding[0]} held before the body is clear"
    out = walk(now, op.label, goal)
    if out:
        now.notes.append(f"{op.label}: stepped first to a stance found for it ({line})")
    return out


def _held_clear(now: Now, goal: dict[str, np.ndarray], others: list) -> tuple[dict[str, np.ndarray], float]:
    """``goal`` moved back (against the facing, -y) by :data:`BACK_STEP` m at a time, :data:`BACK_MOST` m at most,
    until the held object, carried along with the body there, is clear of ``others``; and how far back (m)."""
    if now.holding is None:
        return goal, 0.0
    name = now.holding[0]
    obj = now.objects[name]
    middle = sum(now.feet.values()) / len(now.feet)
    back = 0.0
    while back < BACK_MOST - 1e-9:
        moved = sum(goal.values()) / len(goal) - middle + np.array([0.0, back, 0.0])
        if _clear(Box(now.origins[name] + moved * np.array([1.0, 1.0, 0.0]), obj.size, obj.rotation), others):
            break
        back += BACK_STEP
    return {t: p + np.array([0.0, back, 0.0]) for t, p in goal.items()}, back


def _clear(box: Box, others: list) -> bool:
    """Whether ``box`` is at least :data:`HELD_ROOM` m clear of every obstacle in ``others``."""
    a, b, r = box.skeleton()
    return all(float(np.min(ob.distance(a, b, r).distance)) >= HELD_ROOM for ob in others)
