"""Retargeting onto rigs that face other ways, Rigify's meta-rig and generated rig, and a rig with constraints, run
by tests/blender/test_retarget_rigs.py in a subprocess:

    BLENDER_USER_RESOURCES=<empty dir> python tests/blender/retarget_rigs_session.py <zip> <out.json> <work dir>

installs the extension zip, bakes the box lift retimed to 16 frames, retargets onto shipped Mixamo rigs facing -y
(Blender's usual), +y (bones turned) and turned half a turn (the object), onto Blender's own Rigify meta-rig (the
rigify add-on ships with bpy) with each hand-goal option, refuses the rig Rigify generates from it, and names the
constraint that keeps a rig from following its keys; progress lines in background mode and the window manager's
progress in the UI (a stand-in window manager). Writes what it saw to JSON. bpy is imported here only.
"""

from __future__ import annotations

import importlib
import json
import math
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from session_tools import install  # noqa: E402

from blender_manikin.batch import exit_process  # noqa: E402

ZIP, OUT, WORK = Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3])
MOTION = ROOT / "presets" / "scenarios" / "box_lift_motion.toml"
FRAMES = list(range(1, 17))
ENDS = ("hand_l", "hand_r", "foot_l", "foot_r", "upper_arm_l", "upper_arm_r")
LEGS = [f"{p}_{s}" for s in "lr" for p in ("thigh", "shank", "foot", "upper_arm", "forearm", "hand")]
seen: dict = {"calls": {}, "rigs": {}, "times": {}}
started = time.perf_counter()

import bpy  # noqa: E402  (after BLENDER_USER_RESOURCES is set by the caller)
from mathutils import Matrix  # noqa: E402

addon_utils = importlib.import_module("addon_utils")  # on the path once bpy is imported

module = install(ZIP)
compat = importlib.import_module(module + ".blender_manikin.scene.compat")
motion = importlib.import_module(module + ".blender_manikin.retarget.motion")
progress = importlib.import_module(module + ".blender_manikin.retarget.progress")
scene = bpy.context.scene


def select(ob) -> None:
    for other in bpy.context.view_layer.objects.selected:
        other.select_set(False)
    bpy.context.view_layer.objects.active = ob
    ob.select_set(True)


def call(label: str, target, **settings) -> None:
    """Run Retarget on ``target``; its result or its error report (bpy raises an error report as RuntimeError)."""
    select(target)
    try:
        seen["calls"][label] = {"result": sorted(bpy.ops.manikin.retarget("EXEC_DEFAULT", True, **settings))}
    except RuntimeError as exc:
        seen["calls"][label] = {"error": str(exc)}


def rows(ob) -> dict[str, str]:
    return {r.ours: r.theirs for r in ob.manikin_retarget.bones if r.theirs}


def world_head(ob, bone: str) -> list[float]:
    return list(ob.matrix_world @ ob.data.bones[bone].head_local)


def record(target, manikin) -> dict:
    """Per frame, the world matrices of the manikin's and the target's hand, foot and upper arm bones; the limb
    bones' rest heads of both; the stored summary and the keyed channels."""
    mapped = rows(target)
    out = {"map": mapped, "rest_ours": {b: world_head(manikin, b) for b in LEGS},
           "rest_theirs": {b: world_head(target, mapped[b]) for b in LEGS}, "frames": {}}  # fmt: skip
    for frame in FRAMES:
        scene.frame_set(frame)
        out["frames"][str(frame)] = {
            "ours": {b: [list(r) for r in manikin.matrix_world @ manikin.pose.bones[b].matrix] for b in ENDS},
            "theirs": {b: [list(r) for r in target.matrix_world @ target.pose.bones[mapped[b]].matrix] for b in ENDS},
        }
    scene.frame_set(1)
    out["summary"] = json.loads(target.get("manikin_retargeted", "{}"))
    out["keyed"] = len(compat.object_fcurves(target))
    return out


def shipped(name: str):
    select(manikin)
    bpy.ops.manikin.add_retarget_rig(rig="mixamo")
    rig = bpy.context.active_object
    rig.name = name
    return rig


# Blender's Rigify meta-rig and the rig generated from it, before the manikin (generating is slower beside it).
seen["rigify_shipped"] = any(m.__name__ == "rigify" for m in addon_utils.modules())
addon_utils.enable("rigify", default_set=True)
bpy.ops.object.armature_human_metarig_add()
metarig = bpy.context.active_object
metarig.location = (-1.5, 0.0, 0.0)
bpy.ops.pose.rigify_generate()
generated = bpy.context.active_object
seen["generated"] = {"name": generated.name, "rig_id": "rig_id" in generated.data, "rows": len(rows(generated))}
seen["times"]["generate"] = time.perf_counter() - started
bpy.ops.object.select_all(action="DESELECT")

short = WORK / "box_lift_short.toml"
text = MOTION.read_text(encoding="utf-8")
for old, new in (("frame = 30", "frame = 8"), ("frame = 48", "frame = 13"), ("frame = 60", "frame = 16"),
                 ("end = 60", "end = 16")):  # fmt: skip
    text = text.replace(old, new)
# The standard comfort's stoop: the retargeting premises (body-scaled hand goals reachable on every rig) were set on
# it; the behaviour model's squat brings the hands closer to the feet than a Rigify meta-rig's shorter arms reach.
text += "\n[comfort]\ntrunk = 0.0\n"
short.write_text(text, encoding="utf-8")
seen["import"] = sorted(bpy.ops.manikin.import_scenario(filepath=str(short)))
manikin = bpy.context.active_object
scene.frame_set(1)
seen["bake"] = sorted(bpy.ops.manikin.bake_motion("EXEC_DEFAULT", frame_start=FRAMES[0], frame_end=FRAMES[-1]))
seen["times"]["bake"] = time.perf_counter() - started

# Facing: -y as built, +y (the bones turned half a turn about the object's origin), the object turned half a turn.
facing = {"minus_y": shipped("MinusY"), "plus_y": shipped("PlusY"), "object_180": shipped("Turned")}
plus_y = facing["plus_y"]
plus_y.data.transform(Matrix.Rotation(math.pi, 4, "Z"))  # about the object's origin
facing["object_180"].rotation_euler.z = math.pi
progress.EVERY = 5  # a line per 5 frames for this session's 16 (100 by default)
for label, rig in facing.items():
    call(label, rig)
    seen["rigs"][label] = record(rig, manikin)
progress.EVERY = 100
seen["times"]["facing"] = time.perf_counter() - started

# The UI's progress: a stand-in for the window manager, through the operator.
calls: list = []


class WindowManager:
    def progress_begin(self, low, high) -> None:
        calls.append(["begin", low, high])

    def progress_update(self, value) -> None:
        calls.append(["update", value])

    def progress_end(self) -> None:
        calls.append(["end"])


class InTheUI(progress.Progress):
    def __init__(self, label: str, frames: int, window_manager=None, background=None) -> None:
        super().__init__(label, frames, WindowManager(), background=False)


motion.Progress = InTheUI
call("ui_progress", facing["minus_y"])
motion.Progress = progress.Progress
seen["ui_progress"] = calls

# A rig whose forearm copies another bone's rotation: keyed, but it does not follow; the report names why.
constrained = shipped("Constrained")
copy = constrained.pose.bones["mixamorig:LeftForeArm"].constraints.new("COPY_ROTATION")
copy.target, copy.subtarget = constrained, "mixamorig:Hips"
call("constrained", constrained)
seen["rigs"]["constrained"] = record(constrained, manikin)

# The rig Rigify generates from its meta-rig and the meta-rig itself (later): bpy ships the rigify add-on.
call("generated", generated)
seen["generated_unchanged"] = len(compat.object_fcurves(generated)) == 0 and not rows(generated)
select(generated)
try:
    bpy.ops.manikin.auto_fill_bone_map("EXEC_DEFAULT", True)
    seen["generated_auto_fill"] = ""
except RuntimeError as exc:
    seen["generated_auto_fill"] = str(exc)
for goals in ("BODY", "ARM", "AUTO"):  # AUTO last: the recorded keys are the default's
    metarig.manikin_retarget.hand_goals = goals
    call(f"metarig_{goals.lower()}", metarig)
    seen["rigs"][f"metarig_{goals.lower()}"] = record(metarig, manikin)
seen["metarig_default"] = bpy.types.Object.bl_rna.properties["manikin_retarget"].fixed_type.properties[
    "hand_goals"].default  # fmt: skip
seen["times"]["total"] = time.perf_counter() - started
OUT.write_text(json.dumps(seen), encoding="utf-8")
print("retarget rigs session done")
exit_process(0)
