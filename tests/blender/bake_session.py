"""Baking a motion in a Blender session as a user would, run by tests/blender/test_bake.py in a subprocess:

    BLENDER_USER_RESOURCES=<empty dir> python tests/blender/bake_session.py <zip> <out.json> <work dir>

installs the extension zip, imports the box-lift motion (keyed target empties), exports it back, keys a bone
channel by hand inside and outside the range, bakes frames 2-9 through the operator (the carried box keyed too),
undoes, cancels a bake half-way, bakes 1-8 again and exports BVH and glTF, re-imports both, and writes what it saw
to JSON for the assertions in the test. bpy is imported here only.
"""

from __future__ import annotations

import importlib
import json
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from session_tools import install  # noqa: E402

from blender_manikin.batch import exit_process  # noqa: E402

ZIP, OUT, WORK = Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3])
MOTION = ROOT / "presets" / "scenarios" / "box_lift_motion.toml"
HAND_KEYS = [(0, 0.0), (5, 0.05), (12, -0.03)]  # (frame, value) keyed by hand on the pelvis x slide
seen: dict = {}

import bpy  # noqa: E402  (after BLENDER_USER_RESOURCES is set by the caller)

module = install(ZIP)
package = sys.modules[module]
bake_module = importlib.import_module(module + ".blender_manikin.motion.bake")
armature = importlib.import_module(module + ".blender_manikin.scene.armature")
keyframes = importlib.import_module(module + ".blender_manikin.scene.keyframes")
exports = importlib.import_module(module + ".blender_manikin.motion.exports")  # imported lazily by the add-on
scene = bpy.context.scene


def curves(ob) -> dict[str, list]:
    """Every F-curve of ``ob``: "path[index]" -> [[frame, value, interpolation], ...]."""
    out = {}
    for fc in keyframes.object_fcurves(ob):
        out[f"{fc.data_path}[{fc.array_index}]"] = [[k.co.x, k.co.y, k.interpolation] for k in fc.keyframe_points]
    return out


def world_bones(arm, frames: list[int]) -> dict[str, list]:
    """Per frame, each pose bone's world matrix."""
    out = {}
    for frame in frames:
        scene.frame_set(frame)
        out[str(frame)] = {pb.name: [list(r) for r in arm.matrix_world @ pb.matrix] for pb in arm.pose.bones}
    return out


# Import: a manikin with keyed hand targets; export writes the keys back.
bpy.ops.object.select_all(action="DESELECT")
seen["import"] = sorted(bpy.ops.manikin.import_scenario(filepath=str(MOTION)))
arm = bpy.context.active_object
NAME = arm.name  # undo replaces the object: look it up again by name
seen["range"] = [scene.frame_start, scene.frame_end]
seen["target_curves"] = {ob.name: curves(ob) for ob in bpy.data.objects if ob.name.startswith("target.")}
seen["target_at"] = {}
for frame in (1, 15, 30, 45, 60):
    scene.frame_set(frame)
    seen["target_at"][str(frame)] = {t: list(bpy.data.objects[f"target.{t}"].matrix_world.translation)
                                     for t in ("hand_l", "hand_r")}  # fmt: skip
scene.frame_set(1)
seen["export"] = sorted(bpy.ops.manikin.export_scenario(filepath=str(WORK / "exported_motion.toml")))

# Keys set by hand on the root bone: outside the range they must survive a bake, inside be replaced.
pelvis = arm.pose.bones["pelvis"]
for frame, value in HAND_KEYS:
    pelvis.location[0] = value
    pelvis.keyframe_insert("location", index=0, frame=frame)
seen["before"] = curves(arm)
bpy.ops.ed.undo_push(message="Keys by hand")

# Bake 2-9 through the operator, as the UI does (with an undo push).
scene.frame_set(2)
seen["x_at_2"] = list(armature.read_x(arm))
scene.frame_set(1)
seen["bake"] = sorted(bpy.ops.manikin.bake_motion("EXEC_DEFAULT", True, frame_start=2, frame_end=9))
arm = bpy.data.objects[NAME]
seen["baked"] = curves(arm)
seen["compiled_kernels"] = importlib.import_module(module + ".solver.kernels").active()  # which solved the bake
seen["bake_summary"] = json.loads(arm["manikin_bake"])
seen["frame_after"] = scene.frame_current
seen["bake_flags"] = sorted(bpy.types.MANIKIN_OT_bake_motion.bl_options)
seen["arm_matrix"] = [list(row) for row in arm.matrix_world]
seen["crate_baked"] = curves(next(ob for ob in bpy.data.objects if "manikin_carried" in ob))  # the carried box


class Layout:
    """Stands in for UILayout when drawing the Motion panel: records labels, checks property names."""

    def __init__(self, log: list) -> None:
        self.log = log

    def row(self, **kw) -> Layout:
        return Layout(self.log)

    column = box = row

    def label(self, text: str = "", **kw) -> None:
        self.log.append(text)

    def prop(self, data, name: str, **kw) -> None:
        assert name in data.bl_rna.properties, name

    def operator(self, idname: str, **kw) -> None:
        assert hasattr(bpy.ops.manikin, idname.split(".")[1]), idname


bpy.context.view_layer.objects.active = arm
seen["panel"] = []
importlib.import_module(module + ".blender_manikin.motion.panel").MANIKIN_PT_motion.draw(
    type("Panel", (), {"layout": Layout(seen["panel"])})(), bpy.context
)

# Undo restores the hand-set keys exactly.
bpy.ops.ed.undo()
arm, scene = bpy.data.objects[NAME], bpy.context.scene  # undo replaced both
seen["undone"] = curves(arm)

# The modal path (what a click in the UI runs), driven with stand-in events: a timer tick solves, view events
# pass through, others are swallowed, Esc cancels (nothing keyed, the frame restored); ticks run it to the end.
motion_operators = importlib.import_module(module + ".blender_manikin.motion.operators")
motion_operators.SLICE_S = 0.0  # one frame per timer tick, however fast this machine solves
operator = motion_operators.MANIKIN_OT_bake_motion
reports: list = []
methods = {n: operator.__dict__[n] for n in ("modal", "current_frame", "show_status", "cleanup", "stop", "finish")}
Modal = type("Modal", (), dict(methods, report=lambda self, kind, text: reports.append((sorted(kind)[0], text))))
context = type("Context", (), dict(window_manager=bpy.context.window_manager, workspace=None, scene=scene))()


def event(kind: str):
    return type("Event", (), {"type": kind})()


scene.frame_set(4)
op = Modal()
op.baker, op.timer = bake_module.Baker(scene, arm, 2, 9), None
seen["modal_events"] = [sorted(op.modal(context, event(e))) for e in ("TIMER", "MIDDLEMOUSE", "GKEY", "ESC")]
seen["cancel_done"] = op.baker.done
seen["cancelled"] = curves(arm)
seen["cancel_frame"] = scene.frame_current
seen["crate_cancelled"] = curves(next(ob for ob in bpy.data.objects if "manikin_carried" in ob))
op.baker = bake_module.Baker(scene, arm, 2, 9)
ticks = [sorted(op.modal(context, event("TIMER"))) for _ in range(50)]
seen["modal_ticks"] = ticks[: ticks.index(["FINISHED"]) + 1] if ["FINISHED"] in ticks else ticks
seen["modal_keys"] = curves(arm)
seen["modal_thetas"] = op.baker.thetas.tolist()
seen["modal_reports"] = reports

# A bake from frame 1 (the whole start of the lift), then exports and their re-imports.
for fc in keyframes.object_fcurves(arm):
    fc.keyframe_points.clear()
scene.frame_set(1)
baker = bake_module.Baker(scene, arm, 1, 8)
baker.run()
baker.write()
seen["thetas"] = baker.thetas.tolist()
seen["rebaked"] = curves(arm)
seen["frames"] = baker.frames
seen["converged"] = [r.converged for r in baker.records]
again = bake_module.Baker(scene, arm, 1, 8)  # as a headless job without a picture: the joint values dropped once keyed
again.run()
solved = again.thetas.tolist()
again.write(release=True)
seen["released"] = dict(rows=len(again.thetas), keys=curves(arm), thetas=solved)
frames = list(range(1, 9))
seen["original"] = world_bones(arm, frames)
seen["tcps"] = {}
for frame in frames:
    scene.frame_set(frame)
    seen["tcps"][str(frame)] = {ob["manikin_tcp"]: list(ob.matrix_world.translation) for ob in arm.children
                                if "manikin_tcp" in ob}  # fmt: skip
paths = {ext: exports.export(arm, WORK / f"motion{ext}", 1, 8) for ext in (".bvh", ".glb", ".fbx")}
seen["exported"] = {ext: p.stat().st_size for ext, p in paths.items()}
before = set(bpy.data.objects)
bpy.ops.import_anim.bvh(filepath=str(paths[".bvh"]), axis_forward="Y", axis_up="Z", rotate_mode="NATIVE",
                        update_scene_fps=False, update_scene_duration=False, use_fps_scale=False)  # fmt: skip
bvh = next(ob for ob in bpy.data.objects if ob not in before and ob.type == "ARMATURE")
before = set(bpy.data.objects)
bpy.ops.import_scene.gltf(filepath=str(paths[".glb"]))
gltf = next(ob for ob in bpy.data.objects if ob not in before and ob.type == "ARMATURE")
seen["bvh"] = world_bones(bvh, frames)
seen["gltf"] = world_bones(gltf, frames)
seen["gltf_mesh"] = any(ob.type == "MESH" and ob.find_armature() == gltf for ob in bpy.data.objects)
seen["finite"] = bool(np.isfinite(np.array(seen["thetas"])).all())

# Moving the manikin carries its imported (keyed) targets: each stays where it was in the manikin's frame.
scene.frame_set(15)
local = {t: list(arm.matrix_world.inverted() @ bpy.data.objects[f"target.{t}"].matrix_world.translation)
         for t in ("hand_l", "hand_r", "foot_l")}  # fmt: skip
arm.location.x += 1.0
arm.rotation_euler.z += 0.5
scene.frame_set(16)
scene.frame_set(15)
seen["moved_local"] = [local, {t: list(arm.matrix_world.inverted() @ bpy.data.objects[f"target.{t}"].matrix_world
                                       .translation) for t in local}]  # fmt: skip
OUT.write_text(json.dumps(seen), encoding="utf-8")
print("bake session done")
exit_process(0)  # bpy 4.2 would segfault at exit after the glTF export
