"""The sidebar's "Reach Envelope" panel: the active manikin's reach envelope computed in the background
(:mod:`.control`), its progress, Cancel, and how the last one ended. Imports only bpy and light modules."""

from __future__ import annotations

import bpy

from ..scene.help import draw_help
from ..scene.schema import rig_of
from . import control


class MANIKIN_PT_envelope(bpy.types.Panel):
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Manikin"
    draw_header_preset = draw_help  # the help button (scene/help.py)
    bl_label = "Reach Envelope"
    bl_parent_id = "MANIKIN_PT_main"
    bl_order = 8  # after the population study (pose/panels.py lists the others' places)
    bl_options = {"DEFAULT_CLOSED"}

    @classmethod
    def poll(cls, context: bpy.types.Context) -> bool:
        settings = getattr(context.scene, "manikin_envelope", None)
        return settings is not None and (rig_of(context.active_object) is not None or control.is_running())

    def draw(self, context: bpy.types.Context) -> None:
        s = context.scene.manikin_envelope
        layout = self.layout
        col = layout.column()
        col.use_property_split = True
        for name in ("hand", "feet", "load_kg", "frequency", "hemisphere", "tolerance", "sole_scale", "folder"):
            col.prop(s, name)
        row = layout.row(align=True)
        row.scale_y = 1.3
        if control.is_running():
            row.operator("manikin.envelope_cancel", icon="CANCEL")
            layout.label(text=control.current_job().line(), icon="TIME")
            return
        row.operator("manikin.envelope_compute", icon="MESH_UVSPHERE")
        if s.status:
            layout.label(text=s.status, icon="ERROR" if s.status.startswith("Envelope failed") else "INFO")


classes = (MANIKIN_PT_envelope,)
