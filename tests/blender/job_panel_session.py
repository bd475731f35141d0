"""The Job panel (issue 38), run by tests/blender/test_job_panel.py in a subprocess:

    BLENDER_USER_RESOURCES=<empty dir> python tests/blender/job_panel_session.py <zip> <out.json> <work dir>

installs the extension zip, imports the box-lift motion, presses Assess Job before any bake (its one line), bakes
frames 1-8 through Bake Motion, draws the Job panel (the load from the bake), presses Assess Job (the defaults: a
30 s cycle, 800 cycles in 8 h), reads the stored verdicts and the panel's rows, presses every Go to Frame button,
tries a zero cycle time and a cycle shorter than the motion, sets the load by hand, writes the report through Write
Report (again with matplotlib blocked, and under a file, as if a folder), then bakes again (the verdicts marked out
of date). Writes what it saw to JSON.
"""

from __future__ import annotations

import importlib
import json
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

import session_tools  # noqa: E402
from session_tools import draw_panels, error_of, install  # noqa: E402

from blender_manikin.batch import exit_process  # noqa: E402

ZIP, OUT, WORK = Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3])
MOTION = ROOT / "presets" / "scenarios" / "box_lift_motion.toml"
seen: dict = {}
T0 = time.perf_counter()

import bpy  # noqa: E402

module = install(ZIP)
job_panel = importlib.import_module(module + ".blender_manikin.motion.job_panel")
job_assess = importlib.import_module(module + ".blender_manikin.motion.job_assess")
buttons: list = []  # (text, operator, properties) of each button drawn
lines: list = []  # (text, icon, red) of each label drawn


class Props:
    """Stands in for the properties of a button's operator."""


def operator(self, idname: str, text: str = "", **kw) -> Props:
    group, name = idname.split(".")
    assert hasattr(getattr(bpy.ops, group), name), idname
    props = Props()
    buttons.append((text, idname, props))
    self.log.append(text)
    return props


def label(self, text: str = "", icon: str = "NONE", **kw) -> None:
    assert icon in session_tools.icons(), icon
    self.log.append(text)
    lines.append((text, icon, bool(getattr(self, "alert", False))))


session_tools.Layout.operator = operator
session_tools.Layout.label = label


def drawn() -> list[str]:
    log: list = []
    buttons.clear()
    lines.clear()
    draw_panels([job_panel.MANIKIN_PT_job], log)
    return log


bpy.ops.object.select_all(action="DESELECT")
bpy.ops.manikin.import_scenario(filepath=str(MOTION))
arm = bpy.context.active_object
NAME = arm.name
scene = bpy.context.scene
seen["fps"] = scene.render.fps / scene.render.fps_base
seen["before_bake"] = error_of(lambda: bpy.ops.manikin.assess_job())
seen["panel_before_bake"] = drawn()
seen["matplotlib"] = job_assess.has_matplotlib()

scene.frame_set(1)
t0 = time.perf_counter()
seen["bake"] = sorted(bpy.ops.manikin.bake_motion("EXEC_DEFAULT", True, frame_start=1, frame_end=8))
seen["bake_s"] = time.perf_counter() - t0
arm = bpy.data.objects[NAME]
bpy.context.view_layer.objects.active = arm
seen["panel_baked"] = drawn()

t0 = time.perf_counter()
seen["assess"] = sorted(bpy.ops.manikin.assess_job())
seen["assess_s"] = time.perf_counter() - t0
seen["stored"] = json.loads(arm["manikin_job_verdicts"])
seen["panel_assessed"] = drawn()
seen["lines_assessed"] = list(lines)
seen["buttons"] = [(text, idname, getattr(props, "frame", None)) for text, idname, props in buttons]
seen["jumps"] = []
for _, idname, props in list(buttons):
    if idname == "manikin.go_to_frame":
        bpy.ops.manikin.go_to_frame(frame=props.frame)
        seen["jumps"].append([props.frame, scene.frame_current])

s = arm.manikin_job
s.cycle_time = 0.0
seen["zero_cycle"] = error_of(lambda: bpy.ops.manikin.assess_job())
s.cycle_time = 0.25  # shorter than the 8 frames at 24 fps (0.33 s)
seen["short_cycle"] = error_of(lambda: bpy.ops.manikin.assess_job())
seen["stored_after_errors"] = json.loads(arm["manikin_job_verdicts"])  # the last good assessment stays
s.cycle_time, s.load_source, s.load_mass, s.hands = 30.0, "SET", 20.0, "right"
seen["panel_set"] = drawn()
seen["assess_set"] = sorted(bpy.ops.manikin.assess_job())
seen["stored_set"] = json.loads(arm["manikin_job_verdicts"])

report = WORK / "job.html"
t0 = time.perf_counter()
seen["write"] = sorted(bpy.ops.manikin.write_job_report(filepath=str(report)))
seen["write_s"] = time.perf_counter() - t0
seen["html"] = report.read_text(encoding="utf-8")
seen["left_over"] = sorted(p.name for p in WORK.iterdir() if p.name.startswith("job") and p.name != "job.html")
kept = sys.modules.get("matplotlib")
sys.modules["matplotlib"] = None  # as in a Blender whose Python has no matplotlib (an add-on built without wheels)
seen["bare_has_matplotlib"] = job_assess.has_matplotlib()
seen["write_bare"] = sorted(bpy.ops.manikin.write_job_report(filepath=str(WORK / "bare.html")))
seen["html_bare"] = (WORK / "bare.html").read_text(encoding="utf-8")
sys.modules["matplotlib"] = kept
seen["file_as_folder"] = error_of(lambda: bpy.ops.manikin.write_job_report(filepath=str(report / "job.html")))

scene.frame_set(1)
seen["rebake"] = sorted(bpy.ops.manikin.bake_motion("EXEC_DEFAULT", True, frame_start=1, frame_end=3))
bpy.context.view_layer.objects.active = bpy.data.objects[NAME]
seen["panel_rebaked"] = drawn()
seen["session_s"] = time.perf_counter() - T0

OUT.write_text(json.dumps(seen), encoding="utf-8")
print("job panel session done")
exit_process(0)
