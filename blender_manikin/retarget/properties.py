"""Retarget settings stored on a target armature (bpy): ``Object.manikin_retarget`` holds the source manikin, the
options and the user-editable bone map (one row per bone of ours: our bone, their bone or ""), so a map survives
saving and reloading the .blend. Light to import: bpy and the scene schema only."""

from __future__ import annotations

import bpy
from bpy.props import BoolProperty, CollectionProperty, EnumProperty, IntProperty, PointerProperty, StringProperty

from ..scene.schema import is_manikin


class MANIKIN_PG_bone_pair(bpy.types.PropertyGroup):
    """One row of a bone map: our bone and the target's bone that follows it."""

    ours: StringProperty(name="Manikin bone", description="The manikin's bone")
    theirs: StringProperty(name="Target bone", description="The target armature's bone that follows it (empty: none)")


def _is_manikin(_self, obj: bpy.types.Object) -> bool:
    return is_manikin(obj)


class MANIKIN_PG_retarget(bpy.types.PropertyGroup):
    """How a baked manikin motion goes onto this armature."""

    source: PointerProperty(
        name="Manikin", type=bpy.types.Object, poll=_is_manikin,
        description="The manikin whose baked motion this armature takes (default: the scene's only manikin)",
    )  # fmt: skip
    rig: StringProperty(name="Shipped rig", description="The shipped rig this armature was built as (if any)")
    bones: CollectionProperty(type=MANIKIN_PG_bone_pair, name="Bone map")
    active_index: IntProperty(name="Active row")
    pin_feet: BoolProperty(
        name="Pin feet", default=True,
        description="Where the manikin's feet are supports, put the target's feet where the manikin's (scaled) are, "
        "with a two-bone IK correction of the legs: no sliding",
    )  # fmt: skip
    pin_hands: BoolProperty(
        name="Pin hands", default=True,
        description="Put the target's wrists where the manikin's (scaled) are, with a two-bone IK correction of the "
        "arms (the hands keep the manikin's grip on what they hold)",
    )  # fmt: skip
    hand_goals: EnumProperty(
        name="Hand goals", default="AUTO",
        items=[
            ("AUTO", "Auto", "Where the manikin's hands are, scaled with the body, when the character reaches them at "
             "every frame; else arm-relative for the whole motion"),
            ("BODY", "Scaled with the body", "Where the manikin's hands are in the scene scaled by the leg-length "
             "ratio about the ankles (the hands stay on a scaled workplace; a character with relatively shorter "
             "arms falls short)"),
            ("ARM", "Arm-relative", "The manikin's shoulder-to-wrist reach scaled by the arm-length ratio, from "
             "the character's own shoulder (always within reach; the hands keep the manikin's arm posture)"),
        ],
        description="Where pinned hands go",
    )  # fmt: skip


def read_rows(arm: bpy.types.Object) -> dict[str, str]:
    """The stored bone map: our bone -> their bone (rows with no target bone left out)."""
    return {row.ours: row.theirs for row in arm.manikin_retarget.bones if row.theirs}


def write_rows(arm: bpy.types.Object, ours: list[str], bone_map: dict[str, str]) -> None:
    """Store ``bone_map`` as one row per bone of ``ours`` (then any mapped bone not in it)."""
    rows = arm.manikin_retarget.bones
    rows.clear()
    for name in [*ours, *(k for k in bone_map if k not in ours)]:
        row = rows.add()
        row.ours, row.theirs = name, bone_map.get(name, "")


classes = (MANIKIN_PG_bone_pair, MANIKIN_PG_retarget)


def attach() -> None:
    bpy.types.Object.manikin_retarget = PointerProperty(type=MANIKIN_PG_retarget)


def detach() -> None:
    del bpy.types.Object.manikin_retarget
