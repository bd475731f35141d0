"""A reach envelope computed from the sidebar, and two messages, run by tests/blender/test_envelope_compute.py:

    BLENDER_USER_RESOURCES=<empty dir> python tests/blender/envelope_compute_session.py <zip> <out.json> <work dir>

A manikin away from the origin and turned; Compute Envelope on a coarse setting (the front half of 12 directions,
10 cm tolerance, 2 kg) runs in a subprocess while this script drives the timer (background mode never fires
``bpy.app.timers``: ``poll_job`` is called every 0.2 s until it returns None, each call timed); the result is
imported onto the manikin. The same settings again import the finished files at once; a full sphere is cancelled
(nothing imported). Then the messages: a study varying a target the manikin does not have, and an OBJ Manikin did
not write imported as an envelope. Writes what it saw to JSON.
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

from session_tools import draw_panels, error_of, install  # noqa: E402

from blender_manikin.batch import exit_process  # noqa: E402

ZIP, OUT, WORK = Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3])
DEADLINE_S = 120.0
seen: dict = {"t0": time.monotonic(), "marks": {}}


def mark(name: str) -> None:
    """When (s since the start) a part of the session ended."""
    seen["marks"][name] = round(time.monotonic() - seen["t0"], 2)


import bpy  # noqa: E402

module = install(ZIP)
mark("installed")
control = importlib.import_module(module + ".blender_manikin.envelope.control")
panel = importlib.import_module(module + ".blender_manikin.envelope.panel")
heavy = ("scipy", "matplotlib")


def draw() -> list:
    log: list = []
    draw_panels([panel.MANIKIN_PT_envelope], log)
    return log


def envelopes() -> dict:
    """Every envelope object: its parent, vertex count and world-space vertices."""
    bpy.context.view_layer.update()  # imported by the timer: a real Blender updates the matrices as it redraws
    return {
        ob.name: dict(parent=ob.parent.name if ob.parent else None, source=ob["manikin_envelope"],
                      vertices=[list(ob.matrix_world @ v.co) for v in ob.data.vertices])
        for ob in bpy.data.objects if "manikin_envelope" in ob
    }  # fmt: skip


def compute() -> dict:
    t = time.perf_counter()
    result = list(bpy.ops.manikin.envelope_compute())
    job = control.current_job()
    return dict(result=result, execute_s=time.perf_counter() - t, armed=bpy.app.timers.is_registered(control.poll_job),
                total=job.total if job else None)  # fmt: skip


def drive(stop_when=None) -> dict:
    """Call the timer function until the envelope ends (or ``stop_when(job)``); what was seen on the way."""
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
    return dict(lines=lines, slowest_poll_s=slowest, state=job.state, seconds=time.monotonic() - t0,
                output=str(job.output))  # fmt: skip


# A manikin at (1, 0.5), turned 90 degrees.
bpy.context.scene.cursor.location = (1.0, 0.5, 0.0)
bpy.ops.manikin.add_manikin(preset="male_50")
arm = bpy.context.active_object
arm.rotation_euler.z = math.radians(90.0)
bpy.context.view_layer.update()
seen["matrix"] = [list(row) for row in arm.matrix_world]
loaded_before = {m for m in sys.modules if m.startswith(heavy)}
mark("manikin")

settings = bpy.context.scene.manikin_envelope
settings.frequency, settings.hemisphere, settings.tolerance, settings.load_kg = 1, "front", 0.1, 2.0
settings.folder = str(WORK / "envelopes")
seen["idle_panel"] = draw()
seen["start"] = compute()
arm.name = "male_50 renamed"  # while it runs: the envelope still lands on this manikin (a pointer, not its name)
seen["running_panel"] = draw()
seen["run"] = drive()
seen["onto_renamed"] = [ob.parent == arm for ob in bpy.data.objects if "manikin_envelope" in ob]
arm.name = "male_50"
seen["status"] = settings.status
seen["done_panel"] = draw()
seen["objects"] = envelopes()
mark("computed")

# The same settings again: the finished folder is imported at once, replacing the objects.
seen["again"] = compute()
seen["again_status"] = settings.status
seen["again_objects"] = sorted(envelopes())

# A whole sphere with another load: cancelled once it runs; nothing is imported.
settings.frequency, settings.hemisphere, settings.load_kg = 3, "all", 5.0
seen["big_start"] = compute()
seen["cancel_panel"] = None
seen["big"] = drive(stop_when=lambda job: time.monotonic() - job.started > 1.0)
seen["cancel_panel"] = draw()
seen["cancel"] = list(bpy.ops.manikin.envelope_cancel())
seen["cancelled"] = drive()
seen["cancelled_status"] = settings.status
seen["cancelled_objects"] = sorted(envelopes())
mark("cancelled")
seen["heavy_loaded"] = sorted({m for m in sys.modules if m.startswith(heavy)} - loaded_before)

# Message: a study varying the height of a target the manikin does not have; nothing written.
study = bpy.context.scene.manikin_study
study.vary, study.tcps, study.values, study.folder = "z", "hand_l", "0.0, 0.1", str(WORK / "studies")
bpy.ops.manikin.add_target(tcp="hand_r")
bpy.context.view_layer.objects.active = arm
seen["no_such_target"] = error_of(bpy.ops.manikin.study_run)
mark("study message")
seen["studies_written"] = sorted(str(p) for p in (WORK / "studies").rglob("*")) if (WORK / "studies").exists() else []

# Message: an OBJ another program wrote is not an envelope.
cube = "# Blender 4.2 OBJ\no Cube\n" + "".join(f"v {x} {y} {z}\n" for x in (0, 1) for y in (0, 1) for z in (0, 1))
(WORK / "cube.obj").write_text(cube + "f 1 2 4 3\nf 5 6 8 7\nf 1 2 6 5\n", encoding="utf-8")
seen["cube"] = error_of(lambda: bpy.ops.manikin.import_envelope(filepath=str(WORK / "cube.obj")))
seen["cube_objects"] = sorted(ob.name for ob in bpy.data.objects if ob.name.startswith("cube"))

# Disabled while an envelope is computed: it is stopped, the timer and the scene's settings go.
compute()
job = control.current_job()
bpy.ops.preferences.addon_disable(module=module)
t0 = time.monotonic()
while job.poll() and time.monotonic() - t0 < DEADLINE_S:
    time.sleep(0.1)
mark("disabled")
seen["disabled"] = dict(state=job.state, timer=bpy.app.timers.is_registered(control.poll_job),
                        settings=hasattr(bpy.types.Scene, "manikin_envelope"))  # fmt: skip
seen["session_s"] = time.monotonic() - seen.pop("t0")

OUT.write_text(json.dumps(seen), encoding="utf-8")
exit_process(0)
