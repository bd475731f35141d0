"""Motion ergonomics in the sidebar after a bake (issue 33), run by tests/blender/test_motion_ergo.py in a subprocess:

    BLENDER_USER_RESOURCES=<empty dir> python tests/blender/motion_ergo_session.py <zip> <out.json> <work dir>

installs the extension zip, imports the box-lift motion, bakes frames 1-6 through Bake Motion, then reads what a
user sees: the per-frame entries and graph curves stored on the armature, the Motion Ergonomics panel (its worst
frames pressed through Go to Frame), the Result panel at two frames and after a Solve Pose; then an out-of-reach
head target baked at frame 8 (the Bake Motion's report lines and the Motion panel). Writes what it saw to JSON.
"""

from __future__ import annotations

import importlib
import json
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

import session_tools  # noqa: E402
from session_tools import draw_panels, install  # noqa: E402

from blender_manikin.batch import exit_process  # noqa: E402

ZIP, OUT, WORK = Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3])
MOTION = ROOT / "presets" / "scenarios" / "box_lift_motion.toml"
seen: dict = {}

import bpy  # noqa: E402

module = install(ZIP)
pose_panels = importlib.import_module(module + ".blender_manikin.pose.panels")
motion_panel = importlib.import_module(module + ".blender_manikin.motion.panel")
ergo_panel = importlib.import_module(module + ".blender_manikin.motion.ergonomics_panel")
operators = importlib.import_module(module + ".blender_manikin.motion.operators")
bake_module = importlib.import_module(module + ".blender_manikin.motion.bake")
keyframes = importlib.import_module(module + ".blender_manikin.scene.keyframes")
buttons: list = []  # (text, operator, properties) of each button drawn
lines: list = []  # (text, icon, red) of each label drawn


class Props:
    """Stands in for the properties of a button's operator."""


def operator(self, idname: str, text: str = "", **kw) -> Props:
    """Stands in for UILayout.operator: checks it as session_tools does, records the button."""
    group, name = idname.split(".")
    assert hasattr(getattr(bpy.ops, group), name), idname
    props = Props()
    buttons.append((text, idname, props))
    self.log.append(text)
    return props


def label(self, text: str = "", icon: str = "NONE", **kw) -> None:
    assert icon in session_tools.icons(), icon
    self.log.append(text)
    lines.append((text, icon, bool(getattr(self, "alert", False))))


session_tools.Layout.operator = operator
session_tools.Layout.label = label


def drawn(panel) -> list[str]:
    log: list = []
    buttons.clear()
    lines.clear()
    draw_panels([panel], log)
    return log


bpy.ops.object.select_all(action="DESELECT")
bpy.ops.manikin.import_scenario(filepath=str(MOTION))
arm = bpy.context.active_object
NAME = arm.name
scene = bpy.context.scene
scene.frame_set(1)
t0 = time.perf_counter()
seen["bake"] = sorted(bpy.ops.manikin.bake_motion("EXEC_DEFAULT", True, frame_start=1, frame_end=6))
seen["bake_s"] = time.perf_counter() - t0
arm = bpy.data.objects[NAME]
bpy.context.view_layer.objects.active = arm
stored = arm["manikin_frames"]
seen["stored_keys"] = sorted(stored.keys())
seen["stored"] = {k: json.loads(stored[k]) for k in stored.keys()}
seen["graph_curves"] = {
    fc.data_path: [[k.co.x, k.co.y] for k in fc.keyframe_points] for fc in keyframes.object_fcurves(arm.data)
}
seen["arm_other_curves"] = sorted({fc.data_path for fc in keyframes.object_fcurves(arm)} - {
    fc.data_path for fc in keyframes.object_fcurves(arm) if fc.data_path.startswith("pose.bones")})  # fmt: skip

# The score curves on the armature's data do not get in the way of the exports.
exports = importlib.import_module(module + ".blender_manikin.motion.exports")
seen["exported"] = {ext: exports.export(arm, WORK / f"baked{ext}", 1, 6).stat().st_size for ext in (".glb", ".fbx")}
bpy.context.view_layer.objects.active = arm

# The Motion Ergonomics panel at frame 1 (where the bake left the scene); each worst frame's button pressed.
seen["ergo_panel"] = drawn(ergo_panel.MANIKIN_PT_motion_ergonomics)
seen["ergo_lines"] = list(lines)
seen["ergo_buttons"] = [(text, idname, getattr(props, "frame", None)) for text, idname, props in buttons]
seen["jumps"] = []
for _, idname, props in list(buttons):
    if idname == "manikin.go_to_frame":
        bpy.ops.manikin.go_to_frame(frame=props.frame)
        seen["jumps"].append([props.frame, scene.frame_current])

# The Result panel follows the frame through the baked range.
seen["result_at"] = {}
for frame in (3, 5):
    scene.frame_set(frame)
    seen["result_at"][str(frame)] = dict(panel=drawn(pose_panels.MANIKIN_PT_result), lines=list(lines))
scene.frame_set(4)
seen["ergo_at_4"] = drawn(ergo_panel.MANIKIN_PT_motion_ergonomics)
scene.frame_set(9)
seen["result_outside"] = drawn(pose_panels.MANIKIN_PT_result)
seen["ergo_outside"] = drawn(ergo_panel.MANIKIN_PT_motion_ergonomics)
scene.frame_set(3)
seen["solve"] = sorted(bpy.ops.manikin.solve_pose())  # a later solve: the panel shows it, not the stored frame
seen["result_after_solve"] = drawn(pose_panels.MANIKIN_PT_result)
seen["result_after_solve_lines"] = list(lines)
seen["last_result"] = json.loads(arm["manikin_result"])

# An out-of-reach head target: the bake's report lines and the Motion panel name the frame.
bpy.ops.manikin.add_target(tcp="head")
bpy.data.objects["target.head"].location.z += 1.0
bpy.context.view_layer.objects.active = arm
reports: list = []
names = ("finish", "cleanup", "stop")
Op = type("Op", (), {n: operators.MANIKIN_OT_bake_motion.__dict__[n] for n in names}
          | {"report": lambda self, kind, text: reports.append([sorted(kind)[0], text])})  # fmt: skip
op = Op()
op.baker, op.timer = bake_module.Baker(scene, arm, 8, 8), None
op.baker.run()
context = type("Context", (), dict(window_manager=bpy.context.window_manager, workspace=None, scene=scene))()
seen["far_finish"] = sorted(op.finish(context))
seen["far_reports"] = reports
seen["far_records"] = [[r.frame, r.converged, r.unmet, r.notes, r.why()] for r in op.baker.records]
seen["motion_panel"] = drawn(motion_panel.MANIKIN_PT_motion)

OUT.write_text(json.dumps(seen), encoding="utf-8")
print("motion ergonomics session done")
exit_process(0)
