"""The Job panel (issue 38; tests/blender/job_panel_session.py in a subprocess, the built zip installed): the job's
inputs with the load from the bake, Assess Job rating the baked motion with every registered job method (one row
each: its verdict line, its colour, a Go to Frame button per driving frame), bad input in one line, Write Report's
one-file HTML put in place, and the verdicts marked out of date by a new bake. The bpy-free side (the same rating
as ``manikin job``): tests/blender_manikin/test_job_assess.py."""

from __future__ import annotations

import re

import pytest

from solver.job.registry import METHODS

SESSION_S = 30.0  # s: the session's budget (install, import, two bakes, three assessments, the report)


@pytest.fixture(scope="module")
def session(tmp_path_factory, run_session) -> dict:
    return run_session(tmp_path_factory.mktemp("job_panel"), "job_panel_session.py")


def test_without_a_bake_assess_job_says_so_in_one_line(session: dict) -> None:
    error = session["before_bake"].strip()
    assert re.search(r"Assess Job: .+ has no baked motion: bake the motion first \(Motion > Bake Motion\)$", error)
    assert "\n" not in error and "Traceback" not in session["log"]
    assert "Load from the bake (bake the motion first)" in session["panel_before_bake"]


def test_the_load_defaults_to_what_the_baked_hands_held(session: dict) -> None:
    assert session["bake"] == ["FINISHED"]
    assert "Load from the bake: 10.0 kg, both hands" in session["panel_baked"]
    assert session["stored"]["load_kg"] == pytest.approx(10.0, rel=1e-3) and session["stored"]["hands"] == "both"
    assert session["stored"]["motion_s"] == pytest.approx(8 / session["fps"])


def test_assess_job_shows_one_row_per_registered_method(session: dict) -> None:
    assert session["assess"] == ["FINISHED"]
    rows = session["stored"]["rows"]
    assert [r["name"] for r in rows] == list(METHODS)  # whatever the registry has, in its order
    assert [r["title"] for r in rows] == [m.title for m in METHODS.values()]
    assert all(r["severity"] in (0, 1, 2, None) for r in rows)
    lifft = next(r for r in rows if r["name"] == "lifft")
    assert re.match(r"P\(high-risk job\) \d+ % \(CD [\d.e-]+, PLM \d+ N\*m at frame \d+, 800 lifts\)", lifft["text"])
    panel, lines = session["panel_assessed"], session["lines_assessed"]
    for r in rows:
        at = panel.index(r["title"])
        shown = " ".join(t.strip() for t in panel[at + 1 : at + 1 + len(panel)] if t.startswith("    "))
        assert r["text"][:40] in shown
        title_line = next(line for line in lines if line[0] == r["title"])
        assert title_line[2] == (r["severity"] == 2)  # red rows are drawn red
    assert "Rated with 10.0 kg in both hands, 0.33 s of motion" in panel


def test_each_driving_frame_is_a_button_that_sets_the_frame(session: dict) -> None:
    wanted = [f for r in session["stored"]["rows"] for f in r["frames"]]
    jumps = [b for b in session["buttons"] if b[1] == "manikin.go_to_frame"]
    assert [frame for _, _, frame in jumps] == wanted and wanted
    assert all(text == f"Go to frame {frame}" for text, _, frame in jumps)
    assert all(1 <= f <= 8 for f in wanted)
    assert session["jumps"] and all(asked == now for asked, now in session["jumps"])


def test_bad_inputs_are_one_line_and_keep_the_last_verdicts(session: dict) -> None:
    zero = "Assess Job: Cycle time (s): expected a number in (0, 28800] s, got 0.0"
    assert session["zero_cycle"].strip().endswith(zero)
    assert re.search(r"Assess Job: Cycle time \(s\): expected at least the motion's 8 frames at 24 fps \(0\.33 s\), "
                     r"got 0\.25$", session["short_cycle"].strip())  # fmt: skip
    assert "\n" not in session["zero_cycle"].strip() and "\n" not in session["short_cycle"].strip()
    assert session["stored_after_errors"] == session["stored"]


def test_a_load_set_by_hand_is_rated(session: dict) -> None:
    assert session["assess_set"] == ["FINISHED"]
    assert session["stored_set"]["load_kg"] == 20.0 and session["stored_set"]["hands"] == "right"
    assert "Load from the bake: 10.0 kg, both hands" not in session["panel_set"]
    lifft = lambda s: next(r for r in s["rows"] if r["name"] == "lifft")["text"]  # noqa: E731
    assert lifft(session["stored_set"]) != lifft(session["stored"])


def test_write_report_writes_the_job_command_s_html(session: dict) -> None:
    assert session["write"] == ["FINISHED"]
    html = session["html"]
    assert html.startswith("<!DOCTYPE html>") and html.rstrip().endswith("</html>")
    for r in session["stored_set"]["rows"]:
        assert r["title"] in html
    if session["matplotlib"]:  # the extension ships matplotlib: the same plots and pictures as the job command's
        assert html.count("<img") >= len(METHODS) and "no matplotlib" not in html
    else:
        assert "<img" not in html and "no matplotlib" in html
    assert session["left_over"] == []  # the temporary file was renamed, none left
    bare = session["html_bare"]  # matplotlib blocked: the same verdicts and tables, no plots, and a line saying so
    assert session["write_bare"] == ["FINISHED"] and not session["bare_has_matplotlib"]
    assert "<img" not in bare and "no matplotlib" in bare
    assert all(r["title"] in bare for r in session["stored_set"]["rows"])
    error = session["file_as_folder"].strip()  # a path under a file: one line, the report kept
    assert re.search(r"Write Report: .+job.html: cannot write \(.+\)$", error) and "\n" not in error


def test_a_new_bake_marks_the_verdicts_out_of_date(session: dict) -> None:
    assert session["rebake"] == ["FINISHED"]
    assert "Out of date: the motion was baked again; Assess Job again" in session["panel_rebaked"]
    assert "Out of date: the motion was baked again; Assess Job again" not in session["panel_assessed"]


def test_the_session_stays_short(session: dict) -> None:
    parts = {k: round(v, 1) for k, v in session.items() if k.endswith("_s")}
    assert session["session_s"] < SESSION_S, parts
    assert "Traceback" not in session["log"]
