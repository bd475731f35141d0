"""What a bake stores per frame for the sidebar (blender_manikin/motion/frame_store.py, issue 33), checked without
bpy: each frame's Result-panel summary and ergonomics (every registered score's verdict, graph number and detail
lines), the motion's head (the NIOSH lift's line, the worst frames, each score's worst frame naming the item at
fault), and a score registered for one test reaching all of it. The panels that read it: tests/blender/test_bake.py.
"""

from __future__ import annotations

import json

import pytest
from test_scores_follow_registry import FRAMES, ROOT, Reach, Record, Span, _module

store_module, solver = _module("blender_manikin.motion.frame_store"), _module("solver")
report_module, registry = _module("blender_manikin.motion.report"), _module("solver.ergonomics.registry")


@pytest.fixture(scope="module")
def result():
    """The box lift's pose (10 kg in the hands), taken as each frame of a three-frame motion."""
    scenario = solver.load_scenario(ROOT / "presets/scenarios/box_lift.toml")
    return solver.solve(scenario.problem_at(1), scenario.start, scenario.options)


@pytest.fixture
def throwaway(monkeypatch) -> None:
    """Reach and Span registered for one test."""
    monkeypatch.setitem(registry.SCORES, Reach.name, Reach())
    monkeypatch.setitem(registry.SCORES, Span.name, Span())


def baked(result, records: list | None = None):
    """The store and the motion scores' values of three frames, as the bake fills them."""
    report = report_module.MotionReport(result.problem.model, "male_50", None, plots=False, store=True)
    for record in records or [Record(frame) for frame in FRAMES]:
        report.add(record, result)
    return report.store, report.motion()


def test_each_frame_has_the_result_panel_s_keys_and_every_score_s_verdict(result) -> None:
    store, _ = baked(result)
    assert [e["frame"] for e in store.entries] == list(FRAMES)
    entry = json.loads(store.texts()["2"])  # JSON as stored on the armature, one text per frame
    for key in ("converged", "iterations", "time_ms", "unmet", "residuals", "comfort", "comfort_parts", "joint_loads",
                "contacts", "scores", "verdicts"):  # fmt: skip
        assert key in entry, key
    names = [s.name for s in registry.frame_scores()]
    assert [v["score"] for v in entry["verdicts"]] == names
    assert entry["scores"] == [v["text"] for v in entry["verdicts"]]
    assert all(v["severity"] in (0, 1, 2) and v["level"] for v in entry["verdicts"])
    assert set(entry["graph"]) == {"rula", "reba", "owas", "worksheet"} and list(entry["details"]) == ["worksheet"]
    assert len(entry["joint_loads"]) == store_module.TOP_LOADS and entry["comfort"] <= 0


def test_the_head_has_the_lift_the_worst_frames_and_where_each_score_is_worst(result) -> None:
    store, motion = baked(result)
    head = json.loads(json.dumps(store.head(motion, 7)))
    assert (head["frame_start"], head["frame_end"], head["result_crc"]) == (1, 3, 7)
    assert head["motion_lines"][0].startswith("NIOSH lift: RWL ") and head["motion_levels"][0][0] == "NIOSH"
    assert sorted(head["worst"]) == list(FRAMES)  # three equal frames: all listed, the earliest first
    assert head["worst"] == [1, 2, 3]
    sheet = next(text for text, _, _ in head["worst_of_each"] if "worksheet" in text)
    level = store.entries[0]["verdicts"][3]["level"]
    assert sheet.endswith(f" at frame 1 ({level})") and level.startswith("worst level ")
    assert [prop for _, _, prop in head["graphs"]] == ["manikin_rula", "manikin_reba", "manikin_owas",
                                                       "manikin_worksheet"]  # fmt: skip
    frames, values = store.series()["manikin_rula"]
    assert frames.tolist() == [1.0, 2.0, 3.0] and values[0] == store.entries[0]["graph"]["rula"]


def test_the_worst_frames_rank_severity_then_how_many_scores_then_reba() -> None:
    def entry(frame: int, severities: list, reba: float) -> dict:
        return dict(frame=frame, graph={"reba": reba}, verdicts=[dict(severity=s) for s in severities])

    entries = [entry(1, [0, 0], 2), entry(2, [2, 0], 4), entry(3, [2, 2], 3), entry(4, [1, None], 9)]
    entries.append(entry(5, [2, 0], 9))
    assert store_module.worst_frames(entries, 4) == [3, 5, 2, 4]


def test_a_registered_score_reaches_the_stored_frames(result, throwaway) -> None:
    store, motion = baked(result)
    assert [e["graph"]["reach_test"] for e in store.entries] == [1.25, 2.25, 3.25]
    assert "Reach 2.25" in store.entries[1]["scores"]
    head = store.head(motion, 0)
    assert ("reach_test", "Reach", "manikin_reach_test") in head["graphs"]
    assert "Span: frames 1 to 3" in head["motion_lines"]
