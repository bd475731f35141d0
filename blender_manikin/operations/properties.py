"""Settings of the "Operations" panel: a mesh marked as an object (``Object.manikin_object``: its mass; its child
empties named ``grasp_*`` are its grasps) and the scene's operation list (``Scene.manikin_operations``). The
operation kinds and hand choices are the scenario schema's (:mod:`solver.operations.schema`, read here as names
only). Imports only bpy."""

from __future__ import annotations

import re

import bpy
from bpy.props import (
    BoolProperty,
    CollectionProperty,
    EnumProperty,
    FloatProperty,
    IntProperty,
    PointerProperty,
    StringProperty,
)

DOES = (  # the schema's DOES (walk is step there): (id, label, description)
    ("GET", "Get", "Reach to the object's grasp, close the hands, lift it and bring it before the belly"),
    ("PLACE", "Place", "Carry the held object to the target (an empty: its middle goes there; an object or obstacle: "
                       "onto it) and release it"),
    ("REACH", "Reach", "A hand (or both) to the target empty; it stays there"),
    ("HOLD", "Hold", "A hand (or both) to the target empty, held there for Hold seconds"),
    ("LOOK", "Look", "Aim the eyes at the target"),
    ("STEP", "Step", "Step to a stance: the feet's middle to the target's x, y"),
    ("WALK", "Walk", "As Step (paces of at most 0.45 m)"),
    ("WAIT", "Wait", "Stay (Duration, default 1 s)"),
)
HANDS = (
    ("AUTO", "Auto", "Both for an object over 3 kg or wider than 0.3 m, else the right; a reach: the right"),
    ("BOTH", "Both", "Both hands"),
    ("RIGHT", "Right", "The right hand"),
    ("LEFT", "Left", "The left hand"),
)
PRIORITIES = (
    ("DEFAULT", "Default", "Hands on a held object must hold (1); a reach as close as possible (2)"),
    ("1", "Must hold", "Priority 1: the solve must meet it"),
    ("2", "As close as possible", "Priority 2: met as closely as the rest allows"),
)
GRASP = re.compile(r"^grasp(?:_(?P<name>.+?))?_(?P<hand>[lr])(?:\.\d{3})?$")  # a grasp empty (objects.py)
NEEDS_OBJECT = {"GET", "PLACE"}
NEEDS_TARGET = {"PLACE", "REACH", "HOLD", "LOOK", "STEP", "WALK"}
HAS_HANDS = {"GET", "REACH", "HOLD"}


def is_work_object(ob: bpy.types.Object | None) -> bool:
    """A mesh marked as an object operations handle."""
    return ob is not None and ob.type == "MESH" and ob.manikin_object.enabled


def _object_poll(self, ob: bpy.types.Object) -> bool:
    return is_work_object(ob)


def _target_poll(self, ob: bpy.types.Object) -> bool:
    return ob.type in {"EMPTY", "MESH"}


class MANIKIN_PG_object(bpy.types.PropertyGroup):
    """A mesh as an object of operations: its mass; its grasps are its child empties named ``grasp_*``."""

    enabled: BoolProperty(name="Object", description="Operations can get and place this mesh (its child empties "
                          "grasp_l / grasp_r, or grasp_NAME_l / grasp_NAME_r, are its grasps)")  # fmt: skip
    mass: FloatProperty(name="Mass", default=5.0, min=0.0, max=1000.0, unit="MASS", description="kg")


class MANIKIN_PG_operation(bpy.types.PropertyGroup):
    """One operation of the list (``name``: its label in messages; empty: "get box", ...)."""

    do: EnumProperty(name="Do", items=DOES, default="GET", description="What the manikin does")
    object: PointerProperty(type=bpy.types.Object, name="Object", poll=_object_poll,
                            description="The object a get or place handles")  # fmt: skip
    target: PointerProperty(type=bpy.types.Object, name="Target", poll=_target_poll,
                            description="Where: an empty (its position; a place: the object's middle), or an "
                            "object or obstacle a place puts the object onto")  # fmt: skip
    use_rotation: BoolProperty(name="Rotation", description="A reach or hold takes the target empty's rotation "
                               "too (all six axes)")  # fmt: skip
    hands: EnumProperty(name="Hands", items=HANDS, default="AUTO", description="Which hand")
    use_duration: BoolProperty(name="Own duration", description="Scale the operation to Duration instead of its "
                               "MTM-1 time (a wait's is 1 s)")  # fmt: skip
    duration: FloatProperty(name="Duration", default=1.0, min=0.0, max=600.0, unit="TIME_ABSOLUTE", description="s")
    hold: FloatProperty(name="Hold", default=1.0, min=0.0, max=600.0, unit="TIME_ABSOLUTE",
                        description="s a hold keeps the hand there")  # fmt: skip
    priority: EnumProperty(name="Priority", items=PRIORITIES, default="DEFAULT")


class MANIKIN_PG_operations(bpy.types.PropertyGroup):
    """The scene's operation list, the generator's settings and what the last run said."""

    items: CollectionProperty(type=MANIKIN_PG_operation)
    index: IntProperty(name="Operation", default=0, min=0)
    fps: IntProperty(name="Frames/s", default=24, min=1, max=240, description="Frames a second of the motion")
    folder: StringProperty(name="Output", subtype="DIR_PATH", description="Where runs go (empty: manikin_operations "
                           "beside the .blend, or in the temporary folder)")  # fmt: skip
    manikin: PointerProperty(type=bpy.types.Object, name="Manikin", description="The armature the last run keys")
    status: StringProperty(name="Status", description="How the last run ended")
    summary: StringProperty(name="Summary", description="The last run's summary lines (per operation its frames "
                            "and how many converged, the cycle time)")  # fmt: skip


classes = (MANIKIN_PG_object, MANIKIN_PG_operation, MANIKIN_PG_operations)


def attach() -> None:
    """Give every object the object settings and every scene the operation list."""
    bpy.types.Object.manikin_object = PointerProperty(type=MANIKIN_PG_object)
    bpy.types.Scene.manikin_operations = PointerProperty(type=MANIKIN_PG_operations)


def detach() -> None:
    del bpy.types.Scene.manikin_operations
    del bpy.types.Object.manikin_object
