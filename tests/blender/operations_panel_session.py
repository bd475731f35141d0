"""Operations from the sidebar (issue 36), run by tests/blender/test_operations_panel.py in a subprocess:

    BLENDER_USER_RESOURCES=<empty dir> python tests/blender/operations_panel_session.py <zip> <out.json> <work dir>

installs the extension zip; a manikin and a 5 kg box (a cube scaled to 0.3 x 0.2 x 0.2 m) before it at 0.9 m,
marked as an object; Propose Grasps; the list built with Add Operation (Get box, Place it on an empty 25 cm to
the side, Wait 0.4 s); bad lists refused in one line (a Place without a target, a Place 2.6 m up);
Generate Motion at 8 frames/s, the background run driven by calling the timer function (background mode never
fires ``bpy.app.timers``), then what was keyed (the armature's and the box's curves, the box's place per frame),
the panel, the Motion Ergonomics panel; a second run cancelled at once (nothing keyed). Writes what it saw to JSON.
"""

from __future__ import annotations

import importlib
import json
import shutil
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

import session_tools  # noqa: E402
from session_tools import draw_panels, error_of, install  # noqa: E402

from blender_manikin.batch import exit_process  # noqa: E402

ZIP, OUT, WORK = Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3])
DEADLINE_S = 120.0
seen: dict = {}
T0 = time.perf_counter()

import bpy  # noqa: E402

module = install(ZIP)
control = importlib.import_module(module + ".blender_manikin.operations.control")
panel = importlib.import_module(module + ".blender_manikin.operations.panel")
ergo_panel = importlib.import_module(module + ".blender_manikin.motion.ergonomics_panel")
keyframes = importlib.import_module(module + ".blender_manikin.scene.keyframes")
rows: list = []


class Props:
    """Stands in for the properties of a button's operator."""


def operator(self, idname: str, text: str = "", **kw) -> Props:
    group, name = idname.split(".")
    assert hasattr(getattr(bpy.ops, group), name), idname
    self.log.append(f"[{idname}]")
    return Props()


def template_list(self, list_type: str, list_id: str, data, prop: str, active_data, active_prop: str, **kw) -> None:
    """Stands in for UILayout.template_list: the list class must be registered, and each item draws."""
    ui_list = getattr(bpy.types, list_type)
    assert prop in data.bl_rna.properties and active_prop in active_data.bl_rna.properties
    for index, item in enumerate(getattr(data, prop)):
        log: list = []
        ui_list.draw_item(ui_list, bpy.context, session_tools.Layout(log), data, item, 0, active_data, active_prop,
                          index)  # fmt: skip
        rows.append(log)


session_tools.Layout.operator = operator
session_tools.Layout.template_list = template_list


def drawn(panel_class) -> list[str]:
    log: list = []
    rows.clear()
    draw_panels([panel_class], log)
    return log + [" | ".join(r) for r in rows]


def drive(stop_when=None) -> dict:
    """Call the timer function until the run ends (or ``stop_when(job)``); what was seen on the way."""
    lines, t0 = [], time.monotonic()
    while time.monotonic() - t0 < DEADLINE_S:
        again = control.poll_job()
        job = control.current_job()
        lines.append(job.line())
        if again is None or (stop_when is not None and stop_when(job)):
            break
        time.sleep(0.2)
    if bpy.app.timers.is_registered(control.poll_job):  # it never fires here: remove it as the timer's end would
        bpy.app.timers.unregister(control.poll_job)
    return dict(lines=lines, state=job.state, seconds=time.monotonic() - t0)


scene = bpy.context.scene
scene.frame_start, scene.frame_end = 1, 250
scene.frame_set(1)
bpy.ops.manikin.add_manikin(preset="male_50")
arm = bpy.context.active_object
seen["idle_panel_manikin"] = drawn(panel.MANIKIN_PT_operations)

# The box: a cube 0.3 x 0.2 x 0.2 m, 0.45 m before the manikin (it faces -y) at 0.9 m, marked, 5 kg.
bpy.ops.mesh.primitive_cube_add(size=1.0, location=(0.0, -0.45, 0.9))
box = bpy.context.active_object
box.name = "box"
box.scale = (0.3, 0.2, 0.2)
bpy.context.view_layer.update()
seen["unmarked_panel"] = drawn(panel.MANIKIN_PT_operations)
seen["propose_unmarked"] = error_of(lambda: bpy.ops.manikin.propose_grasps())
box.manikin_object.enabled, box.manikin_object.mass = True, 5.0
seen["propose"] = sorted(bpy.ops.manikin.propose_grasps())
seen["grasps"] = {c.name: [list(c.matrix_world.translation), [list(r) for r in c.matrix_world.to_3x3()]]
                  for c in box.children}  # fmt: skip
seen["object_panel"] = drawn(panel.MANIKIN_PT_operations)

# The list: Add Operation with the box active makes a Get of it; after a Get, Add makes a Place of it.
settings = scene.manikin_operations
bpy.ops.manikin.operation_add()
bpy.ops.manikin.operation_add()
seen["defaults"] = [[i.do, i.object.name if i.object else None, i.hands, i.priority, i.use_duration]
                    for i in settings.items]  # fmt: skip
bpy.context.view_layer.objects.active = arm
seen["place_without_target"] = error_of(lambda: bpy.ops.manikin.operations_generate())
far = bpy.data.objects.new("far", None)
scene.collection.objects.link(far)
far.location = (0.2, -0.5, 2.6)  # above any reach (far away would be stepped to)
settings.items[1].target = far
bpy.context.view_layer.update()
seen["place_far"] = error_of(lambda: bpy.ops.manikin.operations_generate())
seen["running_after_errors"] = control.is_running()
# The Place to an empty 25 cm to the right of where the box is, then a Wait of 0.4 s added after it (Add with the
# manikin active: a Wait); the Wait moved up and down again (the order stays Get, Place, Wait).
spot = bpy.data.objects.new("spot", None)
scene.collection.objects.link(spot)
spot.location = (-0.25, -0.45, 0.95)
settings.items[1].target = spot
settings.index = 1
bpy.ops.manikin.operation_add()
item = settings.items[2]
seen["added_after_place"] = [item.do, item.object is None, settings.index]
item.use_duration, item.duration = True, 0.4
bpy.ops.manikin.operation_move(direction="UP")
seen["moved_up"] = [i.do for i in settings.items]
bpy.ops.manikin.operation_move(direction="DOWN")
seen["order"] = [i.do for i in settings.items]
settings.fps = 8
settings.folder = str(WORK / "runs")
seen["list_panel"] = drawn(panel.MANIKIN_PT_operations)

# Generate Motion: the operator returns at once; the timer, driven here, keys the result when the run ends.
t = time.perf_counter()
seen["generate"] = sorted(bpy.ops.manikin.operations_generate())
seen["generate_s"] = time.perf_counter() - t
seen["armed"] = bpy.app.timers.is_registered(control.poll_job)
seen["running_panel"] = drawn(panel.MANIKIN_PT_operations)
seen["run"] = drive()
job = control.current_job()
seen["result_file"] = str(shutil.copy(job.result, WORK / "first_result.json"))  # the next run starts afresh
seen["status"], seen["summary"] = settings.status, settings.summary
seen["done_panel"] = drawn(panel.MANIKIN_PT_operations)
seen["frame_end"] = scene.frame_end
curves = keyframes.object_fcurves(arm)
seen["arm_curves"] = len(curves)
seen["arm_key_frames"] = sorted({k.co.x for fc in curves for k in fc.keyframe_points})
seen["box_curves"] = sorted(f"{fc.data_path}[{fc.array_index}]" for fc in keyframes.object_fcurves(box))
seen["box_at"] = {}
for frame in range(scene.frame_start, scene.frame_end + 1):
    scene.frame_set(frame)
    seen["box_at"][str(frame)] = list(box.matrix_world.translation)
scene.frame_set(1)
bpy.context.view_layer.objects.active = arm
seen["stored_frames"] = sorted(int(k) for k in arm["manikin_frames"].keys() if k != "head")
seen["ergo_panel"] = drawn(ergo_panel.MANIKIN_PT_motion_ergonomics)

# A second run cancelled at once: nothing keyed (the keys stay those of the first run).
before = [list(k.co) for k in curves[0].keyframe_points]
seen["second"] = sorted(bpy.ops.manikin.operations_generate())
seen["cancel"] = sorted(bpy.ops.manikin.operations_cancel())
seen["cancelled"] = drive()
seen["cancel_status"] = settings.status
seen["keys_kept"] = before == [list(k.co) for k in keyframes.object_fcurves(arm)[0].keyframe_points]
# Import Operations: the pallet preset with the box's grasps given (the docs' "sides"): the manikin, obstacles,
# the box marked with its grasp empties, the list with its target empties; written back as the same tables.
scenario_module = importlib.import_module(module + ".blender_manikin.operations.scenario")
text = (ROOT / "presets" / "operations" / "pallet_to_shelf.toml").read_text(encoding="utf-8")
grasps = """mass = 8.0
[[objects.grasps]]
name = "sides"
hand_r = { position = [-0.202, 0, 0], rotation = [0.7071068, 0, 0.7071068, 0], lock = ["x", "y", "z", "rx", "ry"] }
hand_l = { position = [0.202, 0, 0], rotation = [0.7071068, 0, -0.7071068, 0], lock = ["x", "y", "z", "rx", "ry"] }
"""
(WORK / "pallet.toml").write_text(text.replace("mass = 8.0\n", grasps), encoding="utf-8")
box.manikin_object.enabled = False  # the first box stays in the scene, no longer an object: the new one is box.001
seen["import"] = sorted(bpy.ops.manikin.import_operations(filepath=str(WORK / "pallet.toml")))
arm = bpy.context.active_object
pallet_box = bpy.data.objects["box.001"]
seen["imported"] = dict(
    arm=arm.name, fps=settings.fps, marked=pallet_box.manikin_object.enabled, mass=pallet_box.manikin_object.mass,
    children=sorted(c.name for c in pallet_box.children),
    items=[[i.do, i.object.name if i.object else None, i.target.name if i.target else None] for i in settings.items],
    obstacles=sorted(ob.name for ob in scene.objects if ob.manikin_obstacle.enabled),
)  # fmt: skip
seen["written_back"] = scenario_module.operations_scenario(scene, arm)
seen["bad_import"] = error_of(lambda: bpy.ops.manikin.import_operations(filepath=str(WORK / "nowhere.toml")))
seen["session_s"] = time.perf_counter() - T0

OUT.write_text(json.dumps(seen), encoding="utf-8")
exit_process(0)
