"""The skinned human's twist helper bones (bpy): ``<bone>.twist`` for the upper arms, forearms and thighs.

Each is a hidden child of its bone at the bone's rest frame, and a driver keeps its y rotation at -(1 - share) of
the bone's own y rotation (the bone's twist, applied first; ``rigging/skin.py``), so the helper turns by ``share``
of the twist and the skin it carries (the segment's proximal part) twists half as far as the bone. The driver's
expression is a simple one, evaluated by Blender without Python (it runs with Python scripts disabled too).
"""

from __future__ import annotations

import bpy

from ..rigging.bones import RigLayout
from ..rigging.skin import TWIST_CHANNEL, TWIST_SHARE, twist_bones, twist_name

VARIABLE = "twist"


def add_twist_bones(arm: bpy.types.Object, layout: RigLayout) -> list[str]:
    """In edit mode: a helper bone under each twisting bone of ``layout``; their names."""
    edit = arm.data.edit_bones
    names = []
    for bone in twist_bones(layout):
        parent = edit[bone]
        helper = edit.new(twist_name(bone))
        helper.head, helper.tail, helper.roll = parent.head, parent.tail, parent.roll
        helper.length = 0.5 * parent.length  # shorter than its bone, so the two stay apart in the viewport
        helper.parent = parent
        helper.use_deform = True
        names.append(helper.name)
    return names


def drive_twist_bones(arm: bpy.types.Object, names: list[str]) -> None:
    """In object mode: hide the helpers, lock all but their twist channel and drive it from their bones."""
    for name in names:
        bone = name.removesuffix(twist_name(""))
        arm.data.bones[name].hide = True
        pb = arm.pose.bones[name]
        pb.rotation_mode = "XYZ"
        pb.lock_location = pb.lock_scale = (True, True, True)
        pb.lock_rotation = (True, False, True)
        driver = pb.driver_add("rotation_euler", TWIST_CHANNEL).driver
        driver.type = "SCRIPTED"
        variable = driver.variables.new()
        variable.name = VARIABLE
        variable.type = "SINGLE_PROP"
        variable.targets[0].id_type = "OBJECT"
        variable.targets[0].id = arm
        path = f'pose.bones["{bpy.utils.escape_identifier(bone)}"].rotation_euler[{TWIST_CHANNEL}]'
        variable.targets[0].data_path = path
        driver.expression = f"{TWIST_SHARE - 1.0:g}*{VARIABLE}"
