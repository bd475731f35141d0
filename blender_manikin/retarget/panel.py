"""The Retarget panel of the Manikin sidebar tab: with a manikin selected, Add Target Rig; with another armature
selected, its source manikin, options, the editable bone map (a list: our bone, their bone) and Retarget."""

from __future__ import annotations

import bpy

from ..scene.help import draw_help
from ..scene.schema import is_manikin, last_retarget, rig_of


class MANIKIN_UL_bone_map(bpy.types.UIList):
    """One row per bone of the manikin: its name and the target's bone (searchable among the armature's bones)."""

    def draw_item(self, context, layout, data, item, icon, active_data, active_property, index=0, flt_flag=0):
        row = layout.split(factor=0.4)
        row.label(text=item.ours, icon="BONE_DATA" if item.theirs else "DOT")
        row.prop_search(item, "theirs", item.id_data.data, "bones", text="")


class MANIKIN_PT_retarget(bpy.types.Panel):
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Manikin"
    bl_label = "Retarget"
    bl_parent_id = "MANIKIN_PT_main"
    bl_order = 6  # the places of the subpanels: pose/panels.py
    bl_options = {"DEFAULT_CLOSED"}
    draw_header_preset = draw_help  # the help button (scene/help.py)

    @classmethod
    def poll(cls, context: bpy.types.Context) -> bool:
        ob = context.active_object
        return rig_of(ob) is not None or (ob is not None and ob.type == "ARMATURE")

    def draw(self, context: bpy.types.Context) -> None:
        layout = self.layout
        ob = context.active_object
        if rig_of(ob) is not None:
            layout.operator_menu_enum(
                "manikin.add_retarget_rig", "rig", text="Add Target Rig", icon="OUTLINER_OB_ARMATURE"
            )
            layout.label(text="Then select a rig or your character and Retarget", icon="INFO")
            return
        settings = ob.manikin_retarget
        layout.prop(settings, "source")
        if settings.source is None and not any(is_manikin(o) for o in context.scene.objects):
            layout.label(text="Add a manikin and bake a motion first", icon="INFO")
        row = layout.row(align=True)
        row.prop(settings, "pin_feet", toggle=True)
        row.prop(settings, "pin_hands", toggle=True)
        sub = layout.row()
        sub.active = settings.pin_hands
        sub.prop(settings, "hand_goals")
        layout.template_list("MANIKIN_UL_bone_map", "", settings, "bones", settings, "active_index", rows=6)
        row = layout.row(align=True)
        row.operator("manikin.auto_fill_bone_map", text="Auto-Fill", icon="AUTO")
        row.operator("manikin.load_bone_map", text="Load", icon="IMPORT")
        row.operator("manikin.save_bone_map", text="Save", icon="EXPORT")
        row = layout.row()
        row.scale_y = 1.3
        row.operator("manikin.retarget", icon="ARMATURE_DATA")
        done = last_retarget(ob)
        if done is not None:
            layout.label(text=f"{done['source']} {done['frame_start']}-{done['frame_end']}: {done['bones']} bones, "
                              f"leg ratio {done['ratio']:.3f}", icon="CHECKMARK")  # fmt: skip


classes = (MANIKIN_UL_bone_map, MANIKIN_PT_retarget)
