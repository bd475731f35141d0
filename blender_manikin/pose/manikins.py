"""Delete Manikin and Duplicate Manikin (Object menu and the Manikin panel): a manikin as one thing.

A manikin is its armature and what belongs to it: its body objects (``DISPLAY_KEY``), its TCP empties (``TCP_KEY``),
the target, loop and load empties pointing at it, and its carried box. Blender's own X and Shift+D act on the
armature alone: X leaves the rest behind (the targets still point at the deleted armature, which stays in the
file), Shift+D makes an armature with no body and no supports. The work is in :mod:`..scene.lifecycle`, loaded
inside ``execute``.
"""

from __future__ import annotations

import bpy
from bpy.props import FloatProperty

from ..scene.schema import owner_rig


class MANIKIN_OT_delete_manikin(bpy.types.Operator):
    """Delete the manikin and everything that belongs to it: body, TCP empties, targets, loops, loads, carried box
    (also what a manikin deleted with X left behind)"""

    bl_idname = "manikin.delete_manikin"
    bl_label = "Delete Manikin"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context: bpy.types.Context) -> bool:
        if owner_rig(context.active_object) is None:
            cls.poll_message_set("Select a manikin, one of its targets or its body")
            return False
        return context.mode == "OBJECT"

    def execute(self, context: bpy.types.Context) -> set[str]:
        from ..scene.lifecycle import delete_manikin

        arm = owner_rig(context.active_object)
        name = arm.name
        count = delete_manikin(arm)
        self.report({"INFO"}, f"Deleted {name} and the {count - 1} objects that belonged to it")
        return {"FINISHED"}


class MANIKIN_OT_duplicate_manikin(bpy.types.Operator):
    """Duplicate the manikin with its own body, TCP empties, targets, loops, loads and carried box, beside it"""

    bl_idname = "manikin.duplicate_manikin"
    bl_label = "Duplicate Manikin"
    bl_options = {"REGISTER", "UNDO"}

    offset: FloatProperty(
        name="Offset", default=1.0, unit="LENGTH", description="How far to the manikin's side the copy stands (m)"
    )

    @classmethod
    def poll(cls, context: bpy.types.Context) -> bool:
        arm = owner_rig(context.active_object)
        if arm is None or not arm.users_scene:
            cls.poll_message_set("Select a manikin, one of its targets or its body")
            return False
        return context.mode == "OBJECT"

    def execute(self, context: bpy.types.Context) -> set[str]:
        from ..scene.lifecycle import duplicate_manikin

        arm = owner_rig(context.active_object)
        copy = duplicate_manikin(arm, self.offset)
        for ob in context.view_layer.objects.selected:
            ob.select_set(False)
        copy.select_set(True)
        context.view_layer.objects.active = copy
        self.report({"INFO"}, f"Duplicated {arm.name} as {copy.name}, {self.offset:g} m to its side")
        return {"FINISHED"}


def draw_object_menu(self: bpy.types.Menu, context: bpy.types.Context) -> None:
    if owner_rig(context.active_object) is not None:
        self.layout.separator()
        self.layout.operator("manikin.duplicate_manikin", icon="DUPLICATE")
        self.layout.operator("manikin.delete_manikin", icon="TRASH")


MENUS = (("VIEW3D_MT_object", draw_object_menu),)

classes = (MANIKIN_OT_delete_manikin, MANIKIN_OT_duplicate_manikin)
