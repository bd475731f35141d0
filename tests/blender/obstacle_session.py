"""Obstacles in a Blender session, run by tests/blender/test_obstacles.py in a subprocess:

    BLENDER_USER_RESOURCES=<empty dir> python tests/blender/obstacle_session.py <zip> <out.json> <work dir>

a turned manikin away from the origin among six obstacles (a mesh, and a box, sphere, capsule, plane and cylinder made
from objects' bounds), solved; what the overlay would draw from that result (lines, labels, capsules) and its draw
handlers added in this Blender; the scenario exported (meshes beside it), imported into an emptied scene onto
another turned manikin and exported again; imported a second time; the failures a user can meet (a missing
mesh file, a folder that cannot be written); a scenario's cylinder imported, and a hand target put inside it
solved. Writes what it saw to JSON; bpy is imported here only.
"""

from __future__ import annotations

import importlib
import json
import math
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from session_tools import GpuRecorder, draw_panels, error_of, install  # noqa: E402

from blender_manikin.batch import exit_process  # noqa: E402

ZIP, OUT, WORK = Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3])
seen: dict = {}

import bpy  # noqa: E402
from mathutils import Vector  # noqa: E402

module = install(ZIP)
overlay = importlib.import_module(module + ".blender_manikin.pose.overlay")
problem_io = importlib.import_module(module + ".blender_manikin.scene.problem_io")


def mat(m) -> list:
    return [list(row) for row in m]


def turned_manikin(location: tuple, degrees: float) -> bpy.types.Object:
    bpy.ops.object.select_all(action="DESELECT")
    bpy.context.scene.cursor.location = location
    bpy.ops.manikin.add_manikin(preset="male_50")
    arm = bpy.context.active_object
    arm.rotation_euler.z = math.radians(degrees)
    bpy.context.view_layer.update()
    for tcp in ("foot_l", "foot_r"):  # the supports snap to the turned feet
        bpy.context.view_layer.objects.active = arm
        bpy.ops.manikin.add_target(tcp=tcp)
    bpy.context.view_layer.objects.active = arm
    return arm


arm = turned_manikin((1.0, 0.5, 0.0), 90.0)
bpy.ops.manikin.add_target(tcp="hand_r")
hand = bpy.data.objects["target.hand_r"]
forward = arm.matrix_world.to_3x3() @ Vector((0.0, -1.0, 0.0))  # the manikin faces its -y
hand.location += 0.3 * forward + Vector((0.0, 0.0, 0.3))


def add(kind: str, name: str, shape: str, clearance: float, **place) -> bpy.types.Object:
    getattr(bpy.ops.mesh, f"primitive_{kind}_add")(**place)
    ob = bpy.context.active_object
    ob.name = name
    ob.manikin_obstacle.enabled, ob.manikin_obstacle.shape, ob.manikin_obstacle.clearance = True, shape, clearance
    return ob


# A 30 cm cube round the hand target (a mesh), and five shapes from objects' bounds well away from the manikin.
add("cube", "shelf.top", "MESH", 0.01, size=0.3, location=hand.matrix_world.translation)
box = add("cube", "table", "BOX", 0.02, size=1.0, location=(3.0, -2.0, 0.4), rotation=(0.3, 0.0, 0.7))
box.scale = (0.8, 0.4, 0.8)
add("uv_sphere", "ball", "SPHERE", 0.0, radius=0.1, location=(4.0, 1.0, 1.0))
add("cylinder", "rail", "CAPSULE", 0.0, radius=0.02, depth=0.5, location=(4.0, 0.0, 1.0), rotation=(1.2, 0.0, 0.0))
add("plane", "wall", "PLANE", 0.0, size=2.0, location=(0.0, 4.0, 1.0), rotation=(math.radians(90.0), 0.0, 0.0))
add("cylinder", "drum", "CYLINDER", 0.03, radius=0.3, depth=0.9, location=(-3.0, 3.0, 0.45), rotation=(0.0, 0.4, 0.2))
bpy.context.view_layer.update()
seen["panel"] = []  # the sidebar with an obstacle active: its settings, and the capsules toggle of the manikin
bpy.context.view_layer.objects.active = box
draw_panels(importlib.import_module(module + ".blender_manikin.addon").panels(), seen["panel"])
bpy.context.view_layer.objects.active = arm
draw_panels(importlib.import_module(module + ".blender_manikin.addon").panels(), seen["panel"])
read = {ob.name: ob for ob in problem_io.read_problem(arm).problem.obstacles}
seen["read"] = dict(
    kinds={name: type(ob).__name__ for name, ob in read.items()},
    ball=dict(center=list(read["ball"].center), radius=read["ball"].radius),
    ball_local=list(arm.matrix_world.inverted() @ bpy.data.objects["ball"].matrix_world.translation),
    drum=dict(a=list(read["drum"].a), b=list(read["drum"].b), radius=read["drum"].radius),
    drum_matrix=mat(arm.matrix_world.inverted() @ bpy.data.objects["drum"].matrix_world),
)
# Read again as a bake does, the last read given: only the targets' poses changed, so the obstacle rows are shared;
# a moved obstacle gives new ones (with the new shape).
first = problem_io.read_problem(arm, start=False)
again = problem_io.read_problem(arm, start=False, reuse=first)
bpy.data.objects["ball"].location.z += 0.05
bpy.context.view_layer.update()
moved = problem_io.read_problem(arm, start=False, reuse=again)
seen["reuse"] = dict(
    shared=again.problem.obstacle_constraint is first.problem.obstacle_constraint,
    fresh=moved.problem.obstacle_constraint is not again.problem.obstacle_constraint,
    ball_moved=float(
        next(o for o in moved.problem.obstacles if o.name == "ball").center[2]
        - next(o for o in again.problem.obstacles if o.name == "ball").center[2]
    ),
)
bpy.data.objects["ball"].location.z -= 0.05
bpy.context.view_layer.update()

bpy.context.view_layer.objects.active = arm
seen["solve"] = sorted(bpy.ops.manikin.solve_pose())
result = json.loads(arm["manikin_result"])
seen["result"] = dict(unmet=result["unmet"], closest=result["closest"], capsules=result["capsules"])

# What the overlay would draw: lines and labels from this result, capsules with the toggle.
geometry = overlay.geometry(arm, result)
seen["geometry"] = {key: [list(v) for v in lines] for key, lines in geometry.items()}
seen["labels"] = [(list(p), text, list(color)) for p, text, color in overlay.labels(arm, result)]
seen["shown"] = [list(overlay.shown(arm))]
arm.manikin.show_capsules = True
seen["shown"].append(list(overlay.shown(arm)))
arm.manikin.show_overlay = False
seen["shown"].append(list(overlay.shown(arm)))
arm.manikin.show_overlay, arm.manikin.show_capsules = True, False
recorder = GpuRecorder()  # the draw callback with each toggle: (colour, vertex count) of every batch
real_gpu, real_batch = overlay.gpu, overlay.batch_for_shader
overlay.gpu, overlay.batch_for_shader = recorder.gpu, recorder.batch_for_shader
for overlay_on, capsules_on in ((True, False), (True, True), (False, False)):
    arm.manikin.show_overlay, arm.manikin.show_capsules = overlay_on, capsules_on
    recorder.drawn.append(("draw", 0))
    overlay.draw()
overlay.gpu, overlay.batch_for_shader = real_gpu, real_batch
arm.manikin.show_overlay, arm.manikin.show_capsules = True, False
seen["batches"] = recorder.drawn
seen["matrix"] = mat(arm.matrix_world)

texts: list = []


class Blf:
    """Stands in for blf (background mode draws nothing): records the text drawn."""

    @staticmethod
    def size(font: int, size: float) -> None:
        pass

    @staticmethod
    def color(font: int, *rgba: float) -> None:
        texts.append(["color", *rgba])

    @staticmethod
    def position(font: int, x: float, y: float, z: float) -> None:
        pass

    @staticmethod
    def draw(font: int, text: str) -> None:
        texts.append(["text", text])


real_blf, real_project = overlay.blf, overlay.location_3d_to_region_2d
overlay.blf = Blf
overlay.location_3d_to_region_2d = lambda region, view, point: Vector((point.x, point.y))
overlay.draw_labels(object(), object())
overlay.blf, overlay.location_3d_to_region_2d = real_blf, real_project
seen["drawn_labels"] = texts
seen["handlers"] = error_of(overlay.add_handlers) or "added"
seen["handlers_removed"] = error_of(overlay.remove_handlers) or "removed"

# Export: the mesh beside the TOML, the shapes in it.
exported = WORK / "exported.toml"
bpy.context.view_layer.objects.active = arm
seen["export"] = sorted(bpy.ops.manikin.export_scenario(filepath=str(exported)))
seen["files"] = sorted(p.name for p in WORK.iterdir() if p.suffix in (".toml", ".obj"))

# An emptied scene, another turned manikin, the scenario imported onto it and exported again.
for ob in list(bpy.data.objects):
    bpy.data.objects.remove(ob, do_unlink=True)
for collection in list(bpy.data.collections):
    bpy.data.collections.remove(collection)
other = turned_manikin((-1.0, 2.0, 0.0), 30.0)
seen["import"] = sorted(bpy.ops.manikin.import_scenario(filepath=str(exported)))
seen["import_onto"] = bpy.context.active_object.name == other.name
obstacles = bpy.data.collections["Obstacles"]
seen["imported"] = {
    ob.name: dict(shape=ob.manikin_obstacle.shape, enabled=ob.manikin_obstacle.enabled,
                  clearance=ob.manikin_obstacle.clearance, local=mat(other.matrix_world.inverted() @ ob.matrix_world))
    for ob in obstacles.objects
}  # fmt: skip
seen["other_matrix"] = mat(other.matrix_world)
bpy.context.view_layer.objects.active = other
seen["export_again"] = sorted(bpy.ops.manikin.export_scenario(filepath=str(WORK / "again.toml")))

# Imported again: the import's own objects are replaced; a user's object of an obstacle's name stays.
del bpy.data.objects["wall"]["manikin_imported"]  # now the user's own
bpy.context.view_layer.objects.active = other
seen["import_twice"] = sorted(bpy.ops.manikin.import_scenario(filepath=str(exported)))
seen["after_twice"] = sorted(ob.name for ob in bpy.data.collections["Obstacles"].objects)

# Failures: a missing mesh file; a folder that cannot be written.
bad = WORK / "bad.toml"
bad.write_text(exported.read_text(encoding="utf-8").replace("exported_shelf_top.obj", "nowhere.obj"), "utf-8")
seen["missing_mesh"] = error_of(lambda: bpy.ops.manikin.import_scenario(filepath=str(bad)))
(WORK / "blocked").write_text("", encoding="utf-8")
bpy.context.view_layer.objects.active = other
seen["unwritable"] = error_of(lambda: bpy.ops.manikin.export_scenario(filepath=str(WORK / "blocked" / "s.toml")))

# A mesh obstacle flattened to no thickness (every triangle of zero area): one line naming it.
flat = add("plane", "flat", "MESH", 0.0, size=0.5, location=(2.0, 2.0, 0.5))
flat.scale = (0.0, 1.0, 1.0)
bpy.context.view_layer.update()
bpy.context.view_layer.objects.active = other
seen["flat"] = error_of(lambda: bpy.ops.manikin.solve_pose())
bpy.data.objects.remove(flat, do_unlink=True)

# A scenario's cylinder (a post in front of the right hand, 2 cm clearance) imported as a cylinder obstacle; the hand's
# target put inside it (the shelf cube gone): the solve keeps the arm out of the post's clearance.
post = WORK / "post.toml"
post.write_text(exported.read_text(encoding="utf-8") + '\n[[obstacles]]\nname = "post"\nkind = "cylinder"\n'
                'a = [-0.2, -0.45, 0.0]\nb = [-0.2, -0.45, 1.4]\nradius = 0.05\nclearance = 0.02\n',
                encoding="utf-8")  # fmt: skip
bpy.context.view_layer.objects.active = other
seen["import_post"] = sorted(bpy.ops.manikin.import_scenario(filepath=str(post)))
read = {ob.name: ob for ob in problem_io.read_problem(other).problem.obstacles}
post_object = bpy.data.objects["post"]
seen["post"] = dict(shape=post_object.manikin_obstacle.shape, read=type(read["post"]).__name__,
                    a=list(read["post"].a), b=list(read["post"].b), radius=read["post"].radius,
                    clearance=read["post"].clearance)  # fmt: skip
bpy.data.objects.remove(bpy.data.objects["shelf.top"], do_unlink=True)
bpy.data.objects["target.hand_r"].matrix_world.translation = other.matrix_world @ Vector((-0.2, -0.45, 1.0))
bpy.context.view_layer.update()
bpy.context.view_layer.objects.active = other
seen["post_solve"] = sorted(bpy.ops.manikin.solve_pose())
result = json.loads(other["manikin_result"])
seen["post_result"] = dict(unmet=result["unmet"], broken=result.get("broken"), closest=result["closest"],
                           capsules=result["capsules"])  # fmt: skip

OUT.write_text(json.dumps(seen), encoding="utf-8")
exit_process(0)
