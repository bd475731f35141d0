"""A manikin's life in Blender (tests/blender/lifecycle_session.py in a subprocess, the built zip installed): Add
Manikin does not remember a body file, Add Load refuses a negative mass, renaming keeps every part attached, a new
scenario replaces the previous one's obstacles and box (per scene), and Delete / Duplicate Manikin act on all of a
manikin and nothing else."""

from __future__ import annotations

import numpy as np
import pytest


@pytest.fixture(scope="module")
def session(tmp_path_factory, run_session) -> dict:
    return run_session(tmp_path_factory.mktemp("lifecycle"), "lifecycle_session.py")


def _part(session: dict, name: str) -> dict:
    assert name not in session["crashed"], session["crashed"][name]
    return session[name]


def test_add_manikin_does_not_remember_a_body_file(session: dict) -> None:
    """Item 1: after one Add Manikin from a body file, Add > Manikin > Female 5 builds the preset (not the file's
    person), and still works once that file moved."""
    seen = _part(session, "body_file")
    assert seen["first"][0] == "" and seen["first"][1].endswith("tall.toml")
    assert seen["second"] == ["female_5", ""]
    assert seen["moved_error"] == "" and seen["third"] == ["male_50", ""]
    # what a click reuses: only the file browsers' paths (the browser sets them on every call)
    assert seen["remembered"] == [
        "export_motion.filepath", "export_scenario.filepath", "import_envelope.filepath", "import_operations.filepath",
        "import_scenario.filepath", "load_bone_map.filepath", "save_bone_map.filepath",
    ]  # fmt: skip


def test_add_load_refuses_a_negative_mass_in_one_line(session: dict) -> None:
    """Item 5: -3 kg is refused (not clamped to 0 kg silently); 4 kg hangs 39.24 N at the hand."""
    seen = _part(session, "load")
    error = seen["error"].strip()
    assert "load mass must be a non-negative number of kg, got -3.0" in error and "\n" not in error
    assert not seen["made_negative"]
    np.testing.assert_allclose(seen["force"], [0.0, 0.0, -4.0 * 9.81], atol=1e-4)


def test_renaming_changes_nothing_but_the_names(session: dict) -> None:
    """Item 2: armature, box, a target and an obstacle renamed: the box still follows the hands on Solve, is found,
    and is exported; the renamed obstacle and all targets still count."""
    seen = _part(session, "rename")
    assert seen["solved"] == ["FINISHED"] and seen["found"] == "crate"
    np.testing.assert_allclose(seen["box_after"], seen["hands"], atol=1e-4)
    assert np.linalg.norm(np.subtract(seen["box_after"], seen["box_before"])) > 0.1  # it did move with the hands
    assert seen["carried_in_export"] and seen["rack_in_export"] and seen["targets"] == 6


def test_duplicate_manikin_gives_a_working_manikin_of_its_own(session: dict) -> None:
    """Item 4: the copy has its own body, TCP empties, targets and box, 1 m to the side (keyed targets too), its
    twist drivers read its own bones, it solves; the first manikin keeps all of its parts."""
    seen = _part(session, "duplicate")
    assert seen["done"] == ["FINISHED"] and seen["is_new"] and seen["name"] == "worker.001"
    assert seen["copy"] == seen["before"] == seen["after"] and seen["tcps"] == seen["tcps_first"] > 10
    assert seen["bodies"] == ["HUMAN"] and seen["drivers"] == ["worker.001"]
    assert seen["box"] == "crate.001" and seen["box_first"] == "crate"
    np.testing.assert_allclose(seen["offset"], [1.0, 0.0, 0.0], atol=1e-6)
    first, copy = (np.array(p) for p in seen["keyed"])
    np.testing.assert_allclose(copy - first, [1.0, 0.0, 0.0], atol=1e-5)
    assert seen["solved"] == ["FINISHED"] and seen["converged"]


def test_delete_manikin_removes_all_of_it_and_nothing_else(session: dict) -> None:
    """Item 4: the copy, its 28 parts and its box go; the first manikin and its box stay; a user's tool parented
    to the copy's hand stays where it was."""
    seen = _part(session, "delete")
    assert seen["done"] == ["FINISHED"] and seen["copy_gone"] and seen["box_gone"] and seen["left"] == []
    assert seen["removed"] == 1 + 28 + 1
    assert seen["first_same"] and seen["first_box"] and seen["tool"]
    np.testing.assert_allclose(*seen["tool_where"], atol=1e-6)


def test_a_new_scenario_replaces_the_previous_ones_obstacles_and_box(session: dict) -> None:
    """Item 3: box lift, then cabinet reach: the box lift's obstacles and box are gone, the cabinet's keep their
    names when imported again; the deep squat after it meets every target (no cabinet left); with the option off
    the previous obstacles stay."""
    seen = _part(session, "replace")
    cabinet = ["cabinet back", "cabinet bottom", "cabinet shelf", "cabinet side left", "cabinet side right",
               "cabinet top"]  # fmt: skip
    assert "rack" in seen["first"]
    assert seen["after_cabinet"] == dict(obstacles=cabinet, boxes=[])
    assert seen["again"] == cabinet and seen["squat"] == []
    assert seen["solved"] == ["FINISHED"] and seen["converged"] and seen["unmet"] == []
    assert seen["kept"] == cabinet and seen["arm_alive"]


def test_each_scene_has_its_own_obstacles(session: dict) -> None:
    """Item 3: importing into a second scene leaves the first scene's obstacles and collection alone."""
    seen = _part(session, "scenes")
    assert seen["done"] == ["FINISHED"] and seen["after"] == seen["before"] and len(seen["before"]) == 6
    assert seen["second"] == 6 and not seen["shared"] and seen["second_in_first"] == []
    assert seen["collections"] == [["Obstacles"], ["Obstacles.001"]]


def test_a_manikin_deleted_with_x_is_not_solved_and_its_leftovers_can_be_deleted(session: dict) -> None:
    """Item 4: X on the armature leaves its parts; Solve on one of them says so in one line (no "Converged"), and
    Delete Manikin there removes them and the deleted armature."""
    seen = _part(session, "ghost")
    assert seen["left_by_x"] > 20
    solve = seen["solve"].strip()
    assert "belongs to the deleted manikin worker" in solve and "Delete Manikin" in solve and "\n" not in solve
    assert seen["done"] == ["FINISHED"] and seen["left"] == [] and seen["arm_gone"]


def test_the_manikin_panel_offers_delete_and_duplicate(session: dict) -> None:
    """The buttons are in the sidebar: both for a manikin; for a target left by X, the hint and Delete Manikin."""
    seen = _part(session, "ghost")
    assert {"manikin.duplicate_manikin", "manikin.delete_manikin"} <= set(seen["live_panel"]["operators"])
    assert seen["panel"]["operators"][-1] == "manikin.delete_manikin"
    assert any("belongs to the deleted manikin worker" in line for line in seen["panel"]["lines"])


def test_the_session_stays_short(session: dict) -> None:
    assert session["seconds"] < 40.0
    assert "Traceback" not in session["log"]
