"""A Blender session as a user would have it, run by tests/blender/test_session.py in a subprocess:

    BLENDER_USER_RESOURCES=<empty dir> python tests/blender/session.py <zip> <out.json> <work dir>

installs the extension zip, enables it, adds a manikin, moves the right-hand target 30 cm forward, solves,
undoes, tries live mode, exports and imports scenarios, disables the add-on, and writes what it saw (poses,
frames, results, leftovers) to JSON for the assertions in the test. bpy is imported here only, so the pytest
process stays clean.
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

from session_tools import draw_panels, error_of  # noqa: E402

from blender_manikin.batch import exit_process  # noqa: E402
from blender_manikin.dev.build import install  # noqa: E402

ZIP, OUT, WORK = Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3])
seen: dict = {}

import bpy  # noqa: E402  (after BLENDER_USER_RESOURCES is set by the caller)


def mat(m) -> list:
    return [list(row) for row in m]


def pose_of(arm) -> dict:
    """Everything the tests compare: pose bone matrices (world), TCP empty frames, the stored solution."""
    bpy.context.view_layer.update()
    return dict(
        x=list(arm.get("manikin_x", [])),
        bones={pb.name: mat(arm.matrix_world @ pb.matrix) for pb in arm.pose.bones},
        tcps={ob["manikin_tcp"]: mat(ob.matrix_world) for ob in arm.children if "manikin_tcp" in ob},
        channels={pb.name: [pb.rotation_mode, list(pb.rotation_euler), list(pb.location)] for pb in arm.pose.bones},
    )


def ui(op, **props) -> list[str]:
    """Call an operator as the UI does: with an undo push for UNDO operators (a plain script call has none)."""
    return sorted(op("EXEC_DEFAULT", True, **props))


module = install(ZIP)
seen["module"] = module
package = sys.modules[module]
live = importlib.import_module(module + ".blender_manikin.pose.live")
overlay = importlib.import_module(module + ".blender_manikin.pose.overlay")

# A manikin, a target for the right hand, moved 30 cm forward (the manikin faces -y).
seen["add"] = ui(bpy.ops.manikin.add_manikin, preset="male_50")
arm = bpy.data.objects["male_50"]
seen["armature"] = dict(
    preset=arm["manikin_preset"], bones=len(arm.data.bones), objects=sorted(o.name for o in arm.children)
)
seen["rest"] = {b.name: [mat(b.matrix_local), b.length, b.parent.name if b.parent else None] for b in arm.data.bones}
seen["supports"] = {
    name: dict(support=s.support, lock=list(s.lock), rig=s.rig.name)
    for name in ("target.foot_l", "target.foot_r")
    for s in [bpy.data.objects[name].manikin_target]
}
seen["add_target"] = ui(bpy.ops.manikin.add_target, tcp="hand_r")
seen["add_load"] = ui(bpy.ops.manikin.add_load, tcp="hand_l", mass=0.0)  # weightless: a marker for the panel test
target = bpy.data.objects["target.hand_r"]
target.location.y -= 0.3
bpy.ops.ed.undo_push(message="Move target")  # what the UI pushes after a transform
seen["before"] = pose_of(arm)
seen["solve"] = ui(bpy.ops.manikin.solve_pose)
arm = bpy.data.objects["male_50"]
seen["after"] = pose_of(arm)
seen["undo_flag"] = "UNDO" in bpy.types.MANIKIN_OT_solve_pose.bl_options
seen["target"] = mat(bpy.data.objects["target.hand_r"].matrix_world)
seen["result"] = json.loads(arm["manikin_result"])
seen["bone_colors"] = {pb.name: [pb.color.palette, list(pb.color.custom.normal)] for pb in arm.pose.bones}
seen["overlay"] = {k: len(v) for k, v in overlay.geometry(arm, seen["result"]).items()}

# The sidebar draws (checked against a recording layout: properties, operators and icons must exist).
drawn: list = []
for active in ("male_50", "target.hand_r", "load.hand_l"):
    obj = bpy.data.objects.get(active)
    bpy.context.view_layer.objects.active = obj
    draw_panels(importlib.import_module(module + ".blender_manikin.addon").panels(), drawn)
seen["sidebar"] = drawn
bpy.context.view_layer.objects.active = bpy.data.objects["male_50"]

# Undo restores the pose before the solve (the target stays where it was moved).
bpy.ops.ed.undo()
arm = bpy.data.objects["male_50"]
seen["undone"] = pose_of(arm)
seen["undone_target"] = mat(bpy.data.objects["target.hand_r"].matrix_world)

# Errors reach the user as reports (a RuntimeError for scripts), never as tracebacks.
bpy.context.view_layer.objects.active = arm
bad = bpy.data.objects["target.hand_r"].manikin_target
bad.tcp = "hand_x"
seen["bad_tcp"] = error_of(bpy.ops.manikin.solve_pose)
bad.tcp = "hand_r"
seen["bad_preset"] = error_of(lambda: bpy.ops.manikin.add_manikin(filepath=str(WORK / "missing.toml")))

# Live mode: a moved target re-solves through the handler and the timer; the pose write does not re-trigger.
seen["add_loop"] = ui(bpy.ops.manikin.add_loop, tcp="hand_l", other="hand_r")  # the left hand rides along
seen["loop_before"] = pose_of(arm)["tcps"]
arm.manikin.live = True
bpy.context.view_layer.update()
live.solve_pending()
bpy.data.objects["target.hand_r"].location.z += 0.1
bpy.context.view_layer.update()
seen["live_armed"] = bpy.app.timers.is_registered(live.solve_pending)
live.solve_pending()
seen["live"] = pose_of(arm)
seen["live_target"] = mat(bpy.data.objects["target.hand_r"].matrix_world)
stamp = arm["manikin_result"]
bpy.context.view_layer.update()  # the handler sees the pose write ...
live.solve_pending()  # ... and finds nothing new to solve
seen["live_quiet"] = arm["manikin_result"] == stamp
settings = bpy.data.objects["target.hand_r"].manikin_target
settings.tcp = "hand_x"  # a settings edit re-solves too; the error goes to the sidebar (live mode has no report)
seen["live_timer_on_edit"] = bpy.app.timers.is_registered(live.solve_pending)
live.solve_pending()
seen["live_error"] = arm.get("manikin_error", "")
settings.tcp = "hand_r"
live.solve_pending()
seen["live_error_cleared"] = "manikin_error" not in arm
arm.manikin.live = False

# A second manikin away from the origin, turned 90 degrees: everything works in the armature's frame.
bpy.context.scene.cursor.location = (1.5, 0.5, 0.0)
ui(bpy.ops.manikin.add_manikin, preset="female_5")
turned = bpy.context.active_object
turned.rotation_euler.z = math.radians(90.0)
bpy.context.view_layer.update()
for tcp in ("foot_l", "foot_r", "hand_l"):  # snap the feet targets to the turned feet, add one for the hand
    ui(bpy.ops.manikin.add_target, tcp=tcp)
hand_target = bpy.context.active_object  # the new target is made active
hand_target.location.x += 0.15
ui(bpy.ops.manikin.add_load, tcp="hand_l", mass=2.0)
bpy.context.view_layer.objects.active = turned
seen["turned_solve"] = ui(bpy.ops.manikin.solve_pose)
seen["turned"] = dict(
    pose=pose_of(turned),
    target=mat(hand_target.matrix_world),
    result=json.loads(turned["manikin_result"]),
    matrix=mat(turned.matrix_world),
)
bpy.context.view_layer.objects.active = arm

# Scenario files: export this scene, import the box lift onto a new manikin and solve it.
exported = WORK / "exported.toml"
arm.manikin.restarts = 2  # a solver setting that must reach the file
seen["export"] = list(bpy.ops.manikin.export_scenario(filepath=str(exported)))
bpy.ops.object.select_all(action="DESELECT")
bpy.context.view_layer.objects.active = None
box = ROOT / "presets" / "scenarios" / "box_lift.toml"
seen["import"] = list(bpy.ops.manikin.import_scenario(filepath=str(box)))
lifter = bpy.context.active_object
schema = importlib.import_module(module + ".blender_manikin.scene.schema")
seen["imported"] = dict(name=lifter.name, members=sorted(o.name for o in schema.members(lifter)))
seen["import_solve"] = list(bpy.ops.manikin.solve_pose())
seen["import_result"] = json.loads(lifter["manikin_result"])
seen["import_pose"] = pose_of(lifter)
lifter.manikin.reduction = True
seen["reduced_solve"] = list(bpy.ops.manikin.solve_pose())
seen["reduced_result"] = json.loads(lifter["manikin_result"])


# Where the dependencies come from (before disabling, which uninstalls the extension's wheels).
import matplotlib  # noqa: E402
import scipy  # noqa: E402

seen["modules"] = dict(scipy=scipy.__file__, matplotlib=matplotlib.__file__)

# Disable: nothing of the add-on may stay registered.
addon = sys.modules[f"{module}.blender_manikin.addon"]
ours = addon.classes()  # everything the add-on registers
seen["ours"] = dict(
    classes=[c.__name__ for c in ours],
    types=sorted(c.__name__ for c in ours if not issubclass(c, bpy.types.PropertyGroup)),  # not in bpy.types' dir
    menus=sorted(
        draw.__module__.rpartition(".blender_manikin.")[2]
        for m in addon.modules()
        for _, draw in getattr(m, "MENUS", ())
    ),
)


def registered() -> dict:
    lists = [getattr(bpy.app.handlers, name) for name in dir(bpy.app.handlers) if not name.startswith("_")]
    handlers = [h for handler_list in lists if isinstance(handler_list, list) for h in handler_list]
    return dict(
        types=[n for n in dir(bpy.types) if n.startswith("MANIKIN_")],
        classes=[c.__name__ for c in ours if c.is_registered],
        object_props=[
            p
            for p in ("manikin", "manikin_obstacle", "manikin_retarget", "manikin_target")
            if hasattr(bpy.types.Object, p)
        ],  # fmt: skip
        handlers=[h.__module__ for h in handlers if h.__module__.startswith(module)],
        timers=bpy.app.timers.is_registered(live.solve_pending),
        menus=[
            f.__module__
            for menu in (
                bpy.types.VIEW3D_MT_add,
                bpy.types.VIEW3D_MT_object,
                bpy.types.TOPBAR_MT_file_import,
                bpy.types.TOPBAR_MT_file_export,
            )  # fmt: skip
            for f in menu._dyn_ui_initialize()
            if f.__module__.startswith(module)
        ],
        enabled=module in bpy.context.preferences.addons,
    )


live.request(arm)  # a pending timer must go too
seen["registered"] = registered()
bpy.ops.preferences.addon_disable(module=module)
seen["left"] = registered()
seen["x_is_finite"] = bool(np.isfinite(seen["after"]["x"]).all())
OUT.write_text(json.dumps(seen), encoding="utf-8")
exit_process(0)  # bpy 4.2 would segfault at exit after the glTF export
