"""The Job panel's assessment without bpy (blender_manikin/motion/job_assess.py, issue 38): the pose a bake keeps per
frame gives back the solver's frames, the job rated from them equals ``manikin job``'s rating of the same motion
(every method of the registry, the same verdict lines), the panel's inputs are checked by the job file's reader
(one line naming the panel's field), and the report is written without matplotlib. The panel itself:
tests/blender/test_job_panel.py."""

from __future__ import annotations

import json
from html import escape

import numpy as np
import pytest
from test_scores_follow_registry import ROOT, Record, _module

solver, job_assess = _module("solver"), _module("blender_manikin.motion.job_assess")
report_module, registry = _module("blender_manikin.motion.report"), _module("solver.job.registry")
frame_module, job_solver = _module("solver.io.result.frame"), _module("solver.job")
read_module = _module("solver.io.result.read")
JOB = ROOT / "presets/jobs/box_lift_job.toml"
WORK = dict(cycle_time=30.0, repetitions=800, shift=8.0, lifts_per_cycle=1, load_mass=10.0, hands="both")


@pytest.fixture(scope="module")
def baked():
    """The box-lift motion's 60 frames solved, stored as a bake stores them (the entries as JSON and back), and the
    solved (frame, Result) pairs."""
    scenario = solver.load_scenario(ROOT / "presets/scenarios/box_lift_motion.toml")
    solved = list(solver.solve_motion(scenario))
    report = report_module.MotionReport(scenario.model, "male_50", None, plots=False, store=True)
    for frame, result in solved:
        report.add(Record(frame), result)
    entries = [json.loads(text) for text in report.store.texts().values()]
    return entries, solved, scenario.model


def test_a_stored_pose_gives_back_the_solved_frame(baked) -> None:
    entries, solved, model = baked
    frames = job_assess.frames_of(job_assess.stored_poses(entries), model)
    assert [f.number for f in frames] == [n for n, _ in solved]
    for frame, (number, result) in zip(frames[::10], solved[::10], strict=True):
        direct = frame_module.frame_of_result(result, number)
        np.testing.assert_allclose(frame.joint_position, direct.joint_position, atol=1e-6)
        for name in ("hand_r", "hand_l"):
            np.testing.assert_allclose(frame.tcp_position[name], direct.tcp_position[name], atol=1e-6)
        assert [c[0] for c in frame.contacts] == [c[0] for c in direct.contacts]
        for mine, theirs in zip(frame.contacts, direct.contacts, strict=True):
            np.testing.assert_allclose(mine[2], theirs[2], rtol=1e-6, atol=1e-6)
        assert [(t, list(np.round(f, 6))) for t, _, f in frame.loads] == [
            (t, list(np.round(f, 6))) for t, _, f in direct.loads
        ]


def test_the_panel_rates_the_job_as_the_job_command_does(baked) -> None:
    entries, solved, model = baked
    work = job_assess.Work(**WORK)
    report, frames = job_assess.assess(entries, model, work, "box lift", 24.0, "Armature in test.blend")
    job = job_solver.read_job(JOB)
    direct = [frame_module.frame_of_result(result, number) for number, result in solved]
    cli = job_solver.evaluate_job(job, read_module.ResultFile(None, None, direct), model)
    rows = job_assess.verdict_rows(report)
    assert [r["name"] for r in rows] == list(registry.METHODS)  # every registered method, in its order
    assert [r["text"] for r in rows] == [v["text"] for v in cli["verdicts"].values()]
    assert [r["severity"] for r in rows] == [v["severity"] for v in cli["verdicts"].values()]
    assert all(r["frames"] == v["frames"] for r, v in zip(rows, cli["verdicts"].values(), strict=True))
    lifft = report["methods"]["lifft"]
    assert lifft["peak_load_moment_Nm"] == pytest.approx(cli["methods"]["lifft"]["peak_load_moment_Nm"], rel=1e-6)
    assert report["motion_file"] == "Armature in test.blend" and report["job"]["cycle_time_s"] == 30.0
    assert len(frames) == 60


def test_the_scene_s_load_is_the_default(baked) -> None:
    entries, _, _ = baked
    mass, hands = job_assess.scene_load(job_assess.stored_poses(entries))
    assert mass == pytest.approx(10.0, rel=1e-3) and hands == "both"
    one_hand = [e | {"pose": e["pose"] | {"loads": [x for x in e["pose"]["loads"] if x[0] == "hand_l"]}}
                for e in entries[:1]]  # fmt: skip
    assert job_assess.scene_load(one_hand)[1] == "left"
    assert job_assess.scene_load([e | {"pose": e["pose"] | {"loads": []}} for e in entries[:1]]) is None


@pytest.mark.parametrize(
    "change, words",
    [
        (dict(cycle_time=0.0), "Cycle time (s): expected a number in (0, 28800] s, got 0.0"),
        (dict(repetitions=2000), "Cycles per shift: expected at most 960 cycles of 30 s in a 8 h shift, got 2000"),
        (dict(shift=0.0), "Shift (h): expected"),
        (dict(load_mass=-1.0), "Load (kg): expected"),
        (dict(cycle_time=1.0), "Cycle time (s): expected at least the motion's 60 frames at 24 fps (2.50 s), got 1"),
    ],
)
def test_bad_inputs_are_one_line_naming_the_panel_s_field(baked, change: dict, words: str) -> None:
    entries, _, model = baked
    work = job_assess.Work(**(WORK | change))
    with pytest.raises(solver.ManikinError) as caught:
        job_assess.assess(entries, model, work, "box lift", 24.0, "Armature")
    text = str(caught.value)
    assert text.startswith(words) and "\n" not in text and "/tmp" not in text and "job.toml" not in text


def test_no_baked_pose_is_one_line() -> None:
    work = job_assess.Work(**WORK)
    with pytest.raises(solver.ManikinError, match=r"^no baked motion: bake the motion first"):
        job_assess.assess([{"frame": 1, "converged": True}], None, work, "x", 24.0, "Armature")


def test_the_report_without_matplotlib_says_what_it_left_out(baked) -> None:
    entries, _, model = baked
    report, frames = job_assess.assess(entries, model, job_assess.Work(**WORK), "box lift", 24.0, "Armature")
    text = job_assess.html_of(report, frames, plots=False)
    assert "<img" not in text and "no matplotlib" in text
    assert all(escape(v["title"]) in text and escape(v["text"]) in text for v in report["verdicts"].values())
    assert text.startswith("<!DOCTYPE html>") and text.endswith("</html>\n")


def test_a_plot_that_fails_leaves_the_report_without_plots(baked, monkeypatch) -> None:
    entries, _, model = baked
    report, frames = job_assess.assess(entries, model, job_assess.Work(**WORK), "box lift", 24.0, "Armature")
    html = _module("solver.job.html")
    drawn = html.plot

    def broken(report: dict, result: dict) -> str:
        if result.get("plot"):
            raise RuntimeError("no <display>")
        return drawn(report, result)

    monkeypatch.setattr(html, "plot", broken)
    text = job_assess.html_of(report, frames, plots=True)
    assert "<img" not in text and "could not be drawn (RuntimeError: no &lt;display&gt;)" in text
