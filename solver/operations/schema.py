"""``[[objects]]``, ``[[operations]]`` and ``[operate]`` read from a scenario file (every key checked, every problem
one ScenarioError line naming the file and the key). Units: m, s, kg; rotations are quaternions (w, x, y, z).

    [operate]
    fps = 24                    # frames a second of the generated motion
    [[objects]]
    name = "box"
    kind = "box"                # any obstacle kind and its keys (box, cylinder, capsule, sphere, mesh)
    center = [0.0, -0.5, 0.27]
    size = [0.35, 0.26, 0.24]
    mass = 8.0                  # kg
    mating = [0.0, 0.0, 0.12]   # optional: where a part placed onto this one goes (its frame), default its top
    [[objects.grasps]]          # optional: none given, grasps are proposed from the geometry
    name = "sides"
    hand_r = { position = [-0.202, 0, 0], rotation = [0.7071068, 0, 0.7071068, 0], lock = ["x", "y", "z", "rx", "ry"] }
    [[operations]]
    do = "get"                  # get, place, reach, hold, look, step (walk), wait
    object = "box"
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..collision import KINDS
from ..errors import ScenarioError
from ..io.scenario.obstacles import kind_keys, read_obstacles
from ..io.table_reader import TableReader
from ..options import AXES
from ..problem.specs import MAX_DISTANCE, PRIORITIES
from .objects import Grasp, HandFrame, WorkObject, propose_grasps

DOES = ("get", "place", "reach", "hold", "look", "step", "walk", "wait")
HANDS = ("auto", "both", "right", "left")
OPERATION_KEYS = {"do", "object", "grasp", "hands", "to", "onto", "rotation", "at", "duration", "hold", "priority",
                  "case", "name"}  # fmt: skip
OBJECT_KEYS = {"mass", "grasps", "mating"}
MAX_DURATION = 600.0  # s, one operation
MAX_FPS = 240


@dataclass(frozen=True)
class Operation:
    """One ``[[operations]]`` entry: ``label`` names it in messages ("operations[2] (place box)")."""

    label: str
    do: str
    object: str | None = None
    grasp: str | None = None
    hands: str = "auto"
    to: np.ndarray | None = None
    onto: str | None = None
    rotation: np.ndarray | None = None
    at: np.ndarray | None = None
    duration: float | None = None
    hold: float = 1.0
    priority: int | None = None
    case: str | None = None


@dataclass(frozen=True)
class Operate:
    """``[operate]``: frames a second and the first frame's number."""

    fps: float = 24.0
    start: int = 1


def read_operate(root: TableReader) -> Operate:
    t = root.table("operate")
    t.known({"fps", "start"})
    return Operate(t.number("fps", 24.0, 1.0, MAX_FPS, "frames/s"), t.integer("start", 1, -100000, 100000))


def read_objects(root: TableReader, folder: Path) -> tuple[dict[str, WorkObject], list[str]]:
    """The objects by name, and a line per object whose grasps were proposed from its geometry."""
    tables = root.table_list("objects")
    shapes = read_obstacles([_shape_table(t) for t in tables], folder)
    out: dict[str, WorkObject] = {}
    made = []
    for t, shape in zip(tables, shapes, strict=True):
        if "name" not in t.data:
            raise t.fail("name", "a name for the object (operations name it)")
        mating = t.vector("mating", 3, limit=MAX_DISTANCE, unit="m") if "mating" in t.data else None
        obj = WorkObject(shape.name, shape, t.number("mass", 0.0, 0.0, 1000.0, "kg"), {}, mating)
        grasps = {g.name: g for g in (_read_grasp(g, i) for i, g in enumerate(t.table_list("grasps")))}
        if not grasps:
            grasps = propose_grasps(obj)
            made.append(f"{obj.name}: no grasps given; proposed from its {shape.kind}: " + ", ".join(grasps))
        out[obj.name] = WorkObject(obj.name, shape, obj.mass, grasps, mating)
    return out, made


def _shape_table(t: TableReader) -> TableReader:
    """The object's table without its own keys: the obstacle reader reads the rest (its kind's keys)."""
    kind = t.choice("kind", KINDS, "the kind of object (an obstacle kind)")
    t.known(kind_keys(kind) | OBJECT_KEYS)
    return TableReader(t.path, {k: v for k, v in t.data.items() if k not in OBJECT_KEYS}, t.prefix, t.error)


def _read_grasp(t: TableReader, index: int) -> Grasp:
    """One ``[[objects.grasps]]``: name and a table per hand TCP (hand_r, hand_l)."""
    t.known({"name", "hand_r", "hand_l"})
    hands = {}
    for tcp in ("hand_r", "hand_l"):
        if tcp in t.data:
            h = t.table(tcp)
            h.known({"position", "rotation", "lock"})
            h.required("position")
            rotation = h.rotation("rotation")
            hands[tcp] = HandFrame(h.vector("position", 3, limit=MAX_DISTANCE, unit="m"),
                                   np.eye(3) if rotation is None else rotation, h.lock("lock", AXES))  # fmt: skip
    if not hands:
        raise t.fail("hand_r", "a frame for hand_r, hand_l or both")
    return Grasp(t.string("name", f"grasp {index + 1}"), hands)


def read_operations(root: TableReader) -> list[Operation]:
    """The ``[[operations]]`` in order; at least one."""
    out = []
    for i, t in enumerate(root.table_list("operations", non_empty=True)):
        t.known(OPERATION_KEYS)
        do = t.choice("do", DOES, "an operation")
        do = "step" if do == "walk" else do
        obj = t.string("object") if "object" in t.data else None
        label = f"operations[{i}] ({t.string('name', do + (f' {obj}' if obj else ''))})"
        if do in ("get", "place") and obj is None:
            raise t.fail("object", f"the object to {do}")
        needs = {"reach": "to", "hold": "to", "look": "at", "step": "to"}.get(do)
        if needs and needs not in t.data:
            raise t.fail(needs, f"where to {do} ({'[x, y] of the feet' if do == 'step' else '[x, y, z] m'})")
        if do == "place" and ("to" in t.data) == ("onto" in t.data):
            raise t.fail("to", "exactly one of to = [x, y, z] (the object's middle, m) or onto = NAME")
        to = None
        if "to" in t.data:
            to = t.vector("to", 2, limit=MAX_DISTANCE, unit="m") if do == "step" else \
                t.vector("to", 3, limit=MAX_DISTANCE, unit="m")  # fmt: skip
        out.append(Operation(
            label=label, do=do, object=obj, grasp=t.string("grasp") if "grasp" in t.data else None,
            hands=t.choice("hands", HANDS, "which hand") if "hands" in t.data else "auto", to=to,
            onto=t.string("onto") if "onto" in t.data else None, rotation=t.rotation("rotation"),
            at=t.vector("at", 3, limit=MAX_DISTANCE, unit="m") if "at" in t.data else None,
            duration=t.number("duration", None, 0.0, MAX_DURATION, "s") if "duration" in t.data else None,
            hold=t.number("hold", 1.0, 0.0, MAX_DURATION, "s"), priority=_priority(t),
            case=t.choice("case", ("A", "B", "C"), "an MTM-1 case") if "case" in t.data else None,
        ))
    return out


def _priority(t: TableReader) -> int | None:
    if "priority" not in t.data:
        return None
    value = t.get("priority")
    if isinstance(value, bool) or value not in PRIORITIES:
        raise t.fail("priority", "1 (must hold) or 2 (as close as possible)", value)
    return int(value)


class OperationError(ScenarioError):
    """A bad operation: one line naming it (an unknown object, an unreachable place, a grasp inside an obstacle)."""
