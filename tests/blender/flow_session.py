"""The rest of a user's session, run by tests/blender/test_flow.py in a subprocess:

    BLENDER_USER_RESOURCES=<empty dir> python tests/blender/flow_session.py <zip> <out.json> <work dir>

enable time, every preset added, solve and reset, the viewport overlay drawn (with a recording stand-in for the
GPU module, which background mode lacks), and the bad states a user can create: a renamed bone, a deleted target
or TCP empty, nothing selected, a scaled armature. Writes what it saw to JSON; bpy is imported here only.
"""

from __future__ import annotations

import importlib
import json
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from session_tools import GpuRecorder, error_of, install  # noqa: E402

from blender_manikin.batch import exit_process  # noqa: E402

ZIP, OUT, WORK = Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3])
seen: dict = {}

import bpy  # noqa: E402

addon_utils = importlib.import_module("addon_utils")  # on the path once bpy is imported

module = install(ZIP)

# Enable time: the add-on imported and registered afresh (its wheels stay installed).
addon_utils.disable(module, refresh_handled=True)
for name in [m for m in sys.modules if m == module or m.startswith(module + ".")]:
    del sys.modules[name]
t0 = time.perf_counter()
addon_utils.enable(module, default_set=True, refresh_handled=True)
seen["enable_s"] = time.perf_counter() - t0  # measured ~65 ms on 5.0 (~25 ms before the registries were read)
seen["enabled"] = module in bpy.context.preferences.addons
seen["loaded_on_enable"] = sorted(m.removeprefix(module + ".") for m in sys.modules if m.startswith(module + ".solver"))
seen["heavy_on_enable"] = [m for m in ("scipy", "matplotlib") if m in sys.modules]


# Every preset, as Add > Manikin offers them.
presets = importlib.import_module(module + ".solver.presets").list_presets()
seen["presets"] = {}
for x, preset in enumerate(presets):
    bpy.ops.object.select_all(action="DESELECT")
    bpy.context.scene.cursor.location = (1.2 * x, 0.0, 0.0)
    done = sorted(bpy.ops.manikin.add_manikin(preset=preset))
    arm = bpy.context.active_object
    seen["presets"][preset] = dict(
        done=done,
        bones=len(arm.data.bones),
        tcps=sum("manikin_tcp" in child for child in arm.children),
        bodies=sum(child.type == "MESH" for child in arm.children),
        supports=sorted(
            ob.manikin_target.tcp
            for ob in bpy.data.objects
            if ob.manikin_target.rig == arm and ob.manikin_target.support
        ),  # fmt: skip
    )
    seen["presets"][preset]["solve"] = sorted(bpy.ops.manikin.solve_pose())

# Solve a moved hand target on the male, then Reset Pose.
arm = bpy.data.objects["male_50"]
bpy.context.view_layer.objects.active = arm
bpy.ops.manikin.add_target(tcp="hand_r")
bpy.data.objects["target.hand_r"].location.y -= 0.25
seen["solve"] = sorted(bpy.ops.manikin.solve_pose())
seen["converged"] = json.loads(arm["manikin_result"])["converged"]
bpy.context.view_layer.objects.active = arm
seen["reset"] = sorted(bpy.ops.manikin.reset_pose())
seen["reset_channels"] = max(max(map(abs, pb.location)) + max(map(abs, pb.rotation_euler)) for pb in arm.pose.bones)
seen["reset_result_gone"] = "manikin_result" not in arm
bpy.ops.manikin.solve_pose()

# Priorities: the hand target moved 2 m up, out of reach, ends short with the feet and balance held; as "Must hold"
# it is reported as not held instead.
hand_target = bpy.data.objects["target.hand_r"]
hand_target.location.z += 2.0
seen["far_solve"] = sorted(bpy.ops.manikin.solve_pose())
far = json.loads(arm["manikin_result"])
seen["far"] = dict(converged=far["converged"], broken=far["broken"], shortfall=far["shortfall"], unmet=far["unmet"])
hand_target.manikin_target.priority = "1"
bpy.ops.manikin.solve_pose()
seen["far_must_hold"] = json.loads(arm["manikin_result"])["broken"]
hand_target.location.z -= 2.0
hand_target.manikin_target.priority = "AUTO"
bpy.ops.manikin.solve_pose()

# Obstacles: a 30 cm cube around the hand target, marked as an obstacle, keeps the hand out (not held: the hand;
# held: feet, balance and the cube's clearance); unmarked it is ignored; in a collection "Obstacles" it counts again.
bpy.ops.mesh.primitive_cube_add(size=0.3, location=hand_target.matrix_world.translation)
cube = bpy.context.active_object
cube.manikin_obstacle.enabled, cube.manikin_obstacle.clearance = True, 0.01


def solve_state() -> dict:
    bpy.context.view_layer.objects.active = arm
    done = sorted(bpy.ops.manikin.solve_pose())
    result = json.loads(arm["manikin_result"])
    return dict(done=done, converged=result["converged"], unmet=result["unmet"], broken=result["broken"])


seen["obstacle_marked"] = solve_state()
cube.manikin_obstacle.enabled = False
seen["obstacle_unmarked"] = solve_state()
collection = bpy.data.collections.new("Obstacles")
bpy.context.scene.collection.children.link(collection)
collection.objects.link(cube)
seen["obstacle_collection"] = solve_state()
bpy.data.objects.remove(cube, do_unlink=True)
bpy.ops.manikin.solve_pose()

# The overlay, drawn with a stand-in for gpu: which builtin shaders it asks for, and how many line batches.
overlay = importlib.import_module(module + ".blender_manikin.pose.overlay")
recorder = GpuRecorder()
overlay.gpu, overlay.batch_for_shader = recorder.gpu, recorder.batch_for_shader
overlay.draw()
binary = Path(bpy.__spec__.origin).read_bytes()  # the compiled module: builtin shader names are strings in it
known = {name: f"{name}\0".encode() in binary for name in {*recorder.asked, "POINT_UNIFORM_COLOR"}}
seen["overlay"] = dict(asked=sorted(set(recorder.asked)), drawn=[n for _, n in recorder.drawn], known=known)

# Bad states a user can make: each is a report (RuntimeError for a script), never a traceback.
bone = arm.data.bones["upper_arm_r"]
bone.name = "renamed_arm"
seen["renamed_solve"] = error_of(bpy.ops.manikin.solve_pose)
seen["renamed_reset"] = error_of(bpy.ops.manikin.reset_pose)
seen["renamed_bake"] = error_of(lambda: bpy.ops.manikin.bake_motion(frame_start=1, frame_end=2))
bone.name = "upper_arm_r"

arm.manikin.live = True
live = importlib.import_module(module + ".blender_manikin.pose.live")
live.solve_pending()
bpy.data.objects.remove(bpy.data.objects["target.hand_r"], do_unlink=True)  # deleted while live
bpy.context.view_layer.update()
live.solve_pending()
seen["deleted_target_solve"] = sorted(bpy.ops.manikin.solve_pose())  # the feet remain: still solvable
arm.manikin.live = False

tcp = next(child for child in arm.children if child.get("manikin_tcp") == "hand_l")
bpy.data.objects.remove(tcp, do_unlink=True)
bpy.context.view_layer.objects.active = arm
seen["deleted_tcp_load"] = error_of(lambda: bpy.ops.manikin.add_load(tcp="hand_l", mass=2.0)) or "FINISHED"
seen["deleted_tcp_solve"] = error_of(bpy.ops.manikin.solve_pose) or "FINISHED"

bpy.context.view_layer.objects.active = None
seen["nothing_selected"] = dict(
    solve=bpy.ops.manikin.solve_pose.poll(), bake=bpy.ops.manikin.bake_motion.poll(),
    error=error_of(bpy.ops.manikin.solve_pose),
)  # fmt: skip
bpy.context.view_layer.objects.active = arm
arm.scale = (1.5, 1.5, 1.5)
bpy.context.view_layer.update()
seen["scaled"] = error_of(bpy.ops.manikin.solve_pose)
arm.scale = (1.0, 1.0, 1.0)

OUT.write_text(json.dumps(seen), encoding="utf-8")
exit_process(0)
