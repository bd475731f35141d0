"""Result and report frames written from arrays through templates (issue 20, long motions): the same characters as
``json.dumps`` of the dicts, frame after frame, and the dicts' way for anything the templates do not cover (a
number that is not finite, a new layout, names the dicts would merge)."""

from __future__ import annotations

import copy
import dataclasses
import json
from itertools import islice
from pathlib import Path

import numpy as np
import pytest

import solver
from solver.ergonomics import ErgoOptions, checked
from solver.ergonomics.manikin import working_area
from solver.ergonomics.report import frame_parts, frame_report
from solver.ergonomics.report_text import LoadsText, dumps_filled
from solver.ergonomics.stream import PlotSeries
from solver.io.result.document import compact_frame_dict, frame_to_dict, result_to_dict, rotation_quaternion
from solver.io.result.frame_text import SLOT, Numbers, PoseText
from solver.io.result.line_text import CompactText
from solver.io.values import quaternion

BOX_LIFT_MOTION = Path(__file__).resolve().parents[4] / "presets" / "scenarios" / "box_lift_motion.toml"


@pytest.fixture(scope="module")
def solved() -> list[tuple[int, solver.Result]]:
    """Frames of the furnished box lift: contacts, a load, a carried box, closest pairs."""
    return list(islice(solver.solve_motion(solver.load_motion(BOX_LIFT_MOTION)), 4))


@pytest.fixture(scope="module")
def frames(solved) -> list[solver.Frame]:
    return [solver.frame_of_result(result, number) for number, result in solved]


def test_result_frames_are_the_json_of_their_dicts(solved, frames) -> None:
    pose = PoseText()  # one writer: the template of the first frame serves the others
    for (number, result), f in zip(solved, frames, strict=True):
        assert pose(f) == json.dumps(frame_to_dict(f))
        assert pose.result_frame(result, number) == json.dumps(result_to_dict(result, number))
    assert frames[0].contacts and frames[0].loads and solved[0][1].closest  # what the frames hold is covered


def compact_json(result: solver.Result, number: int) -> str:
    return json.dumps(compact_frame_dict(result, number), separators=(",", ":"))


def test_compact_lines_are_the_json_of_their_dicts(solved) -> None:
    text = CompactText()  # one writer: each frame's joint values that kept their bits keep their text
    for number, result in [*solved, *solved[::-1]]:
        assert text(result, number) == compact_json(result, number)


def test_a_compact_line_with_a_value_not_finite_is_the_json_of_its_dict(solved) -> None:
    text = CompactText()
    number, result = solved[1]
    text(solved[0][1], solved[0][0])
    broken = dataclasses.replace(result, x=result.x.copy())
    broken.x[3] = np.inf
    line = text(broken, number, result.state)
    assert line == json.dumps(compact_frame_dict(broken, number, result.state), separators=(",", ":"))
    assert "Infinity" in line and text(result, number) == compact_json(result, number)


def test_quaternions_remembered_by_their_bits_are_those_computed(solved) -> None:
    signed = np.eye(3)
    signed[0, 1] = signed[2, 0] = -0.0
    for _, result in solved:
        for rotation, _ in result.problem.target_frames(result.state).values():
            for matrix in (rotation, rotation.T, signed, np.eye(3)):
                assert rotation_quaternion(matrix) == quaternion(matrix) == rotation_quaternion(matrix.copy())
    flipped = np.diag([-1.0, -1.0, 1.0])
    assert rotation_quaternion(flipped) == quaternion(flipped) != rotation_quaternion(np.eye(3))


def test_a_number_not_finite_goes_the_dicts_way(frames) -> None:
    pose = PoseText()
    pose(frames[0])
    f = copy.copy(frames[1])
    f.link_com = f.link_com.copy()
    f.link_com[3, 1] = np.nan
    f.joint_value = f.joint_value.copy()
    f.joint_value[5] = np.inf
    assert pose(f) == json.dumps(frame_to_dict(f)) and "NaN" in pose(f) and "Infinity" in pose(f)


def test_signed_zeros_and_repeated_rows_keep_their_own_text(frames) -> None:
    rows = np.array([[0.0, 1.5, -2.0], [-0.0, 1.5, -2.0], [0.0, 1.5, -2.0], [1e-17, 1e16, 0.1]])
    assert Numbers().rows(rows) == [json.dumps(r)[1:-1] for r in rows.tolist()]
    f = copy.copy(frames[0])
    f.joint_axis = f.joint_axis.copy()
    f.joint_axis[0] = -0.0 * f.joint_axis[0]
    assert PoseText()(f) == json.dumps(frame_to_dict(f))


def test_a_new_layout_gets_a_new_template(frames) -> None:
    pose = PoseText()
    pose(frames[0])
    names = list(frames[1].joint_names)
    names[2] = 'root %s and 100 % "quoted"'  # the template's own characters in a name
    limits = frames[1].joint_range.copy()
    limits[7] = [-1.0, np.inf]
    renamed = dataclasses.replace(frames[1], joint_names=names, joint_range=limits)
    assert pose(renamed) == json.dumps(frame_to_dict(renamed))
    assert pose(frames[2]) == json.dumps(frame_to_dict(frames[2]))  # and back


@pytest.fixture(scope="module")
def parts(solved, frames) -> list[tuple[dict, object]]:
    model = solved[0][1].problem.model
    options = checked(ErgoOptions(manikin="box lift"))
    return [frame_parts(f, options, model, working_area(model), None)[:2] for f in frames]


def test_report_frames_are_the_json_of_their_dicts(solved, frames, parts) -> None:
    model = solved[0][1].problem.model
    options = checked(ErgoOptions(manikin="box lift"))
    text = LoadsText()
    for f, (report, loads) in zip(frames, parts, strict=True):
        whole = frame_report(f, options, model, working_area(model), None)[0]
        assert whole == report | {"joint_loads": loads.as_dict()}
        assert text(loads) == json.dumps(loads.as_dict(), allow_nan=False)
        assert dumps_filled(report | {"joint_loads": SLOT}, text(loads)) == json.dumps(whole, allow_nan=False)
        assert np.isnan(loads.percent).any() and np.isfinite(loads.percent).any()  # both kinds of percent covered


def test_loads_not_finite_are_null_as_in_the_dicts(parts) -> None:
    loads = copy.copy(parts[0][1])
    loads.percent = loads.percent.copy()
    loads.percent[:3] = [np.inf, -np.inf, np.nan]
    text = LoadsText()
    assert text(loads) == json.dumps(loads.as_dict(), allow_nan=False)
    loads.moment = loads.moment.copy()
    loads.moment[4, 2] = np.nan
    assert text(loads) == json.dumps(loads.as_dict(), allow_nan=False) and '"moment": [' in text(loads)


def test_a_slot_twice_is_not_filled() -> None:
    assert dumps_filled({"a": SLOT, "b": [1.5]}, "[2]") == '{"a": [2], "b": [1.5]}'
    assert dumps_filled({"a": SLOT, "b": SLOT}, "[2]") is None


def test_plot_series_reads_the_arrays_as_the_dicts(parts) -> None:
    from_dicts, from_arrays = PlotSeries(), PlotSeries()
    for report, loads in parts:
        from_dicts.add(report | {"joint_loads": loads.as_dict()})
        from_arrays.add(report, loads)
    assert from_arrays.report() == from_dicts.report()


def test_tcp_frames_in_one_go_are_those_of_each(solved) -> None:
    for _, result in solved:
        kin = result.state.kin
        tcps = list(result.problem.model.tcps.values())
        rotations, positions = kin.tcp_frames(tcps)
        for tcp, rotation, position in zip(tcps, rotations, positions, strict=True):
            one = kin.tcp_frame(tcp)
            # the same up to a few ulp: a stack of matrices may go through other BLAS kernels than one matrix does
            np.testing.assert_allclose(rotation, one[0], rtol=0, atol=1e-14)
            np.testing.assert_allclose(position, one[1], rtol=0, atol=1e-14)
    assert kin.tcp_frames([])[0].shape == (0, 3, 3)


def test_a_result_evaluates_its_pose_once(solved, monkeypatch) -> None:
    """The writer and the report of a frame share the result's state; a solved result's is its solve's last."""
    calls = []
    forward = solver.Model.forward
    monkeypatch.setattr(solver.Model, "forward", lambda self, theta: calls.append(1) or forward(self, theta))
    scenario = solver.load_scenario(BOX_LIFT_MOTION)
    result = solver.solve(scenario.problem, scenario.start, scenario.options)
    before = len(calls)
    state = result.state
    assert state is result.state and state.kin is result.state.kin and state.statics is result.state.statics
    assert len(calls) == before  # no kinematics computed again
    fresh = result.problem.state_of_x(result.x.copy())
    assert np.array_equal(fresh.kin.position, state.kin.position) and np.array_equal(fresh.kin.com, state.kin.com)
    np.testing.assert_array_equal(fresh.statics.load_points, state.statics.load_points)
    result.x = result.x.copy()  # another x: another state
    assert result.state is not state and result.state.x is result.x
    other = result.problem.state_of_x(result.x + 0.01)
    assert "kin" not in result.problem.state_of_x(result.x).adopt(other).__dict__  # not the same point: not taken


def test_a_held_pose_keeps_its_text_and_shares_its_arrays_until_it_moves(solved) -> None:
    """Frames of the same solver kinematics share the posed arrays and the pose's text; a frame of the same
    kinematics with another contact force, or of other kinematics, is written again: each the text of its dicts."""
    (n0, r0), (n1, r1) = solved[0], solved[1]
    pushed = dataclasses.replace(r0, contacts=[dict(c) for c in r0.contacts])
    pushed.contacts[0]["force"] = pushed.contacts[0]["force"] + np.array([0.0, 0.0, 1e-9])
    pose, kept = PoseText(), []
    for number, result in [(n0, r0), (n0 + 1, r0), (n0 + 2, pushed), (n1, r1), (n1 + 1, r1), (n1 + 2, r0)]:
        assert pose.result_frame(result, number) == json.dumps(result_to_dict(result, number))
        kept.append(pose._frames._last[1])
    assert kept[1].joint_position is kept[0].joint_position is kept[2].joint_position
    assert kept[3].joint_position is not kept[2].joint_position and kept[5].joint_position is not kept[0].joint_position
    assert kept[4].number == n1 + 1 and kept[1].contacts is not kept[0].contacts
