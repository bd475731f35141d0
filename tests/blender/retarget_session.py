"""Retargeting in a Blender session as a user would, run by tests/blender/test_retarget.py in a subprocess:

    BLENDER_USER_RESOURCES=<empty dir> python tests/blender/retarget_session.py <zip> <out.json> <work dir>

installs the extension zip, imports the box lift retimed to 16 frames, tries Retarget on bad input (nothing baked,
a mesh, the manikin itself, an armature whose names say nothing, a map naming a missing bone), bakes, adds each
shipped rig and retargets onto it (hands free, then pinned), builds a Mixamo-named character with other
proportions (female 5th percentile), arms in a T-pose, an FBX-like object transform (x 0.01, Y up) and Euler
bones, retargets onto it with one call, saves and reloads the .blend, exports FBX and glTF and re-imports the FBX;
writes what it saw to JSON for the assertions. bpy is imported here only.
"""

from __future__ import annotations

import importlib
import json
import math
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from session_tools import Layout, draw_panels, install  # noqa: E402

from blender_manikin.batch import exit_process  # noqa: E402

ZIP, OUT, WORK = Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3])
MOTION = ROOT / "presets" / "scenarios" / "box_lift_motion.toml"
FRAMES = list(range(1, 17))
ENDS = ("hand_l", "hand_r", "foot_l", "foot_r")
LEGS = [f"{p}_{s}" for s in "lr" for p in ("thigh", "shank", "foot")]
seen: dict = {"calls": {}, "rigs": {}}

import bpy  # noqa: E402  (after BLENDER_USER_RESOURCES is set by the caller)
from mathutils import Matrix  # noqa: E402

module = install(ZIP)
solver = importlib.import_module(module + ".solver")
shipped = importlib.import_module(module + ".solver.retarget.shipped")
bone_map = importlib.import_module(module + ".solver.retarget.bone_map")
skeleton = importlib.import_module(module + ".solver.retarget.skeleton")
bodymesh = importlib.import_module(module + ".solver.bodymesh")
exports = importlib.import_module(module + ".blender_manikin.motion.exports")
compat = importlib.import_module(module + ".blender_manikin.scene.compat")
panel = importlib.import_module(module + ".blender_manikin.retarget.panel")
scene = bpy.context.scene


def call(label: str, **settings) -> None:
    """Run Retarget; record its result or its error report (bpy raises the operator's error as RuntimeError)."""
    try:
        seen["calls"][label] = {"result": sorted(bpy.ops.manikin.retarget("EXEC_DEFAULT", True, **settings))}
    except RuntimeError as exc:
        seen["calls"][label] = {"error": str(exc)}


def rows(ob) -> dict[str, str]:
    return {r.ours: r.theirs for r in ob.manikin_retarget.bones if r.theirs}


def keyed_paths(ob) -> list[str]:
    return sorted({f"{fc.data_path}[{fc.array_index}]" for fc in compat.object_fcurves(ob)})


def world_head(ob, bone: str) -> list[float]:
    return list(ob.matrix_world @ ob.data.bones[bone].head_local)


def record(target, manikin) -> dict:
    """Per frame, the world matrices of the manikin's and the target's hand and foot bones and the manikin's sole
    TCPs; the leg bones' rest heads of both (for the leg-length ratio and the ankles' midpoint)."""
    mapped = rows(target)
    out = {"map": mapped, "rest_ours": {b: world_head(manikin, b) for b in LEGS},
           "rest_theirs": {b: world_head(target, mapped[b]) for b in LEGS}, "frames": {}}  # fmt: skip
    tcps = {ob["manikin_tcp"]: ob for ob in manikin.children if "manikin_tcp" in ob}
    for frame in FRAMES:
        scene.frame_set(frame)
        out["frames"][str(frame)] = {
            "ours": {b: [list(r) for r in manikin.matrix_world @ manikin.pose.bones[b].matrix] for b in ENDS},
            "theirs": {b: [list(r) for r in target.matrix_world @ target.pose.bones[mapped[b]].matrix] for b in ENDS},
            "soles": {t: list(tcps[t].matrix_world.translation) for t in ("foot_l", "foot_r")},
        }
    scene.frame_set(1)
    out["summary"] = json.loads(target.get("manikin_retargeted", "{}"))
    out["keyed"] = keyed_paths(target)
    return out


def select(ob) -> None:
    for other in bpy.context.view_layer.objects.selected:
        other.select_set(False)
    bpy.context.view_layer.objects.active = ob
    ob.select_set(True)


# The scene: the box lift in 16 frames (keys at 1, 8, 13, 16), a mesh, an armature with uninformative names.
short = WORK / "box_lift_short.toml"
text = MOTION.read_text(encoding="utf-8")
for old, new in (("frame = 30", "frame = 8"), ("frame = 48", "frame = 13"), ("frame = 60", "frame = 16"),
                 ("end = 60", "end = 16")):  # fmt: skip
    text = text.replace(old, new)
# The standard comfort's stoop: the retargeting premises (body-scaled hand goals reachable on every rig) were set on
# it; the behaviour model's squat brings the hands closer to the feet than a Rigify meta-rig's shorter arms reach.
text += "\n[comfort]\ntrunk = 0.0\n"
short.write_text(text, encoding="utf-8")
bpy.ops.mesh.primitive_cube_add(location=(5.0, 0.0, 0.0))
blob = bpy.data.objects.new("Blob", bpy.data.armatures.new("Blob"))
scene.collection.objects.link(blob)
select(blob)
bpy.ops.object.mode_set(mode="EDIT")
for i in range(3):
    eb = blob.data.edit_bones.new(f"Bone.{i:03d}")
    eb.head, eb.tail = (3.0, 0.0, i * 0.5), (3.0, 0.0, i * 0.5 + 0.5)
    eb.parent = blob.data.edit_bones[f"Bone.{i - 1:03d}"] if i else None
bpy.ops.object.mode_set(mode="OBJECT")
bpy.ops.object.select_all(action="DESELECT")
seen["import"] = sorted(bpy.ops.manikin.import_scenario(filepath=str(short)))
manikin = bpy.context.active_object
seen["manikin"] = manikin.name

# Before any bake: a shipped rig exists, Retarget says there is nothing to retarget and keys nothing.
select(manikin)
seen["add_rig_flags"] = sorted(bpy.types.MANIKIN_OT_add_retarget_rig.bl_options)
seen["retarget_flags"] = sorted(bpy.types.MANIKIN_OT_retarget.bl_options)
bpy.ops.manikin.add_retarget_rig(rig="mixamo")
first_rig = bpy.context.active_object
rows_before = rows(first_rig)
call("no_bake", target=first_rig.name)
seen["no_bake_unchanged"] = keyed_paths(first_rig) == [] and rows(first_rig) == rows_before

scene.frame_set(1)
select(manikin)
seen["bake"] = sorted(bpy.ops.manikin.bake_motion("EXEC_DEFAULT", frame_start=FRAMES[0], frame_end=FRAMES[-1]))
seen["bake_summary"] = json.loads(manikin["manikin_bake"])

# Bad input after the bake: nothing changes.
call("mesh", target="Cube")
call("itself", target=manikin.name)
call("blob", target="Blob")
seen["blob_unchanged"] = keyed_paths(blob) == [] and len(blob.manikin_retarget.bones) == 0
row = next(r for r in first_rig.manikin_retarget.bones if r.ours == "hand_l")
row.theirs = "mixamorig:NoSuchHand"
call("missing_bone", target=first_rig.name)
seen["missing_bone_unchanged"] = keyed_paths(first_rig) == []
row.theirs = rows_before["hand_l"]

# Every shipped rig: hands free, then pinned (the default).
for rig in bone_map.SHIPPED_RIGS:
    select(manikin)
    seen["rigs"][rig] = {"add": sorted(bpy.ops.manikin.add_retarget_rig(rig=rig))}
    target = first_rig if rig == "mixamo" else bpy.context.active_object
    if rig == "mixamo":  # the first one stays: the map was restored above
        bpy.data.objects.remove(bpy.context.active_object)
    target.manikin_retarget.pin_hands = False
    call(f"{rig}.free", target=target.name)
    seen["rigs"][rig]["free"] = record(target, manikin)
    target.manikin_retarget.pin_hands = True
    call(rig, target=target.name)
    seen["rigs"][rig]["pinned"] = record(target, manikin)
    seen["rigs"][rig]["bones"] = len(target.data.bones)

# A Mixamo-named character of other proportions: a female 5th-percentile body's Mixamo rig with the arms in a
# T-pose, bone rolls of 0, as an FBX import has it (object turned 90 degrees about x, scale 0.01: bones in cm,
# Y up), its arms in Euler and axis-angle modes; standing 2 m to the manikin's right.
female = bodymesh.fit_body(solver.load_preset("female_5"))
bones = shipped.rig_bones(female, "mixamo")
heads = {b.name: np.array(b.head) for b in bones}
tails = {b.name: np.array(b.tail) for b in bones}
for side, sign in (("Left", 1.0), ("Right", -1.0)):
    top = f"mixamorig:{side}Arm"
    turn = skeleton.rotation_between(tails[top] - heads[top], np.array([sign, 0.0, 0.0]))
    below = {top} | {b.name for b in bones if b.name.startswith(f"mixamorig:{side}Hand")}
    below |= {f"mixamorig:{side}ForeArm"}
    for name in below:
        heads[name] = heads[top] + turn @ (heads[name] - heads[top])
        tails[name] = heads[top] + turn @ (tails[name] - heads[top])
character = bpy.data.objects.new("Character", bpy.data.armatures.new("Character"))
scene.collection.objects.link(character)
world = Matrix.Translation((-2.0, 0.0, 0.0)) @ Matrix.Rotation(math.pi / 2, 4, "X") @ Matrix.Scale(0.01, 4)
character.matrix_world = world
inverse = np.array(world.inverted())
select(character)
bpy.ops.object.mode_set(mode="EDIT")
for b in bones:
    eb = character.data.edit_bones.new(b.name)
    eb.head = tuple((inverse @ np.append(heads[b.name], 1.0))[:3])
    eb.tail = tuple((inverse @ np.append(tails[b.name], 1.0))[:3])
    eb.roll = 0.0
for b in bones:
    if b.parent:
        character.data.edit_bones[b.name].parent = character.data.edit_bones[b.parent]
bpy.ops.object.mode_set(mode="OBJECT")
for name, mode in (
    ("mixamorig:LeftArm", "XYZ"),
    ("mixamorig:LeftForeArm", "ZXY"),
    ("mixamorig:RightArm", "AXIS_ANGLE"),
):
    character.pose.bones[name].rotation_mode = mode
seen["character_rows_before"] = len(character.manikin_retarget.bones)
select(character)
bpy.ops.ed.undo_push(message="Character built")
call("character")  # one call: the map is filled in from the names, then the motion keyed
seen["character_keyed"] = keyed_paths(character)
bpy.ops.ed.undo()  # takes the keys and the filled-in map away again
scene, character, manikin = bpy.context.scene, bpy.data.objects["Character"], bpy.data.objects[seen["manikin"]]
seen["undone"] = {"keyed": keyed_paths(character), "rows": len(character.manikin_retarget.bones)}
select(character)
call("character")
seen["character"] = record(character, manikin)
seen["panel_character"] = []
draw_panels([panel.MANIKIN_PT_retarget], seen["panel_character"])
for item in list(character.manikin_retarget.bones)[:3]:
    panel.MANIKIN_UL_bone_map.draw_item(None, bpy.context, Layout([]), character.manikin_retarget, item, 0,
                                        character.manikin_retarget, "active_index")  # fmt: skip
select(manikin)
seen["panel_manikin"] = []
draw_panels([panel.MANIKIN_PT_retarget], seen["panel_manikin"])
seen["character_modes"] = {n: character.pose.bones[n].rotation_mode for n in ("mixamorig:LeftArm",
                           "mixamorig:LeftForeArm", "mixamorig:RightArm")}  # fmt: skip
seen["character_source"] = character.manikin_retarget.source.name

# Saved and reloaded: the map and the keys are still there.
bpy.ops.wm.save_as_mainfile(filepath=str(WORK / "retarget.blend"))
bpy.ops.wm.open_mainfile(filepath=str(WORK / "retarget.blend"))
scene = bpy.context.scene
character, manikin = bpy.data.objects["Character"], bpy.data.objects[seen["manikin"]]
seen["reloaded"] = record(character, manikin)

# Exports of the retargeted character, and the FBX re-imported.
paths = {ext: exports.export(character, WORK / f"character{ext}", FRAMES[0], FRAMES[-1]) for ext in (".fbx", ".glb")}
seen["exported"] = {ext: p.stat().st_size for ext, p in paths.items()}
before = set(bpy.data.objects)
compat.call_known(bpy.ops.import_scene.fbx, filepath=str(paths[".fbx"]))  # defaults: lands on the baked frames
imported = next(ob for ob in bpy.data.objects if ob not in before and ob.type == "ARMATURE")
seen["fbx"] = {}
for frame in FRAMES:
    scene.frame_set(frame)
    seen["fbx"][str(frame)] = {
        b: list(imported.matrix_world @ imported.pose.bones[seen["character"]["map"][b]].head) for b in ENDS
    }
OUT.write_text(json.dumps(seen), encoding="utf-8")
print("retarget session done")
exit_process(0)  # bpy 4.2 would segfault at exit after the glTF export
