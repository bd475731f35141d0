"""What a bake saves against what it stands for, run by tests/blender/test_bake_shortcuts.py in a subprocess:

    BLENDER_USER_RESOURCES=<empty dir> python tests/blender/bake_shortcuts_session.py <zip> <out.json> <work dir>

imports the box-lift motion, bakes frames 1-6 and records the carried box's keys as the bake wrote them (from the TCP
positions kept from each frame's solve) and as keying from the joint values writes them (a forward kinematics per
frame); keys a new F-curve (Blender's defaults left as they are) and the same keys over an existing curve (every
attribute written back); builds the human's mesh from arrays and with ``from_pydata``. bpy is imported here only.
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
ATTRIBUTES = {"co": 2, "handle_left": 2, "handle_right": 2, "back": 1, "amplitude": 1, "period": 1,
              "interpolation": 0, "handle_left_type": 0, "handle_right_type": 0, "easing": 0, "type": 0,
              "select_control_point": -1, "select_left_handle": -1, "select_right_handle": -1}  # fmt: skip
seen: dict = {}

import bpy  # noqa: E402

module = install(ZIP)
bake = importlib.import_module(module + ".blender_manikin.motion.bake")
keyframes = importlib.import_module(module + ".blender_manikin.scene.keyframes")
carried_object = importlib.import_module(module + ".blender_manikin.scene.carried_object")
display = importlib.import_module(module + ".blender_manikin.scene.display")
armature = importlib.import_module(module + ".blender_manikin.scene.armature")
scene = bpy.context.scene


def keys(fc) -> dict[str, list]:
    """Every per-key attribute of an F-curve, as stored."""
    points, out = fc.keyframe_points, {}
    for name, size in ATTRIBUTES.items():
        kind = np.float32 if size > 0 else (np.int32 if size == 0 else bool)
        values = np.empty(len(points) * max(size, 1), dtype=kind)
        points.foreach_get(name, values)
        out[name] = values.tolist()
    return out


def object_keys(ob) -> dict[str, dict]:
    return {f"{fc.data_path}[{fc.array_index}]": keys(fc) for fc in keyframes.object_fcurves(ob)}


bpy.ops.manikin.import_scenario(filepath=str(MOTION))
arm = bpy.context.active_object
box = next(ob for ob in bpy.data.objects if "manikin_carried" in ob)

# The box keyed from the kept TCP positions (the bake) and from the joint values (a forward kinematics per frame).
scene.frame_set(1)
baker = bake.Baker(scene, arm, 1, 6)
baker.run()
baker.write(thin=True)
seen["tcps"] = list(baker.box_tcps)
seen["kept"] = object_keys(box)
frames = np.array([r.frame for r in baker.records], dtype=float)
carried_object.key_carried(arm, frames, baker.thetas, baker.worlds, True)
seen["recomputed"] = object_keys(box)
shifted = np.roll(baker.hands, 1, axis=0)  # another frame's positions: the comparison must see it
carried_object.key_carried(arm, frames, baker.thetas, baker.worlds, True, shifted)
seen["shifted"] = object_keys(box)

# A new F-curve keyed (Blender's defaults kept) and the same keys written over an existing curve (all read back).
values = np.array([0.0, 0.25, 0.25, 0.25, -0.5, 1.0 / 3.0, 1.0 / 3.0])
key_frames = np.arange(3, 3 + len(values), dtype=float)
empty = bpy.data.objects.new("keyed", None)
scene.collection.objects.link(empty)
fresh = keyframes.fcurve(empty, "location", 0)
keyframes.replace_keys(fresh, key_frames, values, thin=True)
again = keyframes.fcurve(empty, "location", 1)
keyframes.replace_keys(again, key_frames, values[::-1] + 2.0)  # keys there first: replaced through the full path
keyframes.replace_keys(again, key_frames, values, thin=True)
seen["fresh_curve"], seen["rewritten_curve"] = keys(fresh), keys(again)

# The human's mesh from arrays and through from_pydata.
model = armature.model_of(arm)
skin = display.human_mesh(model, armature.layout_of(model))
made = bpy.data.meshes.new("from arrays")
display._fill(made, skin.vertices, skin.corners, skin.sizes)
polygons = np.split(skin.corners, np.cumsum(skin.sizes)[:-1])
listed = bpy.data.meshes.new("from lists")
listed.from_pydata(skin.vertices.tolist(), [], [p.tolist() for p in polygons])


def mesh_data(mesh) -> dict[str, list]:
    out = {}
    for part, name, size, kind in (("vertices", "co", 3, np.float32), ("edges", "vertices", 2, np.int32),
                                   ("polygons", "loop_start", 1, np.int32), ("polygons", "loop_total", 1, np.int32),
                                   ("loops", "vertex_index", 1, np.int32), ("loops", "edge_index", 1, np.int32),
                                   ("polygons", "use_smooth", 1, bool)):  # fmt: skip
        items = getattr(mesh, part)
        values = np.empty(len(items) * size, dtype=kind)
        items.foreach_get(name, values)
        out[f"{part}.{name}"] = values.tolist()
    return out


seen["mesh_arrays"], seen["mesh_lists"] = mesh_data(made), mesh_data(listed)
seen["mesh_valid"] = not made.validate()  # validate() is True when it had to correct something
OUT.write_text(json.dumps(seen), encoding="utf-8")
print("bake shortcuts session done")
exit_process(0)
