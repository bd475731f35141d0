"""The score registry: every registered score fills the report, the CSV, the summary and the study from one class,
and a new score needs no line outside its own class and its registration."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import solver
from solver.comfort import STANDARD
from solver.ergonomics import ErgoOptions, evaluate, run
from solver.ergonomics.base import Bands, FrameInputs, Score
from solver.ergonomics.registry import SCORES, frame_scores, in_frame_order, motion_scores, register
from solver.ergonomics.report import csv_rows, sources, summary_lines
from solver.ergonomics.rula import Rula
from solver.errors import UsageError
from solver.io.result.write import write_result
from solver.problem.problem import Problem
from solver.study import groups
from solver.study.runner import columns, scores

REPO = Path(__file__).resolve().parents[3]
pytestmark = pytest.mark.filterwarnings("ignore:.*deprecated - use:DeprecationWarning")  # matplotlib's pyparsing


@pytest.fixture(scope="module")
def solved() -> list:
    """The box lift's pose as three frames of a motion (1, 2, 3), 10 kg in the hands; the standard model (trunk 0),
    whose stoop bends the trunk over 60 deg, from its own start (the zero pose: the scenario's start is the behaviour
    model's crouch)."""
    scenario = solver.load_scenario(REPO / "presets/scenarios/box_lift.toml")
    problem = scenario.problem_at(1)
    problem = Problem(problem.model, problem.spec.replace(comfort_weights=STANDARD, comfort=None))
    result = solver.solve(problem, problem.start(), scenario.options)
    return [(k, result) for k in (1, 2, 3)]


class TrunkBend(Score):
    """A score made up for the test: the trunk's forward bend in three bands (1: <= 20 deg, 2: <= 60, 3: more)."""

    name = "trunk_bend"
    title = "Trunk"
    source = "test"
    bands = Bands("trunk bend class", (0.5, 1.5, 2.5, 3.5), "1 upright, 2 bent, 3 far")

    def evaluate(self, inputs: FrameInputs) -> dict:
        if "reason" in inputs.posture:
            return dict(score=None, reason=inputs.posture["reason"])
        bend = abs(inputs.posture["trunk_flexion"])
        return dict(score=1 if bend <= 20 else 2 if bend <= 60 else 3, bend_deg=round(bend, 1))


def test_every_registered_score_has_its_entries_columns_and_sources(solved) -> None:
    report = evaluate(solved)
    header, rows = csv_rows(report)
    first = report["frames"][0]
    expected = ["frame", "converged", "status"] + [c for s in in_frame_order() for c in s.columns(first)]
    assert header[: len(expected)] == expected and all(c.startswith("pct_") for c in header[len(expected) :])
    assert {len(r) for r in rows} == {len(header)}
    assert [k for k in first if k in SCORES] == [s.name for s in in_frame_order()]  # frame scores, then motion
    assert list(sources()) == list(report["sources"]) and all(s.name in report["sources"] for s in SCORES.values())
    assert [s.name for s in motion_scores()] == ["niosh"] and report["niosh"]["LI"] > 0
    for score in SCORES.values():
        assert score.name and score.title and score.source
        assert len(score.cells(first)) == len(score.columns(first))
        assert all(c in groups.groups()[score.name] for c in score.study_columns())
    line = summary_lines(report | {"written": []})[0]
    assert line.startswith("frame 1: RULA ") and ", REBA " in line and ", OWAS " in line and "worksheet" in line


def test_a_new_score_is_one_class_and_one_registration(solved, monkeypatch, tmp_path: Path) -> None:
    before = evaluate(solved)
    header_before = csv_rows(before)[0]
    monkeypatch.setitem(SCORES, TrunkBend.name, TrunkBend())  # what register(TrunkBend()) in registry.py does
    after = evaluate(solved)
    frame = after["frames"][0]
    assert frame["trunk_bend"] == {"score": 3, "bend_deg": pytest.approx(abs(frame["posture"]["trunk_flexion"]))}
    assert list(frame).index("trunk_bend") == list(frame).index("niosh") - 1  # the last frame score, then motion
    assert after["sources"]["trunk_bend"] == "test"
    strip = {k: v for k, v in after.items() if k not in ("frames", "sources")}
    assert strip == {k: v for k, v in before.items() if k not in ("frames", "sources")}
    assert [{k: v for k, v in f.items() if k != "trunk_bend"} for f in after["frames"]] == before["frames"]
    header = csv_rows(after)[0]
    assert header.index("ws_overall") < header.index("trunk_bend") == header.index("niosh_H_cm") - 1
    assert "trunk_bend" not in header_before
    assert "Trunk 3" in summary_lines(after | {"written": []})[0]
    # the study: a group of its own (recorded by default), its peak column, its panel
    assert "trunk_bend" in groups.record() and groups.groups()["trunk_bend"] == ["trunk_bend_peak"]
    assert "trunk_bend_peak" in columns([], groups.record()) and scores(after)["trunk_bend_peak"] == 3
    assert ("trunk_bend", "trunk_bend_peak", "Trunk (peak)", ()) in groups.panels()
    # the files: JSON and CSV carry it, the scores plot has a panel more (5.5 in at 110 dpi each)
    result = tmp_path / "r.json"
    write_result(result, solved, REPO / "presets/scenarios/box_lift.toml")
    out = run(result, tmp_path / "e.json", ErgoOptions())
    assert json.loads((tmp_path / "e.json").read_text())["frames"][2]["trunk_bend"]["score"] == 3
    assert (tmp_path / "e.csv").read_text().splitlines()[0].split(",").count("trunk_bend") == 1
    width = int.from_bytes((tmp_path / "e_scores.png").read_bytes()[16:20], "big")
    panels = [s.name for s in frame_scores() if s.bands is not None]
    assert panels[:2] == ["rula", "reba"] and panels[-1] == "trunk_bend" and out["frame_count"] == 3
    assert width == round(len(panels) * 5.5 * 110)


def test_a_taken_name_is_refused() -> None:
    with pytest.raises(ValueError, match="'rula' is taken"):
        register(Rula())
    with pytest.raises(ValueError, match="'posture' is taken"):
        register(type("Posture", (TrunkBend,), {"name": "posture"})())
    assert [s.name for s in frame_scores()][:4] == ["rula", "reba", "owas", "worksheet"]


def _same(a: object, b: object) -> bool:
    """Equal, numbers to rounding (the file's kinematics are computed again from its joint values)."""
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() == b.keys() and all(_same(a[k], b[k]) for k in a)
    if isinstance(a, float) and isinstance(b, float):
        return a == pytest.approx(b, rel=1e-12, abs=1e-12)
    return a == b


def test_a_motion_score_reads_its_frames_by_number_in_memory_and_streamed(solved, tmp_path: Path) -> None:
    """The NIOSH lift from frame 2 to frame 2 (a one-frame lift, D from the travel): the same from the frames in
    memory and from the file read frame by frame; a number that is no frame is one line naming the option."""
    options = ErgoOptions(origin=2, destination=2, travel=0.5)
    whole = evaluate(solved, options)
    result = tmp_path / "r.json"
    write_result(result, solved, REPO / "presets/scenarios/box_lift.toml")
    streamed = run(result, tmp_path / "e.json", options, plots=False)
    assert _same(streamed["niosh"], whole["niosh"]) and whole["niosh"]["origin"]["frame"] == 2
    assert whole["niosh"]["origin"]["D"] == pytest.approx(50.0)
    for source in (solved, result):
        with pytest.raises(UsageError, match=r"^destination 9: not a frame of the result \(its frames: 1, 2, 3\)$"):
            (evaluate if source is solved else lambda s, o: run(s, tmp_path / "x.json", o))(
                source, ErgoOptions(destination=9)
            )
