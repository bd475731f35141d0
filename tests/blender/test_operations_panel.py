"""Operations from the sidebar (tests/blender/operations_panel_session.py in a subprocess, the built zip
installed): a marked box with proposed grasp empties, the list built with Add Operation, bad lists refused in one
line naming the operation, Generate Motion in the background keying the manikin, the box (following the solved
hands while held, resting where placed) and the Motion Ergonomics panel's frames; a cancelled run keys nothing;
Import Operations of the pallet preset, written back as the same tables. The keyed box is checked here against
the result file the run wrote."""

from __future__ import annotations

import tomllib

import numpy as np
import pytest
from environments import ROOT

from solver.collision import Box
from solver.io.result.read import read_result
from solver.operations.objects import WorkObject, propose_grasps

CM = 0.01
BOX_AT = [0.0, -0.45, 0.9]  # m: the session's box


@pytest.fixture(scope="module")
def session(tmp_path_factory, run_session) -> dict:
    return run_session(tmp_path_factory.mktemp("operations"), "operations_panel_session.py")


def proposed() -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """The solver's proposed two-handed grasp of the session's box (0.3 x 0.2 x 0.2 m at (0, -0.45, 0.9)): per hand
    its world (position, rotation)."""
    box = Box(name="box", center=np.array(BOX_AT), size=np.array([0.3, 0.2, 0.2]))
    grasp = propose_grasps(WorkObject("box", box, 5.0))["both sides"]
    return {tcp: (box.center + hand.position, hand.rotation) for tcp, hand in grasp.hands.items()}


def test_propose_grasps_makes_the_solver_s_proposal_as_two_empties(session: dict) -> None:
    assert session["propose_unmarked"]  # a mesh not marked is refused (poll)
    assert session["propose"] == ["FINISHED"]
    grasps = session["grasps"]
    assert sorted(grasps) == ["grasp_l", "grasp_r"]
    for tcp, (position, rotation) in proposed().items():
        empty = grasps[f"grasp_{tcp[-1]}"]
        assert empty[0] == pytest.approx(position, abs=1e-5) and np.array(empty[1]) == pytest.approx(rotation, abs=1e-5)
    # on the side faces (x = -/+0.15 m), the palm normal (the empty's z) pointing in
    assert grasps["grasp_r"][0][0] < -0.15 < 0.15 < grasps["grasp_l"][0][0]
    assert np.array(grasps["grasp_r"][1])[:, 2] == pytest.approx([1.0, 0.0, 0.0], abs=1e-6)
    assert any("grasp_l, grasp_r" in line for line in session["object_panel"])


def test_add_operation_defaults(session: dict) -> None:
    # a Get of the active object (hands auto, default priority, its MTM-1 time), then a Place of the same object
    assert session["defaults"] == [["GET", "box", "AUTO", "DEFAULT", False], ["PLACE", "box", "AUTO", "DEFAULT", False]]
    assert session["added_after_place"] == ["WAIT", True, 2]  # after a Place, with no marked object active
    assert session["moved_up"] == ["GET", "WAIT", "PLACE"] and session["order"] == ["GET", "PLACE", "WAIT"]
    listed = session["list_panel"]
    assert "1. | box" in listed and "2. | box > spot" in listed and "3. | - | 0.4 s" in listed  # a wait names nothing


def test_bad_operations_are_one_line_naming_the_operation(session: dict) -> None:
    assert "operation 2 (place box): choose its target" in session["place_without_target"]
    far = session["place_far"].strip()
    assert far.startswith("Error: operation 2 (place box): ") and "unreachable" in far and "\n" not in far
    assert "operations.toml" not in far  # the temporary scenario's path is not the user's business
    assert not session["running_after_errors"]


def test_generate_runs_in_the_background_and_keys_the_manikin(session: dict) -> None:
    assert session["generate"] == ["FINISHED"] and session["armed"]
    assert session["generate_s"] < 10.0  # plans here, solves elsewhere
    assert any("Generating" in line for line in session["running_panel"])
    assert session["run"]["state"] == "done"
    assert session["status"].startswith("Keyed frames 1-") and "cycle time" in session["status"]
    assert "box keyed too" in session["status"]
    summary = session["summary"]
    assert "operation 1 (get box)" in summary and "operation 2 (place box)" in summary and "cycle time" in summary
    assert "operation 3 (wait)" in summary
    result = read_result(session["result_file"])
    frames = [f.number for f in result.frames]
    assert frames[0] == 1 and session["frame_end"] == frames[-1]
    assert session["arm_curves"] > 50
    assert session["arm_key_frames"] == [float(f) for f in frames]
    assert any(line.startswith("Keyed frames") for line in session["done_panel"])


def test_the_box_follows_the_solved_hands_while_held_and_rests_where_placed(session: dict) -> None:
    assert session["box_curves"] == ["location[0]", "location[1]", "location[2]"]
    result = read_result(session["result_file"])
    box = {int(k): np.array(v) for k, v in session["box_at"].items()}
    first, last = result.frames[0].number, result.frames[-1].number
    start, end = box[first], box[last]
    assert start == pytest.approx(BOX_AT, abs=1e-6)
    assert end == pytest.approx([-0.25, -0.45, 0.95], abs=1e-3)  # its middle on the place's empty
    hands = {f.number: (f.tcp_position["hand_r"] + f.tcp_position["hand_l"]) / 2 for f in result.frames}
    held = [n for n in hands if min(np.linalg.norm(box[n] - start), np.linalg.norm(box[n] - end)) > 1e-6]
    assert len(held) >= 5 and max(box[n][2] for n in held) > start[2] + 0.05  # lifted and carried
    offsets = np.array([box[n] - hands[n] for n in held])
    assert np.ptp(offsets, axis=0) == pytest.approx([0, 0, 0], abs=1e-6)  # rigidly with the solved hands
    grip = np.mean([position for position, _ in proposed().values()], axis=0)
    assert offsets[0] == pytest.approx(np.array(BOX_AT) - grip, abs=1e-6)  # the plan's grasp
    # no jump at the grasp or the release: the box never moves more in a frame than the hands (2 cm allowed)
    jumps = [np.linalg.norm(box[n + 1] - box[n]) - np.linalg.norm(hands[n + 1] - hands[n]) for n in range(first, last)]
    assert max(jumps) < 2 * CM


def test_the_motion_ergonomics_panel_reads_the_generated_motion(session: dict) -> None:
    result = read_result(session["result_file"])
    assert session["stored_frames"] == [f.number for f in result.frames]
    panel = " ".join(session["ergo_panel"])
    assert "REBA" in panel or "RULA" in panel


def test_a_cancelled_run_keys_nothing(session: dict) -> None:
    assert session["second"] == ["FINISHED"] and session["cancel"] == ["FINISHED"]
    assert session["cancelled"]["state"] == "cancelled"
    assert session["cancel_status"].startswith("Cancelled") and "nothing keyed" in session["cancel_status"]
    assert session["keys_kept"]


def test_the_session_is_short(session: dict) -> None:
    assert session["session_s"] < 60.0


def test_import_operations_makes_the_objects_grasps_and_list_and_writes_them_back(session: dict) -> None:
    assert session["import"] == ["FINISHED"]
    got = session["imported"]
    preset = tomllib.loads((ROOT / "presets" / "operations" / "pallet_to_shelf.toml").read_text(encoding="utf-8"))
    assert got["fps"] == preset["operate"]["fps"] and got["marked"] and got["mass"] == pytest.approx(8.0)
    assert got["children"] == ["grasp_sides_l", "grasp_sides_r"]
    # the file's box is box.001 here (the scene has a box already): the list points at the imported one
    named = {"box": "box.001"}
    expected = [[op["do"].upper(), named.get(op.get("object")),
                 op.get("onto") or (f"op{i + 1}.{op['do']}" if ("to" in op or "at" in op) else None)]
                for i, op in enumerate(preset["operations"])]  # fmt: skip
    assert got["items"] == expected
    assert {"pallet", "bench", "shelf"} <= set(got["obstacles"]) and "box.001" not in got["obstacles"]
    back = session["written_back"]
    assert len(back["operations"]) == len(preset["operations"])
    for mine, theirs in zip(back["operations"], preset["operations"], strict=True):
        assert mine.keys() == theirs.keys()
        for key, value in theirs.items():
            assert mine[key] == (pytest.approx(value, abs=1e-6) if isinstance(value, list) else named.get(value, value))
    (box,) = back["objects"]
    source = preset["objects"][0]
    assert box["center"] == pytest.approx(source["center"], abs=1e-6)
    assert box["size"] == pytest.approx(source["size"], abs=1e-6) and box["mass"] == pytest.approx(8.0)
    sides = {g["name"]: g for g in box["grasps"]}
    assert list(sides)[0] == "sides" and set(sides) == {"sides", "sides right", "sides left"}  # the pair first
    assert sides["sides"]["hand_r"]["position"] == pytest.approx([-0.202, 0, 0], abs=1e-6)
    assert sides["sides"]["hand_l"]["rotation"] == pytest.approx([0.7071068, 0, -0.7071068, 0], abs=1e-6)
    assert sorted(o["name"] for o in back["obstacles"]) == sorted(o["name"] for o in preset["obstacles"])
    assert back["operate"]["fps"] == preset["operate"]["fps"]
    assert "nowhere.toml" in session["bad_import"]
