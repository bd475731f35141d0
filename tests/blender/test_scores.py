"""A new ergonomic score reaches the Blender layer with no edit of it (tests/blender/scores_session.py in a
subprocess, the built zip installed): two scores made up in the session and registered with the extension's own
registry are in the Result panel, the study table and the baked motion's report and summary lines, next to the
scores the extension ships. The bpy-free side: tests/blender_manikin/test_scores_follow_registry.py."""

from __future__ import annotations

import pytest

from solver.ergonomics.registry import SCORES, frame_scores, motion_scores
from solver.study.groups import panels


@pytest.fixture(scope="module")
def session(tmp_path_factory, run_session) -> dict:
    return run_session(tmp_path_factory.mktemp("scores"), "scores_session.py")


def test_the_scores_are_registered_after_the_shipped_ones(session: dict) -> None:
    assert session["registered"] == [*SCORES, "reach_test", "span_test"]


def test_the_result_panel_shows_each_frame_score_s_words(session: dict) -> None:
    assert session["solve"] == ["FINISHED"]
    words = session["words"]  # each frame score's brief; a motion score says nothing of one pose
    assert len(words) == len(frame_scores()) + 1 and words[-1] == "Reach 1.25"
    assert [w.split()[0] for w in words[:3]] == ["RULA", "REBA", "OWAS"] and "worksheet" in words[3]
    panel = session["result_panel"]
    assert panel[panel.index("Ergonomics (this pose)") + 1 :][: len(words)] == words


def test_the_study_table_has_a_column_for_the_new_score(session: dict) -> None:
    shipped = [(SCORES[group].title, column) for group, column, *_ in panels() if group in SCORES]
    assert shipped[:2] == [("RULA", "rula_peak"), ("REBA", "reba_peak")]
    panel = session["study_panel"]
    start = panel.index("Manikin")
    header = ["Manikin", "Role", "Values", *(title for title, _ in shipped), "Reach", "L4/L5 N", "Short mm"]
    assert panel[start : start + len(header)] == header
    cells = {"rula_peak": "5", "reba_peak": "7"}  # the row's; a score it has no peak of shows "-"
    scores = [cells.get(column, "-") for _, column in shipped]
    assert session["study_rows"] == [["male_mean", "mean", "offset_z=0.1", *scores, "3.25", "2346", "0"]]


def test_the_bake_report_holds_the_new_scores(session: dict) -> None:
    assert session["bake"] == 0
    report = session["report"]
    names = [s.name for s in frame_scores()] + ["reach_test"] + [s.name for s in motion_scores()] + ["span_test"]
    for number, frame in zip((1, 2, 3), report["frames"], strict=True):
        assert list(frame["ergonomics"]) == ["posture", "joint_loads", *names]
        assert frame["ergonomics"]["reach_test"] == {"score": number + 0.25}
        assert frame["ergonomics"]["span_test"] == {"share": (number - 1) / 2}
    assert report["span_test"] == {"start": 1, "end": 3} and report["niosh"]["origin"]["frame"] == 1
    assert report["ergonomics_sources"]["reach_test"] == "test source"
    log = session["log"]  # the bake's summary lines, as batch.py prints them
    assert ", highest Reach 3.25 (frame 3)" in log and "  Span: frames 1 to 3" in log and "  NIOSH lift: " in log


def test_no_traceback(session: dict) -> None:
    assert "Traceback" not in session["log"]
