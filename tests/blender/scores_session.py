"""A score registered in the installed extension, run by tests/blender/test_scores.py in a subprocess:

    BLENDER_USER_RESOURCES=<empty dir> python tests/blender/scores_session.py <zip> <out.json> <work dir>

registers two scores made up here (a frame score with a float per frame, a motion score) with the extension's own
registry (``solver.ergonomics.registry.register``, as a new score's line there would), then: Solve Pose and the
Result panel drawn; the study table filled from a row that has the new score's peak and drawn; a three-frame bake
of the box lift by the headless job (what batch.py runs) with a report. Not one line of the Blender layer names
them. Writes what it saw to JSON.
"""

from __future__ import annotations

import importlib
import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

import session_tools  # noqa: E402
from session_tools import draw_panels, install  # noqa: E402

from blender_manikin.batch import exit_process  # noqa: E402

ZIP, OUT, WORK = Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3])
LIFT = ROOT / "presets" / "scenarios" / "box_lift_motion.toml"
seen: dict = {}

import bpy  # noqa: E402

module = install(ZIP)
base = importlib.import_module(module + ".solver.ergonomics.base")
registry = importlib.import_module(module + ".solver.ergonomics.registry")
pose_panels = importlib.import_module(module + ".blender_manikin.pose.panels")
study_panel = importlib.import_module(module + ".blender_manikin.study.panel")
control = importlib.import_module(module + ".blender_manikin.study.control")
job = importlib.import_module(module + ".blender_manikin.motion.job")


class Reach(base.Score):
    """Made up: the frame number and a quarter."""

    name = "reach_test"
    title = "Reach"
    source = "test source"

    def evaluate(self, inputs) -> dict:
        return dict(score=inputs.frame.number + 0.25)


class Span(base.MotionScore):
    """Made up: the motion's first and last frame numbers, and each frame's share of the way."""

    name = "span_test"
    title = "Span"
    source = "test source"

    def ends(self, options) -> dict:
        return {"start": None, "end": None}

    def motion(self, start, end, options) -> dict:
        return dict(start=start.number, end=end.number)

    def keep(self, frame) -> int:
        return frame.number

    def at_frame(self, kept, motion, options) -> dict:
        return dict(share=(kept - motion["start"]) / max(motion["end"] - motion["start"], 1))

    def motion_lines(self, report: dict) -> list[str]:
        return [f"Span: frames {report[self.name]['start']} to {report[self.name]['end']}"]


registry.register(Reach())
registry.register(Span())
seen["registered"] = list(registry.SCORES)

# Solve Pose: the Result panel's ergonomics.
bpy.ops.manikin.add_manikin(preset="male_50")
arm = bpy.context.active_object
bpy.ops.manikin.add_target(tcp="hand_r")
bpy.data.objects["target.hand_r"].location.y -= 0.2
bpy.context.view_layer.objects.active = arm
seen["solve"] = sorted(bpy.ops.manikin.solve_pose())
seen["words"] = json.loads(arm["manikin_result"])["scores"]
seen["result_panel"] = []
draw_panels([pose_panels.MANIKIN_PT_result], seen["result_panel"])

# The study table, filled as the timer fills it when a study ends, and drawn (each row's cells too).
drawn_rows: list = []


def template_list(self, list_type: str, list_id: str, data, prop: str, active_data, active_prop: str, **kw) -> None:
    """Stands in for UILayout.template_list: each item draws."""
    ui_list = getattr(bpy.types, list_type)
    for index, item in enumerate(getattr(data, prop)):
        log: list = []
        ui_list.draw_item(ui_list, bpy.context, session_tools.Layout(log), data, item, 0, active_data, active_prop,
                          index)  # fmt: skip
        drawn_rows.append(log)


session_tools.Layout.template_list = template_list
row = dict(manikin="family/male_mean", run_id="r1", role="mean", p_offset_z=0.1, converged=True, rula_peak=5,
           reba_peak=7, reach_test_peak=3.25, niosh_li=0.4, l4_l5_peak_N=2345.6, shortfall_m=0.0)  # fmt: skip
control.fill_table(bpy.context.scene.manikin_study, [row])
seen["study_panel"] = []
draw_panels([study_panel.MANIKIN_PT_study], seen["study_panel"])
seen["study_rows"] = drawn_rows

# A bake of three frames with a report, as batch.py runs it (its lines are in the session's output).
report = WORK / "report.json"
seen["bake"] = job.run(job.Job(scenario=LIFT, frames=(1, 3), report=report))
seen["report"] = json.loads(report.read_text(encoding="utf-8"))

OUT.write_text(json.dumps(seen), encoding="utf-8")
exit_process(0)
