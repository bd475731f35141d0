"""Animated obstacles and target settings in a bake, run by tests/blender/test_bake_scene.py in a subprocess:

    BLENDER_USER_RESOURCES=<empty dir> python tests/blender/bake_scene_session.py <zip> <out.json> <work dir>

a manikin standing on its feet targets, reaching with a hand target whose weight is keyed, among obstacles (away
from it) animated every way a bake must follow frame by frame: keyed location, a keyed Displace modifier, a keyed
shape key, an animated parent, a keyed Obstacle toggle and clearance; and two that never move. Frames 1-6 are
baked (a Baker reads what cannot change once); each frame's problem as the bake read it is recorded beside the one
Solve Pose reads from scratch at that frame. Then a frame change handler reshapes a mesh each frame, and the same
bake follows it. bpy is imported here only.
"""

from __future__ import annotations

import importlib
import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from session_tools import install  # noqa: E402

from blender_manikin.batch import exit_process  # noqa: E402

ZIP, OUT, WORK = Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3])
FRAMES = (1, 6)
seen: dict = {}

import bpy  # noqa: E402

module = install(ZIP)
bake = importlib.import_module(module + ".blender_manikin.motion.bake")
problem_io = importlib.import_module(module + ".blender_manikin.scene.problem_io")
scene = bpy.context.scene


def cube(name: str, shape: str, location: tuple, size: float = 0.4) -> bpy.types.Object:
    bpy.ops.mesh.primitive_cube_add(size=size, location=location)
    ob = bpy.context.active_object
    ob.name = name
    ob.manikin_obstacle.enabled, ob.manikin_obstacle.shape, ob.manikin_obstacle.clearance = True, shape, 0.01
    return ob


def key(owner, prop: str, values: dict[int, object]) -> None:
    for frame, value in values.items():
        setattr(owner, prop, value)
        owner.keyframe_insert(prop, frame=frame)


scene.cursor.location = (0.0, 0.0, 0.0)
bpy.ops.manikin.add_manikin(preset="male_50")
arm = bpy.context.active_object
for tcp in ("foot_l", "foot_r", "hand_r"):
    bpy.context.view_layer.objects.active = arm
    bpy.ops.manikin.add_target(tcp=tcp)
hand = bpy.data.objects["target.hand_r"]
hand.location.z += 0.1
key(hand.manikin_target, "weight", {1: 1.0, 6: 3.0})  # a target's setting keyed: read every frame

moved = cube("moved", "BOX", (3.0, 0.0, 0.5))
key(moved, "location", {1: (3.0, 0.0, 0.5), 6: (3.0, 1.0, 0.5)})
displaced = cube("displaced", "MESH", (-3.0, 0.0, 0.5))
modifier = displaced.modifiers.new("lift", "DISPLACE")
modifier.direction, modifier.mid_level = "Z", 0.0  # no texture: every vertex up by the strength
key(modifier, "strength", {1: 0.0, 6: 0.5})
stretched = cube("stretched", "BOX", (0.0, 3.0, 0.5))
stretched.shape_key_add(name="Basis")
tall = stretched.shape_key_add(name="tall", from_mix=False)
for point in tall.data:
    if point.co.z > 0.0:
        point.co.z += 0.6
key(tall, "value", {1: 0.0, 6: 1.0})
bpy.ops.object.empty_add(location=(0.0, -3.0, 0.0))
carrier = bpy.context.active_object
carrier.name = "carrier"
key(carrier, "location", {1: (0.0, -3.0, 0.0), 6: (0.0, -3.0, 0.8)})
child = cube("child", "BOX", (0.0, -3.0, 0.5))
child.parent = carrier
switched = cube("switched", "SPHERE", (3.0, 3.0, 0.5))
key(switched.manikin_obstacle, "enabled", {1: True, 4: False})
key(switched.manikin_obstacle, "clearance", {1: 0.01, 3: 0.05})
cube("still", "BOX", (-3.0, 3.0, 0.5))
cube("still mesh", "MESH", (-3.0, -3.0, 0.5))
scene.frame_start, scene.frame_end = FRAMES
scene.frame_set(FRAMES[0])
bpy.context.view_layer.update()


def described(problem) -> dict:
    """What a read problem holds of the scene: each obstacle's kind, bounds (m), clearance and identity, the hand
    target's weight and the identity of each target."""
    return dict(
        obstacles={
            ob.name: dict(kind=ob.kind, bounds=[b.tolist() for b in ob.bounds()], clearance=ob.clearance, id=id(ob))
            for ob in problem.obstacles
        },  # fmt: skip
        weights={t.tcp: t.weight for t in problem.all_targets},
        targets={t.tcp: id(t) for t in problem.all_targets},
    )


baked: dict[str, dict] = {}
baker = bake.Baker(scene, arm, *FRAMES, on_frame=lambda record, result: baked.update({
    str(record.frame): described(result.problem)}))  # fmt: skip
baker.run()
seen["converged"] = [r.converged for r in baker.records]
seen["fixed"] = {s.ob.name: s.fixed for s in baker.held.sources}  # which meshes the bake read once
baker.cancel()
seen["baked"] = baked
fresh = {}
for frame in range(FRAMES[0], FRAMES[1] + 1):
    scene.frame_set(frame)
    fresh[str(frame)] = described(problem_io.read_problem(arm, start=False).problem)
seen["fresh"] = fresh

# A script that edits a mesh on each frame change: with such a handler no mesh is read once.
scripted = cube("scripted", "MESH", (3.0, -3.0, 0.5))


def reshape(scene, *_args) -> None:
    half = 0.2 + 0.05 * scene.frame_current  # m: the cube's top (and bottom) moves away from its centre
    for vertex in scripted.data.vertices:
        vertex.co.z = half if vertex.co.z > 0.0 else -half
    scripted.data.update()


bpy.app.handlers.frame_change_post.append(reshape)
tops: dict[str, float] = {}


def top(record, result) -> None:
    """The scripted mesh's highest point (m, armature space) as the bake read it at this frame."""
    shape = next(ob for ob in result.problem.obstacles if ob.name == "scripted")
    tops[str(record.frame)] = float(shape.bounds()[1][2])


baker = bake.Baker(scene, arm, *FRAMES, on_frame=top)
baker.run()
seen["scripted"] = dict(tops=tops, fixed=[s.fixed for s in baker.held.sources if s.ob == scripted])
baker.cancel()
bpy.app.handlers.frame_change_post.remove(reshape)
OUT.write_text(json.dumps(seen), encoding="utf-8")
exit_process(0)
