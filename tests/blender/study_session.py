"""A population study from the sidebar, run by tests/blender/test_study_ui.py in a subprocess:

    BLENDER_USER_RESOURCES=<empty dir> python tests/blender/study_session.py <zip> <out.json> <work dir>

<work>/family holds a family of two (written by ``python -m solver family --points 0``). A manikin away from the
origin and turned, its right hand's target moved forward and up; Run Study for that family with two target heights
(4 runs, one worker); the study runs in a subprocess while this script drives the timer: background mode never
fires ``bpy.app.timers``, so ``poll_job`` (the registered timer function) is called here every 0.2 s until it says
it is done (returns None), each call timed. Then the table, Load Row, bad input, a study whose subprocess fails,
and a larger study (the shipped family) cancelled, started again (it goes on from its journal) and cancelled
again. Writes what it saw to JSON.
"""

from __future__ import annotations

import importlib
import json
import math
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

import session_tools  # noqa: E402
from session_tools import draw_panels, error_of, install  # noqa: E402

from blender_manikin.batch import exit_process  # noqa: E402

ZIP, OUT, WORK = Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3])
DEADLINE_S = 240.0
seen: dict = {}

import bpy  # noqa: E402
from mathutils import Matrix  # noqa: E402

module = install(ZIP)
control = importlib.import_module(module + ".blender_manikin.study.control")
panel = importlib.import_module(module + ".blender_manikin.study.panel")
properties = importlib.import_module(module + ".blender_manikin.study.properties")
study_job = importlib.import_module(module + ".blender_manikin.study.job")
seen["python_path"] = study_job.python_path()
drawn_rows: list = []


def template_list(self, list_type: str, list_id: str, data, prop: str, active_data, active_prop: str, **kw) -> None:
    """Stands in for UILayout.template_list: the list class must be registered, and each item draws."""
    ui_list = getattr(bpy.types, list_type)
    assert prop in data.bl_rna.properties and active_prop in active_data.bl_rna.properties
    for index, item in enumerate(getattr(data, prop)):
        log: list = []
        ui_list.draw_item(ui_list, bpy.context, session_tools.Layout(log), data, item, 0, active_data, active_prop,
                          index)  # fmt: skip
        drawn_rows.append(log)


session_tools.Layout.template_list = template_list


def mat(m) -> list:
    return [list(row) for row in m]


def draw() -> list:
    log: list = []
    draw_panels([panel.MANIKIN_PT_study], log)
    return log


def drive(stop_when=None) -> dict:
    """Call the timer function until the study ends (or ``stop_when(job)``); what was seen on the way."""
    lines, slowest, t0 = [], 0.0, time.monotonic()
    while time.monotonic() - t0 < DEADLINE_S:
        t = time.perf_counter()
        again = control.poll_job()
        slowest = max(slowest, time.perf_counter() - t)
        job = control.current_job()
        lines.append(job.line())
        if again is None or (stop_when is not None and stop_when(job)):
            break
        time.sleep(0.2)
    if bpy.app.timers.is_registered(control.poll_job):  # it never fires here: remove it as the timer's end would
        bpy.app.timers.unregister(control.poll_job)
    return dict(lines=lines, slowest_poll_s=slowest, state=job.state, done=job.done, total=job.total,
                seconds=time.monotonic() - t0)  # fmt: skip


def run_study() -> dict:
    t = time.perf_counter()
    result = list(bpy.ops.manikin.study_run())
    return dict(result=result, execute_s=time.perf_counter() - t, armed=bpy.app.timers.is_registered(control.poll_job))


# A manikin at (1, 0.5), turned 30 degrees; its right hand's target 20 cm forward and 15 cm up, position only.
bpy.context.scene.cursor.location = (1.0, 0.5, 0.0)
bpy.ops.manikin.add_manikin(preset="male_50")
arm = bpy.context.active_object
arm.rotation_euler.z = math.radians(30.0)
bpy.context.view_layer.update()
bpy.ops.manikin.add_target(tcp="hand_r", lock=(True, True, True, False, False, False))
target = bpy.data.objects["target.hand_r"]
target.matrix_world = (
    arm.matrix_world @ Matrix.Translation((0.0, -0.2, 0.15)) @ arm.matrix_world.inverted() @ (target.matrix_world)
)
bpy.context.view_layer.objects.active = arm
bpy.context.view_layer.update()
seen["arm"] = mat(arm.matrix_world)
seen["target"] = mat(target.matrix_world)

# The study: the family of two, the hand's target at two heights, one worker, the output in WORK.
settings = bpy.context.scene.manikin_study
settings.family = "FOLDER"
settings.family_folder = str(WORK / "family")
settings.vary, settings.tcps, settings.values = "z", "hand_r", "0.0, 0.1"
settings.workers = 1
settings.folder = str(WORK / "studies")
seen["idle_panel"] = draw()
seen["start"] = run_study()
seen["running_panel"] = draw()
seen["tiny"] = drive()
seen["status"] = settings.status
seen["study_file"] = settings.study_file
COLUMNS = ("name", "run_id", "role", "parameters", "converged", "scores", "l4_l5", "shortfall")
seen["rows"] = [{c: getattr(r, c) for c in COLUMNS} for r in settings.rows]
seen["score_titles"] = settings.score_titles
seen["done_panel"] = draw()
seen["drawn_rows"] = drawn_rows

# Load Row: the last row (male_mean, the target 10 cm higher) poses a manikin of that body where the study's stands.
settings.row_index = len(settings.rows) - 1
arm.name = "study manikin, renamed"  # identity is not the name: the row still lands where this manikin stands
seen["load"] = list(bpy.ops.manikin.study_load_row())
loaded = bpy.context.active_object
bpy.context.view_layer.update()
hand = next(ob for ob in loaded.children if ob.get("manikin_tcp") == "hand_r")
seen["loaded"] = dict(name=loaded.name, file=loaded.get("manikin_body_file"), matrix=mat(loaded.matrix_world),
                      x=list(loaded["manikin_x"]), hand=mat(hand.matrix_world),
                      result=json.loads(loaded["manikin_result"]))  # fmt: skip
seen["load_again"] = list(bpy.ops.manikin.study_load_row())
seen["manikins_after_load_again"] = sorted(ob.name for ob in bpy.data.objects if ob.type == "ARMATURE")

# Bad input: one line each, nothing started.
bpy.context.view_layer.objects.active = arm
errors = {}
(WORK / "empty").mkdir()
settings.family_folder = str(WORK / "empty")
errors["no_index"] = error_of(bpy.ops.manikin.study_run)
(WORK / "broken").mkdir()
(WORK / "broken" / "family.toml").write_text("[[members]]\nname = 'x'\n", encoding="utf-8")
settings.family_folder = str(WORK / "broken")
errors["broken_index"] = error_of(bpy.ops.manikin.study_run)
settings.family_folder = ""
errors["no_folder"] = error_of(bpy.ops.manikin.study_run)
settings.family_folder = str(WORK / "family")
settings.values = "0.1, high"
errors["bad_values"] = error_of(bpy.ops.manikin.study_run)
settings.values = "0.0, 0.1"
settings.tcps = "hand_l"  # no target of that TCP
errors["no_such_target"] = error_of(bpy.ops.manikin.study_run)
settings.tcps = "hand_r"
bpy.context.scene.cursor.location = (-2.0, 0.0, 0.0)
bpy.ops.manikin.add_manikin(preset="female_5")
bare = bpy.context.active_object
for ob in [o for o in bpy.data.objects if o.manikin_target.rig == bare]:
    bpy.data.objects.remove(ob, do_unlink=True)
errors["no_targets"] = error_of(bpy.ops.manikin.study_run)
seen["errors"] = errors

# A study whose subprocess fails (here: its study file is gone): the job ends "failed" with the error's one line.
broken = study_job.StudyJob(WORK / "gone" / "study.toml", WORK / "gone" / "out", [], 1)
t0 = time.monotonic()
while broken.poll() and time.monotonic() - t0 < DEADLINE_S:
    time.sleep(0.1)
seen["failed_job"] = dict(state=broken.state, line=broken.line())
seen["job_after_errors"] = control.current_job().state

# The shipped family (18 members) at three heights: cancelled once rows come in, started again, cancelled again.
bpy.context.view_layer.objects.active = arm
settings.family = [item[0] for item in properties.family_items()][0]
settings.values = "0.0, 0.05, 0.1"
seen["big_start"] = run_study()
seen["cancel_panel"] = None
seen["big"] = drive(stop_when=lambda job: job.done >= 1)
seen["cancel_panel"] = draw()
seen["cancel"] = list(bpy.ops.manikin.study_cancel())
seen["cancelled"] = drive()
seen["cancelled_status"] = settings.status
seen["cancelled_rows"] = len(settings.rows)
seen["again_start"] = run_study()
seen["again_kept"] = control.current_job().kept
seen["again"] = drive(stop_when=lambda job: job.done > seen["again_kept"])
bpy.ops.manikin.study_cancel()
seen["again_cancelled"] = drive()
seen["big_study_file"] = settings.study_file

# Disabled while a study runs: the study is stopped, the timer and the scene's settings go.
run_study()
job = control.current_job()
bpy.ops.preferences.addon_disable(module=module)
t0 = time.monotonic()
while job.poll() and time.monotonic() - t0 < DEADLINE_S:
    time.sleep(0.1)
seen["disabled"] = dict(state=job.state, timer=bpy.app.timers.is_registered(control.poll_job),
                        settings=hasattr(bpy.types.Scene, "manikin_study"))  # fmt: skip

OUT.write_text(json.dumps(seen), encoding="utf-8")
exit_process(0)
