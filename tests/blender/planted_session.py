"""Planted feet, moving the manikin, the target list and the pose messages, run by tests/blender/test_planted.py:

    BLENDER_USER_RESOURCES=<empty dir> python tests/blender/planted_session.py <zip> <out.json> <work dir>

through the operators a user's buttons call: Add Manikin, Add Target 2.5 m ahead of the right hand, Solve (the
feet stay, the hand ends short); Feet = May slide, Solve (converges, the feet slid and say how far), the same in
live mode; the manikin moved onto a platform (its targets come along); a foot target left in the world below the
floor, a plane obstacle on a table, Solve in Edit mode (each with its message); the target list. Writes what it
saw to JSON; bpy is imported here only.
"""

from __future__ import annotations

import importlib
import json
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from session_tools import Layout, draw_panels, error_of, install  # noqa: E402

from blender_manikin.batch import exit_process  # noqa: E402

ZIP, OUT, WORK = Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3])
seen: dict = {}
t0 = time.perf_counter()

import bpy  # noqa: E402

module = install(ZIP)
panels = importlib.import_module(module + ".blender_manikin.pose.panels")
live = importlib.import_module(module + ".blender_manikin.pose.live")
view_layer = bpy.context.view_layer


def result() -> dict:
    return json.loads(arm["manikin_result"])


def solve() -> dict:
    """Solve Pose on the manikin; what the result says (and the done set, and how long it took)."""
    view_layer.objects.active = arm
    start = time.perf_counter()
    done = sorted(bpy.ops.manikin.solve_pose())
    data = result()
    kept = ("converged", "moved", "notes", "broken", "shortfall", "unmet")
    return dict(done=done, seconds=time.perf_counter() - start, **{k: data[k] for k in kept})


def world(name: str) -> list[float]:
    return list(bpy.data.objects[name].matrix_world.translation)


def tcp_world(tcp: str) -> list[float]:
    ob = next(c for c in arm.children if c.get("manikin_tcp") == tcp)
    return list(ob.matrix_world.translation)


seen["install_s"] = time.perf_counter() - t0
bpy.ops.manikin.add_manikin(preset="male_50")
arm = bpy.context.active_object
feet = [bpy.data.objects["target.foot_l"], bpy.data.objects["target.foot_r"]]
seen["default"] = dict(feet=arm.manikin.feet, locks=[list(f.manikin_target.lock) for f in feet],
                       parents=[f.parent.name if f.parent else None for f in feet])  # fmt: skip

# A hand target 2.5 m ahead: planted feet stay where they are and the hand ends short.
bpy.ops.manikin.add_target(tcp="hand_r")
hand = bpy.data.objects["target.hand_r"]
seen["hand_parent"] = hand.parent.name if hand.parent else None
hand.location.y -= 2.5
view_layer.update()
feet_before = [tcp_world("foot_l"), tcp_world("foot_r")]
seen["far_planted"] = solve()
view_layer.update()
seen["far_planted"]["feet_shift"] = [max(abs(a - b) for a, b in zip(tcp_world(t), p, strict=True))
                                     for t, p in zip(("foot_l", "foot_r"), feet_before, strict=True)]  # fmt: skip

# Feet = May slide: the reach converges by sliding, and says how far.
arm.manikin.feet = "SLIDE"
seen["far_slide"] = solve()
supports = importlib.import_module(module + ".blender_manikin.scene.supports")
seen["far_slide"]["words"] = supports.moved_text(seen["far_slide"]["moved"])
log: list = []
draw_panels(panels.classes[1:], log)
seen["far_slide"]["panel"] = log

# Feet = May step: the same reach, stepping within a step of each foot's target; each step reported (not a slide).
bpy.ops.manikin.reset_pose()
arm.manikin.feet = "STEP"
t_step = time.perf_counter()
hand.location.y += 2.5 - 1.4  # 1.4 m ahead: beyond planted reach, within a step
view_layer.update()
seen["far_step"] = solve()
seen["far_step"]["steps"] = result()["steps"]
seen["far_step"]["step_lines"] = result()["step_lines"]
log = []
draw_panels(panels.classes[1:], log)
seen["far_step"]["panel"] = log
hand.location.y -= 2.5 - 1.4
view_layer.update()
seen["far_step"]["seconds_all"] = time.perf_counter() - t_step

# Live honours the setting too: planted again, live on, the far target re-solved by the (stand-in) timer.
bpy.ops.manikin.reset_pose()
arm.manikin.feet = "PLANTED"
arm.manikin.live = True
view_layer.update()
live.solve_pending()
seen["live_planted"] = dict(converged=result()["converged"], moved=result()["moved"])
arm.manikin.feet = "SLIDE"
live.solve_pending()
seen["live_slide"] = dict(converged=result()["converged"], moved=result()["moved"])
arm.manikin.live = False
if bpy.app.timers.is_registered(live.solve_pending):
    bpy.app.timers.unregister(live.solve_pending)

# The hand target back within reach; the manikin moved onto a 0.3 m platform and turned: its targets come along.
arm.manikin.feet = "PLANTED"
bpy.ops.manikin.reset_pose()
hand.location.y += 2.5 - 0.15
seen["near"] = solve()
before = {ob.name: world(ob.name) for ob in (hand, *feet)}
arm.location = (1.0, 0.5, 0.3)
arm.rotation_euler.z = 0.4
view_layer.update()
seen["moved_rig"] = solve()
seen["moved_rig"]["target_shift"] = {name: [a - b for a, b in zip(world(name), p, strict=True)]
                                     for name, p in before.items()}  # fmt: skip
seen["moved_rig"]["foot_z"] = [tcp_world("foot_l")[2], tcp_world("foot_r")[2]]

# A foot target left in the world (unparented, as a scenario's are) with the manikin lifted 0.3 m more: below the
# manikin's floor; the message says so and what to do.
left = feet[0]
frame = left.matrix_world.copy()
left.parent = None
left.matrix_world = frame
arm.location.z += 0.3
view_layer.update()
seen["below_floor"] = solve()
arm.location.z -= 0.3
view_layer.update()  # the armature's world matrix, before the foot target is parented to it again
left.parent = arm
left.matrix_world = frame
view_layer.update()
bpy.ops.manikin.reset_pose()  # the failed solve left the legs bent towards the sunken foot
seen["back"] = solve()

# A plane obstacle on a table: an endless half-space above the feet; the message names it.
bpy.ops.mesh.primitive_plane_add(size=0.8, location=(1.0, 0.0, 1.05))
plane = bpy.context.active_object
plane.name = "table top"
plane.manikin_obstacle.enabled, plane.manikin_obstacle.shape = True, "PLANE"
seen["plane"] = solve()
seen["plane"]["words"] = supports.moved_text(seen["plane"]["moved"])
bpy.data.objects.remove(plane, do_unlink=True)

# Units of every residual the Result panel shows.
data = result()
seen["residuals"] = {name: panels._shown(name, value) for name, value in data["residuals"].items()}

# Solve in Edit mode: the poll says what to do instead.
view_layer.objects.active = arm
bpy.ops.object.mode_set(mode="EDIT")
seen["edit_mode"] = error_of(bpy.ops.manikin.solve_pose)
bpy.ops.object.mode_set(mode="OBJECT")

# The target list: registered, every target of the manikin listed, a row click selects its empty.
objects = bpy.data.objects
bpy.ops.manikin.add_load(tcp="hand_l", mass=2.0)
view_layer.objects.active = arm
flags = panels.listed(arm, objects)
ui_list = getattr(bpy.types, "MANIKIN_UL_targets", None)
rows: list = []
for ob, on in zip(objects, flags, strict=True):
    if on:
        ui_list.draw_item(None, bpy.context, Layout(rows), objects, ob, 0, arm.manikin, "target_index")
shown, _order = ui_list.filter_items(type("List", (), {"bitflag_filter_item": 1 << 30})(), bpy.context, bpy.data,
                                     "objects")  # fmt: skip
arm.manikin.target_index = objects.find("target.hand_r")
seen["list"] = dict(
    registered=ui_list is not None and issubclass(ui_list, bpy.types.UIList),
    listed=sorted(ob.name for ob, on in zip(objects, flags, strict=True) if on),
    filtered=sorted(ob.name for ob, flag in zip(objects, shown, strict=True) if flag),
    members=sorted(ob.name for ob in objects if ob.manikin_target.role != "NONE" and ob.manikin_target.rig == arm),
    rows=rows,
    active_after_click=bpy.context.view_layer.objects.active.name,
    index_after_click=arm.manikin.target_index == objects.find("target.hand_r"),
)
log = []
draw_panels(panels.classes[1:], log)  # the main panel with its list, and the Target panel of the clicked row
seen["list"]["panel"] = log
seen["seconds"] = time.perf_counter() - t0

OUT.write_text(json.dumps(seen), encoding="utf-8")
exit_process(0)
