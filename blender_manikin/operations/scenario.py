"""The scene as an operations scenario (bpy): the manikin's scenario as Export Scenario writes it (its supports,
obstacles and settings; its other targets and a carried box left out: the operations give the hands their ways),
the marked objects as ``[[objects]]``, the list as ``[[operations]]`` and ``[operate]``. The same tables a TOML file
gives ``python -m solver operate``; written beside the run and read by the solver's own reader, so the file and
the panel have one code path. Every position is in the armature's space (m), as the scenario's are.
"""

from __future__ import annotations

import bpy
import numpy as np

from ...solver.body.spatial import matrix_to_quat
from ...solver.errors import UsageError
from ..scene.schema import is_obstacle
from .objects import object_table, work_objects
from .properties import HAS_HANDS, NEEDS_OBJECT, NEEDS_TARGET, is_work_object


def _floats(values) -> list[float]:
    return [float(f"{v:.7g}") for v in values]


def _where(ob: bpy.types.Object, to_local: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``ob``'s (position (3,), rotation (3, 3)) in the armature's space."""
    m = to_local @ np.array(ob.matrix_world)
    rotation = m[:3, :3] / np.linalg.norm(m[:3, :3], axis=0)
    return m[:3, 3], rotation


def label(index: int, item) -> str:
    """How the panel and the messages name the operation: "operation 2 (place box)"."""
    what = item.name or f"{item.do.lower()}" + (f" {item.object.name}" if item.object is not None else "")
    return f"operation {index + 1} ({what})"


def operation_table(index: int, item, to_local: np.ndarray) -> dict:
    """One ``[[operations]]`` table of a list item; a UsageError naming it when its object or target is missing."""
    do = item.do.lower()
    table: dict = {"do": do}
    if item.name:
        table["name"] = item.name
    if item.do in NEEDS_OBJECT:
        if item.object is None:
            raise UsageError(f"{label(index, item)}: choose the object to {do}")
        table["object"] = item.object.name
    if item.do in NEEDS_TARGET:
        target = item.target
        if target is None:
            raise UsageError(f"{label(index, item)}: choose its target (an empty{' or object' * (do == 'place')})")
        position, rotation = _where(target, to_local)
        if item.do == "PLACE" and (is_work_object(target) or is_obstacle(target)):
            table["onto"] = target.name
        elif item.do in ("STEP", "WALK"):
            table["to"] = _floats(position[:2])
        else:
            table["at" if item.do == "LOOK" else "to"] = _floats(position)
        if item.do in ("REACH", "HOLD") and item.use_rotation:
            table["rotation"] = _floats(matrix_to_quat(rotation))
    if item.do in HAS_HANDS and item.hands != "AUTO":
        table["hands"] = item.hands.lower()
    if item.use_duration:
        table["duration"] = float(f"{item.duration:.7g}")
    if item.do == "HOLD":
        table["hold"] = float(f"{item.hold:.7g}")
    if item.priority != "DEFAULT":
        table["priority"] = int(item.priority)
    return table


def operations_scenario(scene: bpy.types.Scene, arm: bpy.types.Object) -> dict:
    """The scenario dict of ``scene``'s operation list for the manikin ``arm`` (the scene at the frame it is at)."""
    from ..scenario.write import scene_scenario

    settings = scene.manikin_operations
    if not len(settings.items):
        raise UsageError("Operations: the list is empty; add an operation (+)")
    to_local = np.array(arm.matrix_world.inverted())
    objects = work_objects(scene)
    names = {ob.name for ob in objects}
    data = scene_scenario(arm)
    data["targets"] = [t for t in data.get("targets", []) if t.get("support")]
    data["obstacles"] = [o for o in data.get("obstacles", []) if o["name"] not in names]  # an object rests as one
    for key in ("targets", "obstacles", "carried"):
        if not data.get(key):
            data.pop(key, None)
    s = arm.manikin
    data["motion"] = dict(bounded=s.bound_motion, max_joint_change=float(f"{s.max_joint_change:.7g}"),
                          max_root_shift=float(f"{s.max_root_shift:.7g}"))  # fmt: skip
    if objects:
        data["objects"] = [object_table(ob, to_local) for ob in objects]
    data["operations"] = [operation_table(i, item, to_local) for i, item in enumerate(settings.items)]
    data["operate"] = dict(fps=settings.fps, start=scene.frame_start)
    return data
