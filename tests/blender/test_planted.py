"""Planted feet, moving the manikin, the target list and the pose messages (tests/blender/planted_session.py in a
subprocess, the built zip installed): a reach too far no longer converges by sliding both feet unless Feet is set to
"May slide", and then the slide is reported in mm."""

from __future__ import annotations

import pytest


@pytest.fixture(scope="module")
def session(tmp_path_factory, run_session) -> dict:
    return run_session(tmp_path_factory.mktemp("planted"), "planted_session.py")


def test_new_feet_are_planted_supports_parented_to_the_manikin(session: dict) -> None:
    default = session["default"]
    assert default["feet"] == "PLANTED"
    assert default["locks"] == [[True] * 6, [True] * 6]
    assert default["parents"] == ["male_50", "male_50"] and session["hand_parent"] == "male_50"


def test_a_reach_too_far_ends_short_with_the_feet_where_they_were(session: dict) -> None:
    far = session["far_planted"]
    assert far["done"] == ["FINISHED"] and not far["converged"]
    assert far["moved"] == {} and max(far["feet_shift"]) < 1e-3
    assert far["broken"] == [] and far["unmet"] == ["hand_r"]
    assert far["shortfall"]["hand_r"].endswith("deg") and float(far["shortfall"]["hand_r"].split()[0]) > 500.0


def test_may_slide_converges_and_says_how_far_each_foot_slid(session: dict) -> None:
    slide = session["far_slide"]
    assert slide["converged"] and sorted(slide["moved"]) == ["foot_l", "foot_r"]
    assert all(2000.0 < m["mm"] < 2600.0 for m in slide["moved"].values())
    assert len(slide["words"]) == 2 and all(" slid " in w and w.split(",")[0].endswith(" mm") for w in slide["words"])
    assert any(line.startswith("foot_r slid ") for line in slide["panel"])  # the Result panel says it too


def test_may_step_meets_the_reach_with_steps_reported_not_slides(session: dict) -> None:
    step = session["far_step"]
    assert step["done"] == ["FINISHED"] and step["converged"], step
    assert step["moved"] == {} and step["steps"]  # a step, not a slide
    for s in step["steps"]:  # within a step (0.4 x 1.75 m), ahead, turned within 45 deg
        assert 0.05 < s["length"] <= 0.701 and abs(s["direction_deg"]) < 45.0 and abs(s["turn_deg"]) <= 45.2
    assert all(" stepped " in line and " m, " in line for line in step["step_lines"])
    assert all(line in step["panel"] for line in step["step_lines"])  # the Result panel says it too
    assert step["seconds_all"] < 10.0


def test_live_mode_honours_the_feet_setting(session: dict) -> None:
    assert not session["live_planted"]["converged"] and session["live_planted"]["moved"] == {}
    assert session["live_slide"]["converged"] and sorted(session["live_slide"]["moved"]) == ["foot_l", "foot_r"]


def test_moving_the_manikin_carries_its_targets(session: dict) -> None:
    assert session["near"]["converged"]
    moved = session["moved_rig"]
    assert moved["converged"] and moved["moved"] == {} and moved["notes"] == []
    for shift in moved["target_shift"].values():
        assert abs(shift[2] - 0.3) < 1e-4 and abs(shift[0]) + abs(shift[1]) > 0.5  # up on the platform, across
    assert all(abs(z - 0.3) < 0.05 for z in moved["foot_z"])  # the soles on the platform


def test_a_support_below_the_floor_says_so(session: dict) -> None:
    below = session["below_floor"]
    assert not below["converged"] and "foot_l" in below["broken"]
    assert any(n.startswith("foot_l: its support target is 300 mm below the manikin's floor") for n in below["notes"])
    assert session["back"]["converged"]


def test_an_obstacle_pushing_the_feet_is_named(session: dict) -> None:
    plane = session["plane"]
    assert not plane["converged"] and set(plane["broken"]) >= {"foot_l", "foot_r"}
    assert any("obstacle 'table top'" in n and n.startswith("foot_") for n in plane["notes"])
    assert plane["words"] and all(w.endswith(" off its target") for w in plane["words"])  # pushed, not "slid"


def test_every_residual_has_its_unit(session: dict) -> None:
    units = ("mm", "deg", " N", "N m", "(m and rad combined)")
    assert session["residuals"] and all(text.endswith(units) for text in session["residuals"].values())
    assert session["residuals"]["floor.shortfall"].endswith(" mm")


def test_solve_in_edit_mode_says_what_to_do(session: dict) -> None:
    assert "switch to Pose or Object mode" in session["edit_mode"]


def test_the_target_list_lists_every_target_and_selects_a_clicked_row(session: dict) -> None:
    listed = session["list"]
    assert listed["registered"]
    every = ["load.hand_l", "target.foot_l", "target.foot_r", "target.hand_r"]
    assert listed["filtered"] == listed["listed"] == listed["members"] == every
    assert {"target.hand_r", "load.hand_l", "2.0 kg"} <= set(listed["rows"])
    assert listed["active_after_click"] == "target.hand_r" and listed["index_after_click"]


def test_the_session_stays_short(session: dict) -> None:
    """Its own work, after installing the zip (about 15 s, as every session; 8 s of work measured on 5.0, idle)."""
    assert session["seconds"] - session["install_s"] < 25.0
