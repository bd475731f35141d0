"""The Motion Ergonomics panel (under Motion in the Manikin sidebar tab): what the last bake found, read from the
entries it stored on the armature (motion/frame_store.py), and the Go to Frame button its frame lines use.

It shows the motion scores' lines (the NIOSH lift), each rated score's worst frame and why (the worksheet names the
item at fault), the worst frames as buttons that set the scene's frame, and the current frame's scores with their
levels and the worksheet's items. The per-frame scores over time are F-curves: the bake keys each graphed score as a
custom property of the armature's data (``manikin_rula``, ...), so the Graph Editor draws them with the playhead,
zoom and values a user already knows; a strip of labels in a sidebar would be unreadable beyond a few dozen frames.
Every score comes from the registry through what the bake stored: none is named here.
"""

import bpy
from bpy.props import IntProperty

from ..pose.panels import draw_verdict
from ..scene.help import draw_help
from ..scene.schema import baked_frame, rig_of

LEVEL_SEVERITY = {"green": 0, "yellow": 1, "red": 2}  # a motion score's level (the NIOSH lifting index's band)


class MANIKIN_OT_go_to_frame(bpy.types.Operator):
    """Set the scene's current frame (the Result panel then shows that frame's baked result)"""

    bl_idname = "manikin.go_to_frame"
    bl_label = "Go to Frame"
    bl_options = {"INTERNAL"}

    frame: IntProperty(name="Frame", description="The frame to show")

    def execute(self, context: bpy.types.Context) -> set[str]:
        context.scene.frame_set(self.frame)
        return {"FINISHED"}


def _frame_button(layout: bpy.types.UILayout, frame: int, text: str, severity: int | None) -> None:
    row = layout.row()
    row.alert = severity == 2
    op = row.operator("manikin.go_to_frame", text=text, icon="TIME")
    op.frame = frame


class MANIKIN_PT_motion_ergonomics(bpy.types.Panel):
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Manikin"
    draw_header_preset = draw_help  # the help button (scene/help.py)
    bl_label = "Motion Ergonomics"
    bl_parent_id = "MANIKIN_PT_motion"

    @classmethod
    def poll(cls, context: bpy.types.Context) -> bool:
        arm = rig_of(context.active_object)
        return arm is not None and baked_frame(arm, "head") is not None

    def draw(self, context: bpy.types.Context) -> None:
        arm = rig_of(context.active_object)
        head = baked_frame(arm, "head")
        layout = self.layout
        layout.label(text=f"Baked frames {head['frame_start']}-{head['frame_end']}")
        graphs = ", ".join(prop for _, _, prop in head["graphs"])
        if graphs:  # the scores over time: F-curves of the armature's data
            layout.label(text=f"Graph Editor (armature data): {graphs}", icon="GRAPH")
        levels = dict(head["motion_levels"])
        for line in head["motion_lines"]:  # "NIOSH lift: RWL 12.3 kg, load 10.0 kg, LI 0.81"
            severity = next((LEVEL_SEVERITY.get(lv) for t, lv in levels.items() if line.startswith(t)), None)
            draw_verdict(layout, line, severity)
        if not head["motion_lines"]:
            layout.label(text="No lift rated (no load in the hands, or not the human manikin)", icon="INFO")
        box = layout.box()
        box.label(text="Worst of each score")
        for text, frame, severity in head["worst_of_each"]:  # "worksheet red at frame 23 (worst level red: ...)"
            _frame_button(box, frame, text, severity)
        box = layout.box()
        box.label(text="Worst frames")
        for frame in head["worst"]:
            entry = baked_frame(arm, frame) or {"verdicts": []}
            rated = [v for v in entry["verdicts"] if v["severity"] is not None]
            top = max((v["severity"] for v in rated), default=None)
            words = ", ".join(v["text"] for v in rated if v["severity"] == top) or "not rated"
            _frame_button(box, frame, f"Frame {frame}: {words}", top)
        draw_frame(layout, arm, context.scene.frame_current)


def draw_frame(layout: bpy.types.UILayout, arm: bpy.types.Object, frame: int) -> None:
    """The current frame's scores, their levels and detail lines (the worksheet's items)."""
    entry = baked_frame(arm, frame)
    box = layout.box()
    if entry is None:
        box.label(text=f"Frame {frame} is outside the baked frames", icon="INFO")
        return
    state = "" if entry["converged"] else " (NOT converged: the solver's closest pose)"
    box.label(text=f"Frame {frame}{state}")
    for verdict in entry["verdicts"]:
        text = verdict["text"] + (f": {verdict['level']}" if verdict["level"] else "")
        draw_verdict(box, text, verdict["severity"])
    for name, lines in entry["details"].items():
        title = next((v["title"] for v in entry["verdicts"] if v["score"] == name), name)
        box.label(text=f"{title}, item by item:")
        for text, severity in lines:
            draw_verdict(box, "  " + text, severity)


classes = (MANIKIN_OT_go_to_frame, MANIKIN_PT_motion_ergonomics)
