"""``get``: reach to before the grasp, approach and grasp, lift, bring the object before the belly; a step first
when the grasp is beyond a comfortable planted reach. Units: m, s."""

from __future__ import annotations

import numpy as np

from . import timing
from .objects import WorkObject, grasp_for, world_hand
from .schema import Operation, OperationError
from .timeline import (
    APPROACH,
    CARRY,
    LIFT,
    Now,
    Segment,
    carried_box,
    check_inside,
    check_reach,
    named_object,
    obstacles_for,
    op_priority,
    segment,
    way_or_fail,
)
from .walking import step_first
from .ways import length


def get(op: Operation, now: Now, objects: dict, obstacles: list) -> list[Segment]:
    """Reach to 6 cm before the grasp, approach and grasp, lift the object :data:`LIFT` m."""
    obj = named_object(op, objects)
    if now.holding is not None:
        raise OperationError(f"{op.label}: the hands hold {now.holding[0]} already (place it first)")
    grasp = grasp_for(obj, op.grasp, op.hands)
    if grasp is None:
        known = ", ".join(obj.grasps) or "none"
        raise OperationError(f"{op.label}: {obj.name} has no grasp {op.grasp or 'for hands = ' + op.hands!r} "
                             f"(its grasps: {known})")  # fmt: skip
    origin, rotation = now.origins[obj.name], obj.rotation
    at = {tcp: world_hand(origin, rotation, frame) for tcp, frame in grasp.hands.items()}
    others = obstacles_for(now, objects, obstacles, obj.name)
    check_inside(op, at, others, f"grasp {grasp.name!r} of {obj.name}")
    out = step_first(op, now, {tcp: p for tcp, (p, _) in at.items()}, 0.0, others)
    for tcp, (p, _) in at.items():
        check_reach(op, now, p, f"the {tcp} grasp of {obj.name}")
    case = op.case or "B"
    priority = op_priority(op, 1)
    before = {tcp: p - APPROACH * r[:, 2] for tcp, (p, r) in at.items()}
    moves, longest = {}, 0.0
    for tcp, p in before.items():
        points = way_or_fail(op, now.hands[tcp][0], p, None, others)
        moves[tcp] = (points, at[tcp][1], grasp.hands[tcp].lock, priority)
        low = min(p[2], now.hands[tcp][0][2]) < timing.BEND_HEIGHT
        longest = max(longest, timing.reach_time(length(points), case) + (timing.BEND_TMU * timing.TMU if low else 0))
    now.taking = (obj.name, len(grasp.hands))
    out.append(segment(now, op.label, longest, moves))
    grip = timing.JUMBLED_GRASP_TMU if case == "C" else timing.GRASP_TMU
    closing = {tcp: ([before[tcp], p], r, grasp.hands[tcp].lock, priority) for tcp, (p, r) in at.items()}
    out.append(segment(now, op.label, timing.reach_time(APPROACH, "A") + grip * timing.TMU, closing))
    frames = dict(grasp.hands, rotation=rotation)
    now.holding = (obj.name, tuple(grasp.hands), frames)
    up = np.array([0.0, 0.0, LIFT])
    lifting = {tcp: ([p, p + up], r, grasp.hands[tcp].lock, priority) for tcp, (p, r) in at.items()}
    out.append(segment(now, op.label, timing.move_time(LIFT, "B", obj.mass, len(at)), lifting))
    out.append(to_carry(op, now, obj, others))
    now.taking = None
    return out


def to_carry(op: Operation, now: Now, obj: WorkObject, others: list) -> Segment:
    """The held object brought to :data:`CARRY` in front of the feet's middle (the body faces -y), so that a walk
    carries it there (MTM-1 move B with its weight)."""
    name, tcps, frames = now.holding
    origin = now.origins[name]
    middle = sum(now.feet.values()) / len(now.feet)
    goal = middle + CARRY
    path = way_or_fail(op, origin, goal, carried_box(obj), others)
    moves = {tcp: ([p + now.hands[tcp][0] - origin for p in path], now.hands[tcp][1], frames[tcp].lock,
                   now.hands[tcp][3]) for tcp in tcps}  # fmt: skip
    return segment(now, op.label, timing.move_time(length(path), "B", obj.mass, len(tcps)), moves)
