"""Live mode with obstacles and a carried box, run by tests/blender/test_live.py in a subprocess:

    BLENDER_USER_RESOURCES=<empty dir> python tests/blender/live_session.py <zip> <out.json> <work dir>

a manikin reaching forward with a carried box between its hands (marked as an obstacle by mistake) solved with
Solve Pose; a small box obstacle beside the right forearm, an unmarked cube near it; live mode on; the obstacle
moved into the forearm, then its mesh edited, then the unmarked cube moved. The depsgraph handler is driven as in
session.py: ``view_layer.update()`` runs it, ``solve_pending()`` stands in for the timer, which background mode
never fires (so the timer is unregistered between steps to see whether the handler armed it again). Writes what it
saw to JSON; bpy is imported here only.
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
POST = 0.06  # m, the obstacle cube's edge
NEAR, FAR = 0.06, 0.20  # m, the obstacle's centre from the forearm's axis: moved to overlap it, first clear of it
seen: dict = {}

import bpy  # noqa: E402
from mathutils import Matrix, Vector  # noqa: E402

module = install(ZIP)
live = importlib.import_module(module + ".blender_manikin.pose.live")
problem_io = importlib.import_module(module + ".blender_manikin.scene.problem_io")
carried_object = importlib.import_module(module + ".blender_manikin.scene.carried_object")
Carried = importlib.import_module(module + ".solver.collision.carried").Carried
view_layer = bpy.context.view_layer


def mat(m) -> list:
    return [list(row) for row in m]


def settle() -> None:
    """Let the handler see every write so far, solve what it noted, and disarm the timer: a clean slate."""
    view_layer.update()
    live.solve_pending()
    disarm()


def disarm() -> None:
    if bpy.app.timers.is_registered(live.solve_pending):
        bpy.app.timers.unregister(live.solve_pending)


def cube(name: str, location: Vector) -> bpy.types.Object:
    bpy.ops.mesh.primitive_cube_add(size=POST, location=location)
    ob = bpy.context.active_object
    ob.name = name
    return ob


def state(arm) -> dict:
    """The pose (solver variables), the last result's stamp and where the box and the obstacle are."""
    view_layer.update()
    out = dict(x=list(arm["manikin_x"]), stamp=arm["manikin_result"], crate=mat(crate.matrix_world))
    post = bpy.data.objects.get("post")
    if post is not None:
        corners = [list(post.matrix_world @ v.co) for v in post.data.vertices]
        out.update(post=[np.min(corners, axis=0).tolist(), np.max(corners, axis=0).tolist()])
    return out


# A manikin at the origin reaching 30 cm forward and up with the right hand; a box carried between its hands,
# moved away and marked as an obstacle (the box is never one); solved with Solve Pose.
bpy.ops.manikin.add_manikin(preset="male_50")
arm = bpy.context.active_object
bpy.ops.manikin.add_target(tcp="hand_r")
bpy.data.objects["target.hand_r"].location += Vector((0.0, -0.3, 0.3))
crate = carried_object.add_carried(arm, Carried(np.array([0.3, 0.2, 0.2]), ("hand_l", "hand_r"), "crate"))
crate.matrix_world = Matrix.Translation((3.0, 3.0, 3.0))
crate.manikin_obstacle.enabled = True
view_layer.objects.active = arm
seen["solve"] = sorted(bpy.ops.manikin.solve_pose())
seen["solved"] = state(arm)
seen["arm"] = mat(arm.matrix_world)

# A 6 cm box obstacle (1 cm clearance) 20 cm beside the middle of the right forearm; an unmarked cube farther out.
forearm = next(c for c in json.loads(arm["manikin_result"])["capsules"] if c["link"] == "forearm_r")
middle = (Vector(forearm["start"]) + Vector(forearm["end"])) / 2.0
side = (Vector(forearm["end"]) - Vector(forearm["start"])).cross(Vector((0.0, 0.0, 1.0))).normalized()
post = cube("post", middle + FAR * side)
post.manikin_obstacle.enabled, post.manikin_obstacle.shape, post.manikin_obstacle.clearance = True, "BOX", 0.01
vase = cube("vase", middle + 2.0 * FAR * side)
view_layer.update()
seen["obstacles"] = sorted(ob.name for ob in problem_io.read_problem(arm).problem.obstacles)
seen["clearance"] = post.manikin_obstacle.clearance

# Live on: the first live solve, then quiet (the box follows the hands; as no obstacle it triggers nothing).
arm.manikin.live = True
settle()
seen["live_on"] = state(arm)
settle()
seen["quiet"] = state(arm)["stamp"] == seen["live_on"]["stamp"]

# The obstacle moved into the forearm: the handler arms the timer, the timer re-solves.
post.location = middle + NEAR * side
view_layer.update()
seen["armed_on_move"] = bpy.app.timers.is_registered(live.solve_pending)
seen["stale"] = state(arm)
disarm()
live.solve_pending()
seen["moved"] = state(arm)
settle()

# The obstacle's mesh edited (its vertices 1.5 cm nearer the forearm): the same.
for v in post.data.vertices:
    v.co -= 0.015 * side
post.data.update()
view_layer.update()
seen["armed_on_edit"] = bpy.app.timers.is_registered(live.solve_pending)
disarm()
live.solve_pending()
seen["edited"] = state(arm)
settle()

# The ergonomics scores: a live solve leaves them out and arms the settle timer; the timer (called here, as background
# mode never fires timers) adds this pose's scores, the same as Solve Pose's; a Solve Pose result is left alone.
shown = json.loads(arm["manikin_result"])
seen["live_result"] = dict(pending=shown.get("pending"), scores=shown.get("scores"),
                           armed=bpy.app.timers.is_registered(live.score_settled))  # fmt: skip
seen["settle_waits"] = live.score_settled() is not None  # called right after a solve: the drag may go on
live.score_settled(force=True)
scored = json.loads(arm["manikin_result"])
seen["scored"] = dict(pending=scored.get("pending"), scores=scored.get("scores"), verdicts=scored.get("verdicts"))
live.score_settled(force=True)  # nothing left: a no-op
seen["scored_twice_same"] = arm["manikin_result"] == json.dumps(scored)
if bpy.app.timers.is_registered(live.score_settled):
    bpy.app.timers.unregister(live.score_settled)
arm.manikin.live = False
view_layer.objects.active = arm
seen["solve_again"] = sorted(bpy.ops.manikin.solve_pose())  # the same pose solved by the button: its scores
seen["solved_scores"] = json.loads(arm["manikin_result"]).get("scores")
arm.manikin.live = True
settle()  # a live solve (switching Live on asks for one) and its pose write
settle()  # the write seen: the same inputs, nothing solved
if bpy.app.timers.is_registered(live.score_settled):
    bpy.app.timers.unregister(live.score_settled)

# The unmarked cube moved into the forearm: nothing armed, nothing solved.
stamp = arm["manikin_result"]
vase.location = middle
view_layer.update()
seen["armed_on_unmarked"] = bpy.app.timers.is_registered(live.solve_pending)
live.solve_pending()
seen["unmarked_unsolved"] = arm["manikin_result"] == stamp
arm.manikin.live = False

OUT.write_text(json.dumps(seen), encoding="utf-8")
exit_process(0)
