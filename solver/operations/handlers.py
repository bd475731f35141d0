"""The operations but ``get`` (:mod:`.timeline`): place, reach, hold, look, step, wait, each -> its segments; and
:func:`plan`, every operation of a scenario in turn."""

from __future__ import annotations

import numpy as np

from ..collision import Box, Obstacle
from . import timing
from .objects import WorkObject, origin_of
from .schema import Operation, OperationError
from .stance import stance_for
from .take import get
from .timeline import (
    APPROACH,
    LIFT,
    SET_GAP,
    Now,
    Plan,
    Segment,
    carried_box,
    check_reach,
    named_object,
    obstacles_for,
    op_priority,  # fmt: skip
    segment,
    way_or_fail,
    xyz,
)
from .walking import step_first, walk
from .ways import length

SIDE = 0.10  # m: with both hands to one point, each is this far to its side of it
HAND_LOCK = ("x", "y", "z")  # a reach or hold target: the hand's position (its orientation when one is given)
ROTATION_LOCK = ("x", "y", "z", "rx", "ry", "rz")


def place(op: Operation, now: Now, objects: dict, obstacles: list) -> list[Segment]:
    """Carry the held object over its way to :data:`LIFT` m above its place, set it down, release and withdraw."""
    obj = named_object(op, objects)
    if now.holding is None or now.holding[0] != obj.name:
        raise OperationError(f"{op.label}: the hands do not hold {obj.name} (get it first)")
    _, tcps, frames = now.holding
    goal = op.to if op.to is not None else _onto(op, obj, now, objects, obstacles)
    others = obstacles_for(now, objects, obstacles, obj.name)
    origin = now.origins[obj.name]
    out = step_first(op, now, {tcp: goal + now.hands[tcp][0] - origin for tcp in tcps}, obj.mass, others)
    check_reach(op, now, goal, f"the place for {obj.name}")
    _check_fits(op, obj, goal, others)
    origin = now.origins[obj.name]  # after the steps
    above = goal + np.array([0.0, 0.0, LIFT])
    path = way_or_fail(op, origin, above, carried_box(obj), others)
    priority = op_priority(op, 1)
    shift = {tcp: now.hands[tcp][0] - origin for tcp in tcps}
    carry = {tcp: ([p + shift[tcp] for p in path], now.hands[tcp][1], frames[tcp].lock, priority) for tcp in tcps}
    out.append(segment(now, op.label, timing.move_time(length(path), "B", obj.mass, len(tcps)), carry))
    case = op.case or ("C" if op.onto in objects else "B")  # onto a part's mating frame: an exact place
    down = {tcp: ([above + shift[tcp], goal + shift[tcp]], now.hands[tcp][1], frames[tcp].lock, priority)
            for tcp in tcps}  # fmt: skip
    out.append(segment(now, op.label, timing.move_time(LIFT, case, obj.mass, len(tcps)), down))
    now.holding = None
    now.origins[obj.name] = goal
    back = {tcp: ([now.hands[tcp][0], now.hands[tcp][0] - APPROACH * now.hands[tcp][1][:, 2]], now.hands[tcp][1],
                  frames[tcp].lock, 2) for tcp in tcps}  # fmt: skip
    out.append(segment(now, op.label, timing.RELEASE_TMU * timing.TMU + timing.reach_time(APPROACH, "A"), back))
    now.free.update(tcps)  # released: the hands go where the solver finds comfortable
    return out


def _onto(op: Operation, obj: WorkObject, now: Now, objects: dict, obstacles: list) -> np.ndarray:
    """The object's middle when set onto ``op.onto``: an object's mating point (default its top middle) or an
    obstacle's top middle, plus half the object's height and :data:`SET_GAP`."""
    if op.onto in objects:
        base = objects[op.onto]
        origin = now.origins[op.onto]
        mating = base.mating if base.mating is not None else np.array([0.0, 0.0, base.size[2] / 2.0])
        return origin + base.rotation @ mating + np.array([0.0, 0.0, obj.size[2] / 2.0 + SET_GAP])
    for ob in obstacles:
        if ob.name == op.onto:
            low, high = ob.bounds()
            middle = (low + high) / 2.0
            return np.array([middle[0], middle[1], high[2] + obj.size[2] / 2.0 + SET_GAP])
    known = ", ".join([*objects, *(ob.name for ob in obstacles)])
    raise OperationError(f"{op.label}: onto: no object or obstacle named {op.onto!r} (there are: {known})")


def _check_fits(op: Operation, obj: WorkObject, goal: np.ndarray, others: list) -> None:
    """One line when the object at ``goal`` would be inside an obstacle (its bounding box, 5 mm smaller)."""
    probe = Box(goal, np.maximum(obj.size - 0.01, 1e-3), obj.rotation, name=obj.name)
    corners = probe.skeleton()
    for ob in others:
        if ob.name == op.onto:
            continue
        if float(np.min(ob.distance(corners[0], corners[1], corners[2]).distance)) < 0.0 or \
                bool(np.all(np.abs(origin_of(ob) - goal) < obj.size / 2.0)):  # fmt: skip
            raise OperationError(f"{op.label}: {obj.name} placed at [{xyz(goal)}] m would be inside {ob.name} "
                                 "(unreachable place)")  # fmt: skip


def _hands_of(op: Operation) -> tuple[str, ...]:
    return {"both": ("hand_r", "hand_l"), "left": ("hand_l",)}.get(op.hands, ("hand_r",))


def reach(op: Operation, now: Now, objects: dict, obstacles: list, hold: float = 0.0) -> list[Segment]:
    """A hand (or both, :data:`SIDE` m either side) to ``op.to``, then held there ``hold`` s."""
    if now.holding is not None and set(_hands_of(op)) & set(now.holding[1]):
        raise OperationError(f"{op.label}: the hand holds {now.holding[0]} (place it first)")
    tcps = _hands_of(op)
    others = obstacles_for(now, objects, obstacles, None)
    lock = ROTATION_LOCK if op.rotation is not None else HAND_LOCK
    goals = {tcp: op.to + (np.array([SIDE if tcp == "hand_l" else -SIDE, 0.0, 0.0]) if len(tcps) == 2 else 0.0)
             for tcp in tcps}  # fmt: skip
    out = step_first(op, now, goals, 0.0, others)
    moves, longest = {}, 0.0
    for tcp, goal in goals.items():
        check_reach(op, now, goal, f"the {tcp} target")
        points = way_or_fail(op, now.hands[tcp][0], goal, None, others)
        rotation = op.rotation if op.rotation is not None else now.hands[tcp][1]
        moves[tcp] = (points, rotation, lock, op_priority(op, 2))
        longest = max(longest, timing.reach_time(length(points), op.case or "B"))
    out.append(segment(now, op.label, longest, moves))
    if hold > 0:
        out.append(segment(now, op.label, hold))
    return out


def hold(op: Operation, now: Now, objects: dict, obstacles: list) -> list[Segment]:
    """Reach, hold ``op.hold`` s (default 1 s), then let go (the hands free again)."""
    out = reach(op, now, objects, obstacles, op.hold)
    now.free.update(_hands_of(op))
    return out


def look(op: Operation, now: Now, objects: dict, obstacles: list) -> list[Segment]:
    """Gaze at ``op.at`` from now on (the eyes' view axis aimed at it): MTM-1 eye travel and focus."""
    eyes = sum(now.feet.values()) / len(now.feet) + np.array([0.0, 0.0, 1.6])
    before = now.gaze if now.gaze is not None else eyes + np.array([0.0, -1.0, -0.3])
    travel = float(np.linalg.norm(op.at - before))
    now.gaze = np.asarray(op.at, dtype=float)
    now.gaze_until = 1
    return [segment(now, op.label, timing.eye_time(travel, float(np.linalg.norm(op.at - eyes))))]


def step(op: Operation, now: Now, objects: dict, obstacles: list) -> list[Segment]:
    """Walk to the stance ``op.to`` (the feet's middle), a pace at a time (:func:`.walking.walk`)."""
    return walk(now, op.label, stance_for(now.feet, op.to)) or [segment(now, op.label, timing.MIN_DURATION)]


def wait(op: Operation, now: Now, objects: dict, obstacles: list) -> list[Segment]:
    """Stay as you are ``op.duration`` s (default 1 s)."""
    return [segment(now, op.label, op.duration if op.duration is not None else 1.0)]


HANDLERS = {"get": get, "place": place, "reach": reach, "hold": hold, "look": look, "step": step, "wait": wait}


def plan(operations: list[Operation], objects: dict[str, WorkObject], hands: dict, feet: dict,
         obstacles: list[Obstacle], finder=None) -> Plan:  # fmt: skip
    """The segments of ``operations`` from the hands' (tcp -> (position, rotation)) and feet's (tcp -> position)
    start; ``obstacles``: the scenario's; ``finder``: the stance finder (:class:`.stance.StanceFinder`; None: an
    operation beyond a comfortable reach does not step first)."""
    now = Now({h: (p, r, ("x", "y", "z"), 2) for h, (p, r) in hands.items()}, dict(feet), objects)
    now.finder = finder
    segments: list[Segment] = []
    spans = []
    for op in operations:
        before, start = len(segments), now.t
        segments.extend(HANDLERS[op.do](op, now, objects, obstacles))
        now.gaze_until -= 1
        if now.gaze_until < 0:  # a look holds the gaze through the operation after it, then the eyes are free
            now.gaze = None
        made = segments[before:]
        if op.duration is not None and made:  # the operation's own duration: its segments scaled to it
            scale = op.duration / max(now.t - start, 1e-9)
            for s in made:
                s.t0, s.t1 = start + (s.t0 - start) * scale, start + (s.t1 - start) * scale
            now.t = start + op.duration
        spans.append((op.label, start, now.t))
    return Plan(segments, objects, spans, now.notes)
