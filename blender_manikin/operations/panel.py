"""The sidebar's "Operations" panel: the active mesh as an object (mass, grasps), the scene's operation list and the
selected operation's settings, Generate Motion with its progress, and how the last run went (per operation its
frames and converged frames, the cycle time). Imports only bpy."""

from __future__ import annotations

import bpy

from ..scene.help import draw_help
from ..scene.schema import rig_of
from . import control
from .properties import GRASP, HAS_HANDS, NEEDS_OBJECT, NEEDS_TARGET, is_work_object

SHOWN_ROWS = 5


class MANIKIN_UL_operations(bpy.types.UIList):
    """The operation list: its number, kind, object and target, and its own duration if set."""

    def draw_item(self, context, layout, data, item, icon, active_data, active_propname, index=0) -> None:
        row = layout.row(align=True)
        row.label(text=f"{index + 1}.")
        row.prop(item, "do", text="")
        used = (item.object if item.do in NEEDS_OBJECT else None, item.target if item.do in NEEDS_TARGET else None)
        what = [ob.name for ob in used if ob is not None]
        row.label(text=item.name or " > ".join(what) or "-")
        if item.use_duration:
            row.label(text=f"{item.duration:g} s")


def _grasps(ob: bpy.types.Object) -> list[str]:
    return sorted(c.name for c in ob.children if c.type == "EMPTY" and GRASP.match(c.name))


class MANIKIN_PT_operations(bpy.types.Panel):
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Manikin"
    bl_label = "Operations"
    bl_parent_id = "MANIKIN_PT_main"
    bl_order = 9  # after the reach envelope (pose/panels.py lists the others' places)
    bl_options = {"DEFAULT_CLOSED"}
    draw_header_preset = draw_help  # the help button (scene/help.py)

    @classmethod
    def poll(cls, context: bpy.types.Context) -> bool:
        s = getattr(context.scene, "manikin_operations", None)
        active = context.active_object
        return s is not None and (rig_of(active) is not None or (active is not None and active.type == "MESH")
                                  or len(s.items) > 0)  # fmt: skip

    def draw(self, context: bpy.types.Context) -> None:
        layout, s = self.layout, context.scene.manikin_operations
        ob = context.active_object
        if ob is not None and ob.type == "MESH":
            draw_object(layout.box(), ob)
        row = layout.row()
        row.template_list("MANIKIN_UL_operations", "", s, "items", s, "index", rows=SHOWN_ROWS)
        side = row.column(align=True)
        side.operator("manikin.operation_add", icon="ADD", text="")
        side.operator("manikin.operation_remove", icon="REMOVE", text="")
        side.separator()
        side.operator("manikin.operation_move", icon="TRIA_UP", text="").direction = "UP"
        side.operator("manikin.operation_move", icon="TRIA_DOWN", text="").direction = "DOWN"
        if 0 <= s.index < len(s.items):
            draw_item(layout.column(), s.items[s.index])
        layout.operator("manikin.import_operations", icon="IMPORT", text="Import Operations...")
        col = layout.column()
        col.use_property_split = True
        col.prop(s, "fps")
        col.prop(s, "folder")
        draw_run(layout, s)



def draw_object(box, ob: bpy.types.Object) -> None:
    box.prop(ob.manikin_object, "enabled", text=f"{ob.name} is an object of operations")
    if not is_work_object(ob):
        return
    box.prop(ob.manikin_object, "mass")
    grasps = _grasps(ob)
    box.label(text="Grasps: " + (", ".join(grasps) if grasps else "none (proposed when generating)"))
    box.operator("manikin.propose_grasps", icon="EMPTY_ARROWS")

def draw_item(col, item) -> None:
    col.use_property_split = True
    col.prop(item, "do")
    if item.do in NEEDS_OBJECT:
        col.prop(item, "object")
    if item.do in NEEDS_TARGET:
        col.prop(item, "target")
    if item.do in ("REACH", "HOLD"):
        col.prop(item, "use_rotation")
    if item.do in HAS_HANDS:
        col.prop(item, "hands")
    if item.do == "HOLD":
        col.prop(item, "hold")
    col.prop(item, "use_duration")
    if item.use_duration:
        col.prop(item, "duration")
    col.prop(item, "priority")
    col.prop(item, "name", text="Label")

def draw_run(layout, s) -> None:
    row = layout.row(align=True)
    row.scale_y = 1.3
    job = control.current_job()
    if control.is_running():
        row.operator("manikin.operations_cancel", icon="CANCEL")
        layout.label(text=job.line(), icon="TIME")
        return
    row.operator("manikin.operations_generate", icon="PLAY")
    if s.status:
        failed = s.status.startswith(("Generate failed", "Cancelled", "Generated, but"))
        layout.label(text=s.status, icon="ERROR" if failed else "INFO")
    for line in s.summary.splitlines():
        layout.label(text=line)


classes = (MANIKIN_UL_operations, MANIKIN_PT_operations)
