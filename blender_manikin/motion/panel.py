"""The Motion panel of the Manikin sidebar tab: the frame range, Bake Motion, the per-frame change bound, and how
the last bake went (the frames that did not converge, and why)."""

import bpy

from ..scene.help import draw_help
from ..scene.schema import last_bake, rig_of

SHOWN_FAILURES = 6  # frames listed in the panel


class MANIKIN_PT_motion(bpy.types.Panel):
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Manikin"
    bl_label = "Motion"
    bl_parent_id = "MANIKIN_PT_main"
    bl_order = 4  # under the pose's result (pose/panels.py lists the places)
    draw_header_preset = draw_help  # the help button (scene/help.py)

    @classmethod
    def poll(cls, context: bpy.types.Context) -> bool:
        return rig_of(context.active_object) is not None

    def draw(self, context: bpy.types.Context) -> None:
        arm = rig_of(context.active_object)
        layout = self.layout
        row = layout.row(align=True)
        row.prop(context.scene, "frame_start", text="Start")
        row.prop(context.scene, "frame_end", text="End")
        row = layout.row()
        row.scale_y = 1.3
        row.operator("manikin.bake_motion", icon="RENDER_ANIMATION")
        layout.operator("manikin.export_motion", icon="EXPORT")
        col = layout.column(align=True)
        col.prop(arm.manikin, "bound_motion")
        sub = col.column(align=True)
        sub.active = arm.manikin.bound_motion
        sub.prop(arm.manikin, "max_joint_change")
        sub.prop(arm.manikin, "max_root_shift")
        bake = last_bake(arm)
        if bake is None:
            return
        failed = bake["not_converged"]
        span = f"{bake['frame_start']}-{bake['frame_end']}"
        if not failed:
            layout.label(text=f"Baked {span}: all {bake['solved']} frames converged", icon="CHECKMARK")
            return
        layout.label(text=f"Baked {span}: {len(failed)} frames not converged", icon="ERROR")
        box = layout.box()
        for record in failed[:SHOWN_FAILURES]:  # as FrameRecord.why, from the stored record
            frame = record["frame"]
            notes = [note.removeprefix(f"frame {frame}: ") for note in record["notes"]]
            unmet = "out of reach: " + ", ".join(record["unmet"]) if record["unmet"] else "not converged"
            why = "; ".join(notes) or unmet
            box.label(text=f"frame {frame}: {why}")
        if len(failed) > SHOWN_FAILURES:
            box.label(text=f"... and {len(failed) - SHOWN_FAILURES} more")


classes = (MANIKIN_PT_motion,)
