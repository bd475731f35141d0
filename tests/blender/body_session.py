"""The skinned human in Blender, run by tests/blender/test_body.py in a subprocess:

    BLENDER_USER_RESOURCES=<empty dir> python tests/blender/body_session.py <zip> <out.json> <work dir>

adds a male_50 (its body objects, vertex groups, modifiers and materials recorded; the dense weights saved as
``weights.npy``), poses it with the forearms, upper arms and thighs twisted and the elbows and knees bent (the
evaluated mesh saved as ``twisted.npy``; keyed at a frame and played back: ``keyed.npy``), solves the box lift
(``lift.npy``), switches the display through its three modes, and adds a snake (then untags its solids, as a file
saved before the displays has them). Writes what it saw to JSON; bpy is imported here only.
"""

from __future__ import annotations

import importlib
import json
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from session_tools import install  # noqa: E402

from blender_manikin.batch import exit_process  # noqa: E402

ZIP, OUT, WORK = Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3])
TWISTED = {
    "forearm_r_pronation": 60.0,
    "forearm_l_pronation": -70.0,
    "shoulder_r_rotation": 40.0,
    "hip_l_rotation": -30.0,
    "elbow_r_flexion": 120.0,
    "knee_l_flexion": 90.0,
    "shoulder_l_flexion": 45.0,
}  # fmt: skip (degrees)
seen: dict = {}

import bpy  # noqa: E402

module = install(ZIP)
armature = importlib.import_module(module + ".blender_manikin.scene.armature")


def mat(m) -> list:
    return [list(row) for row in m]


def evaluated(obj: bpy.types.Object) -> np.ndarray:
    """(N, 3) vertex positions of the object's evaluated mesh (armature space: the body sits on the armature)."""
    bpy.context.view_layer.update()
    ev = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = ev.to_mesh()
    co = np.empty(3 * len(mesh.vertices), dtype=np.float32)
    mesh.vertices.foreach_get("co", co)
    ev.to_mesh_clear()
    return co.reshape(-1, 3).astype(float)


def bodies(arm: bpy.types.Object) -> dict:
    return {
        c.name: [c.get("manikin_display"), c.hide_viewport, c.hide_render] for c in arm.children if c.type == "MESH"
    }


def pose_of(arm: bpy.types.Object) -> dict:
    return dict(x=list(arm["manikin_x"]), bones={pb.name: mat(pb.matrix) for pb in arm.pose.bones})


start = time.perf_counter()
bpy.ops.manikin.add_manikin(preset="male_50")
seen["add_seconds"] = time.perf_counter() - start
arm = bpy.context.active_object
body = arm.children[0] if arm.children[0].type == "MESH" else next(c for c in arm.children if c.type == "MESH")
mesh = body.data
seen["display"] = arm.manikin.display
seen["bodies"] = bodies(arm)
seen["body"] = dict(
    name=body.name, parent=body.parent.name, hide_select=body.hide_select, vertices=len(mesh.vertices),
    smooth=all(p.use_smooth for p in mesh.polygons), materials=[m.name for m in mesh.materials],
    material_index=sorted({p.material_index for p in mesh.polygons}),
    modifiers=[[m.type, getattr(m, "object", None) and m.object.name, getattr(m, "levels", None),
                getattr(m, "render_levels", None)] for m in body.modifiers],
)  # fmt: skip
seen["bones"] = {b.name: [b.use_deform, b.hide, b.parent.name if b.parent else None] for b in arm.data.bones}
seen["groups"] = [g.name for g in body.vertex_groups]
weights = np.zeros((len(mesh.vertices), len(body.vertex_groups)))
for v in mesh.vertices:
    for g in v.groups:
        weights[v.index, g.group] = g.weight
np.save(WORK / "weights.npy", weights)
np.save(WORK / "rest.npy", evaluated(body))

model = armature.model_of(arm)
x = np.array(arm["manikin_x"])
for name, degrees in TWISTED.items():
    x[model.joint_index(name)] = np.radians(degrees)
armature.write_pose(arm, x)
np.save(WORK / "twisted.npy", evaluated(body))
seen["twisted"] = pose_of(arm)

# Keyed as a bake keys it (the bones' channels at a frame), played back: the mesh takes the keyed pose again.
rest_x = np.array(seen["twisted"]["x"])
rest_x[: model.n] = model.zero_pose()
for frame, pose in ((5, x), (1, rest_x)):
    armature.write_pose(arm, pose)
    for pb in arm.pose.bones:
        if not pb.name.endswith(".twist"):  # the helpers are driven, never keyed
            pb.keyframe_insert("rotation_euler", frame=frame)
            pb.keyframe_insert("location", frame=frame)
bpy.context.scene.frame_set(5)
np.save(WORK / "keyed.npy", evaluated(body))
bpy.context.scene.frame_set(1)
seen["keyed_rest"] = float(np.abs(evaluated(body) - np.load(WORK / "rest.npy")).max())
arm.animation_data.action = None  # (animation_data_clear would drop the twist drivers too)

bpy.ops.manikin.import_scenario(filepath=str(ROOT / "presets" / "scenarios" / "box_lift.toml"))
seen["solve"] = sorted(bpy.ops.manikin.solve_pose())
np.save(WORK / "lift.npy", evaluated(body))
seen["lift"] = pose_of(arm)

seen["modes"] = {}
for mode in ("CAPSULES", "SOLIDS", "HUMAN"):
    arm.manikin.display = mode
    seen["modes"][mode] = bodies(arm)
capsules = next(c for c in arm.children if c.get("manikin_display") == "CAPSULES")
seen["capsule_groups"] = sorted({len(v.groups) for v in capsules.data.vertices})
seen["capsule_weights"] = sorted({round(g.weight, 6) for v in capsules.data.vertices for g in v.groups})

bpy.ops.object.select_all(action="DESELECT")
bpy.context.view_layer.objects.active = None
bpy.ops.manikin.add_manikin(preset="snake")
snake = bpy.context.active_object
seen["snake"] = dict(display=snake.manikin.display, bodies=bodies(snake))
snake.manikin.display = "HUMAN"  # no human mesh for a snake: the solids stay
seen["snake_human"] = dict(display=snake.manikin.display, bodies=bodies(snake))
del snake.children[0]["manikin_display"]  # as saved before the displays existed: the solids untagged
snake.manikin.display = "CAPSULES"
snake.manikin.display = "SOLIDS"
seen["snake_legacy"] = bodies(snake)

OUT.write_text(json.dumps(seen), encoding="utf-8")
exit_process(0)
