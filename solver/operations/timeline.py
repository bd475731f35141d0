"""Operations -> timed segments: where each hand, foot, the gaze and every object are over time. Units: m, s.

Each operation becomes a few segments (a get: reach to 6 cm before the grasp, approach and grasp, lift; a place:
carry over the way, set down, release and withdraw; a step: one segment per pace), each with an MTM-1 duration
(:mod:`.timing`; an operation's ``duration`` scales its segments to it). Within a segment every moving point
follows its way with the minimum-jerk share of the segment's time. A bad operation raises one OperationError line.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..collision import Obstacle
from ..planning import CarriedBox
from .objects import WorkObject, moved, origin_of
from .schema import Operation, OperationError
from .ways import way

APPROACH = 0.06  # m: a hand comes to a grasp from this far back along its palm normal
LIFT = 0.08  # m: an object is lifted this much off where it rests (and set down from this much above)
SET_GAP = 0.002  # m: a placed object is released this far above its support
REACH = 0.95  # m: a target farther than this (horizontally) from the feet's middle is beyond a planted reach
HIGHEST = 2.1  # m: nor higher than this
CARRY = np.array([0.0, -0.38, 1.0])  # m from the feet's middle: where a held object is carried (before the belly)


@dataclass(frozen=True)
class HandPath:
    """A hand's way in a segment: polyline ``points``, rotations from ``start`` to ``end``, its lock and priority."""

    points: list
    start: np.ndarray
    end: np.ndarray
    lock: tuple[str, ...]
    priority: int


@dataclass
class Segment:
    """``t0``..``t1`` s of operation ``label``: the hands' ways, the feet (from, to), the gaze, the object held
    (``carried``) and where the resting objects are."""

    label: str
    t0: float
    t1: float
    hands: dict[str, HandPath]
    feet: dict[str, tuple[np.ndarray, np.ndarray]]
    gaze: np.ndarray | None
    carried: tuple[str, tuple[str, ...]] | None  # (object, the hand TCPs holding it)
    resting: dict[str, np.ndarray] = field(default_factory=dict)  # object -> origin (3,) m
    taking: tuple[str, int] | None = None  # the resting object the hands close on, and how many hands (posing)


@dataclass
class Plan:
    """The segments, the objects and the operations' time spans (label, start s, end s)."""

    segments: list[Segment]
    objects: dict[str, WorkObject]
    spans: list[tuple[str, float, float]]
    notes: list[str] = field(default_factory=list)

    @property
    def duration(self) -> float:
        return self.segments[-1].t1 if self.segments else 0.0


class Now:
    """Where everything is between segments while the plan is built."""

    def __init__(self, hands: dict, feet: dict, objects: dict[str, WorkObject]) -> None:
        self.hands = hands  # tcp -> (position, rotation, lock, priority, held: bool)
        self.free = set(hands)  # hands with no target (the solver places them)
        self.feet = feet
        self.gaze: np.ndarray | None = None
        self.holding: tuple[str, tuple[str, ...], dict] | None = None  # object, hands, their frames
        self.objects = objects
        self.origins = {name: origin_of(o.shape) for name, o in objects.items()}
        self.t = 0.0
        self.taking: tuple[str, int] | None = None  # the object a get reaches for, with how many hands
        self.gaze_until = 0  # operations the gaze is still held for
        self.finder = None  # the stance finder (feet, hands, mass, obstacles) -> (feet, line); None: no stepping
        self.notes: list[str] = []  # what the plan assumed or did on its own (a step to a found stance)


def segment(now: Now, label: str, duration: float, moves: dict | None = None, feet: dict | None = None) -> Segment:
    """A segment of ``duration`` s from now: ``moves`` tcp -> (points, end rotation, lock, priority) for the hands
    that move (the other targeted hands stay), ``feet`` tcp -> end position for a foot that steps."""
    moves, feet = moves or {}, feet or {}
    hands = {}
    for tcp, (p, r, lock, priority) in now.hands.items():
        if tcp in moves:
            points, end, lock, priority = moves[tcp]
            hands[tcp] = HandPath(points, r, end, lock, priority)
            now.hands[tcp] = (points[-1], end, lock, priority)
            now.free.discard(tcp)
        elif tcp not in now.free:
            hands[tcp] = HandPath([p, p], r, r, lock, priority)
    steps = {tcp: (p, feet.get(tcp, p)) for tcp, p in now.feet.items()}
    now.feet.update(feet)
    carried = None
    if now.holding is not None:
        name, tcps, frames = now.holding
        carried = (name, tcps)
        obj_rotation = frames["rotation"]
        now.origins[name] = now.hands[tcps[0]][0] - obj_rotation @ frames[tcps[0]].position
    # the object being taken is no obstacle while the hands close on it (they grip it, 1 cm off its faces)
    resting = {n: o for n, o in now.origins.items() if carried is None or n != carried[0]}
    out = Segment(label, now.t, now.t + duration, hands, steps, now.gaze, carried, dict(resting), now.taking)
    now.t += duration
    return out


def op_priority(op: Operation, default: int) -> int:
    return op.priority if op.priority is not None else default


def obstacles_for(now: Now, objects: dict[str, WorkObject], obstacles: list[Obstacle], but: str | None) -> list:
    """The scenario's obstacles and every resting object (at its place now) but ``but``."""
    out = list(obstacles)
    for name, obj in objects.items():
        if name != but and (now.holding is None or now.holding[0] != name):
            out.append(moved(obj.shape, now.origins[name] - origin_of(obj.shape)))
    return out


def check_reach(op: Operation, now: Now, point: np.ndarray, what: str) -> None:
    """One line when ``point`` is beyond a planted reach from the feet now."""
    middle = sum(now.feet.values()) / len(now.feet)
    far = float(np.hypot(*(point[:2] - middle[:2])))
    shown = "[" + ", ".join(f"{v:.2f}" for v in point) + "]"
    if far > REACH:
        raise OperationError(f"{op.label}: {what} at {shown} m is {far:.2f} m from the feet's middle, beyond a "
                             f"planted reach of {REACH:g} m (unreachable: add a step before it)")  # fmt: skip
    if point[2] > HIGHEST:
        raise OperationError(f"{op.label}: {what} at {shown} m is higher than {HIGHEST:g} m (unreachable)")


def check_inside(op: Operation, hands: dict, others: list[Obstacle], what: str) -> None:
    """One line when a hand's palm at its grasp is inside an obstacle."""
    for tcp, (p, r) in hands.items():
        axis = p - 0.017 * r[:, 2]  # the hand capsule's axis is behind the palm
        for ob in others:
            if float(np.min(ob.distance(p[None], axis[None], np.array([0.02])).distance)) < 0.0:
                raise OperationError(f"{op.label}: {what}: {tcp} would be inside {ob.name}")


def named_object(op: Operation, objects: dict) -> WorkObject:
    if op.object not in objects:
        known = ", ".join(objects) or "none"
        raise OperationError(f"{op.label}: no object named {op.object!r} (objects: {known})")
    return objects[op.object]


def way_or_fail(op: Operation, start: np.ndarray, goal: np.ndarray, carried, obstacles: list) -> list:
    points = way(start, goal, carried, obstacles)
    if isinstance(points, str):
        raise OperationError(f"{op.label}: no way from [{xyz(start)}] to [{xyz(goal)}] m: {points}")
    return points


def xyz(p: np.ndarray) -> str:
    return ", ".join(f"{v:.2f}" for v in p)


def carried_box(obj: WorkObject) -> CarriedBox:
    """``obj`` as the planner's carried box (its edges along its axes; it does not turn on the way)."""
    return CarriedBox(np.asarray(obj.size, dtype=float), obj.rotation, name=obj.name)
