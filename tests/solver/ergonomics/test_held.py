"""A held pose's ergonomics computed once (solver/ergonomics/held.py): a frame whose every field but the solve's is
the frame before's bit for bit gives the report, JSON text and CSV row that computing it afresh gives; a frame that
differs in one bit or in the sign of a zero is computed; a score that reads the frame's number turns the
reuse off. Compact frames of the same joint values share their posed arrays and equal frames built afresh."""

from __future__ import annotations

import copy
import csv
import dataclasses
import json
import math
from itertools import islice
from pathlib import Path

import numpy as np
import pytest

import solver
from solver.ergonomics import ErgoOptions, run
from solver.ergonomics.base import FrameInputs, Score
from solver.ergonomics.held import HeldFrames
from solver.ergonomics.manikin import resolve_model, working_area
from solver.ergonomics.registry import SCORES
from solver.ergonomics.report import csv_cells, csv_header, csv_row, frame_parts, frame_report
from solver.ergonomics.stream import motion_of
from solver.io.result.frame import Frame
from solver.io.result.read import ResultStream

BOX_LIFT_MOTION = Path(__file__).resolve().parents[3] / "presets" / "scenarios" / "box_lift_motion.toml"
ORDER = (0, 0, 0, 1, 1, 2, 0)  # which solved frame each written frame holds: held runs, and a pose seen before
HELD = [False, True, True, False, True, False, False]


@pytest.fixture(scope="module")
def solved(tmp_path_factory) -> tuple[list, Path]:
    scenario = solver.load_motion(BOX_LIFT_MOTION)
    return [r for _, r in islice(solver.solve_motion(scenario), 3)], scenario.path


@pytest.fixture(scope="module", params=[".jsonl", ".json"])
def held_file(request, solved, tmp_path_factory) -> Path:
    """A result file whose frames repeat solved poses (ORDER), numbered 1..7; frame 3 did not converge."""
    results, scenario = solved
    pairs = [(n, results[i]) for n, i in enumerate(ORDER, start=1)]
    pairs[2] = (3, dataclasses.replace(results[0], converged=False, unmet=["hand_r.position"]))
    path = tmp_path_factory.mktemp("held") / f"held{request.param}"
    return solver.write_result(path, pairs, scenario)


def _fresh(path: Path) -> tuple[list[Frame], dict, object]:
    """Every frame of the file read and its report computed on its own (nothing kept from frame to frame)."""
    stream, options = ResultStream(path), ErgoOptions()
    motion, _ = motion_of(stream, options)
    model = resolve_model(None, stream.scenario, path.parent)[0]
    frames = []
    for index, raw in stream.raw():
        stream._last = None  # no posed arrays taken from the frame before
        frames.append(stream.frame(index, raw))
    return frames, motion, model


def test_held_frames_give_the_reports_computed_afresh(held_file: Path) -> None:
    frames, motion, model = _fresh(held_file)
    options, area = ErgoOptions(), working_area(model)
    parts, held = HeldFrames(options, model, area, motion), []
    for f in ResultStream(held_file):
        report, loads, _ = parts(f)
        held.append(parts.held)
        report["joint_loads"] = loads.as_dict()
        again = frame_report(frames[len(held) - 1], options, model, area, motion)[0]
        assert json.dumps(report, allow_nan=False) == json.dumps(again, allow_nan=False)
    assert held == HELD
    assert [f.converged for f in frames] == [True, True, False, True, True, True, True]


def test_ergo_of_held_frames_writes_the_text_and_rows_of_each_frame_computed_afresh(held_file, tmp_path) -> None:
    summary = run(held_file, tmp_path / "e.json", plots=False)
    frames, motion, model = _fresh(held_file)
    whole = [frame_report(f, ErgoOptions(), model, working_area(model), motion)[0] for f in frames]
    text = (tmp_path / "e.json").read_text(encoding="utf-8")
    written = text[text.index('"frames": [\n') + len('"frames": [\n') : text.index("\n], ")].split(",\n")
    assert written == [json.dumps(r, allow_nan=False) for r in whole]
    assert '"status": "out of reach: hand_r.position"' in written[2] and written[2][10:] != written[1][10:]
    rows = list(csv.reader((tmp_path / "e.csv").read_text(encoding="utf-8").splitlines()))
    joints = [j.removeprefix("pct_") for j in rows[0][len(csv_header(whole[0], [])) :]]
    expected = [csv_header(whole[0], joints)] + [csv_cells(csv_row(r, joints)) for r in whole]
    assert rows == [[str(v) for v in row] for row in expected]
    assert summary["frames"] == whole and summary["not_converged"] == [3]


def test_compact_frames_of_the_same_joint_values_share_their_posed_arrays(solved, tmp_path: Path) -> None:
    results, scenario = solved
    path = solver.write_result(tmp_path / "r.jsonl", [(n, results[i]) for n, i in enumerate(ORDER, 1)], scenario)
    shared, fresh = list(ResultStream(path)), _fresh(path)[0]
    for a, b in zip(shared, fresh, strict=True):
        for field in dataclasses.fields(Frame):
            x, y = getattr(a, field.name), getattr(b, field.name)
            assert json.dumps(_plain(x)) == json.dumps(_plain(y)), field.name
    assert (
        shared[1].joint_position is shared[0].joint_position
        and shared[3].joint_position is not shared[0].joint_position
    )
    assert shared[1].number == 2 and shared[1].contacts is not shared[0].contacts


def _plain(value):
    """Arrays and containers as nested lists of floats' reprs (the sign of a zero kept)."""
    if isinstance(value, np.ndarray):
        return _plain(value.tolist())
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    return repr(value)


def test_same_pose_is_bit_for_bit_and_ignores_only_the_solve(held_file: Path) -> None:
    frame = next(iter(ResultStream(held_file)))
    again = copy.deepcopy(frame)
    assert frame.same_pose(again) and not frame.same_pose(None)
    solve = dataclasses.replace(again, number=9, converged=False, unmet=("a",), broken=("b",))
    assert frame.same_pose(solve)

    def changed(edit) -> Frame:
        other = copy.deepcopy(frame)
        edit(other)
        return other

    def force_zero_sign(f: Frame) -> None:
        f.contacts[0][2][0] = -0.0 if math.copysign(1.0, f.contacts[0][2][0]) > 0 else 0.0

    def set_zero(f: Frame) -> None:
        f.contacts[0][2][0] = 0.0

    base = changed(set_zero)
    assert base.same_pose(changed(set_zero)) and not base.same_pose(
        changed(lambda f: (set_zero(f), force_zero_sign(f)))
    )
    tcp = next(iter(frame.tcp_position))
    edits = [
        lambda f: f.tcp_position[tcp].__setitem__(2, np.nextafter(f.tcp_position[tcp][2], 9.0)),
        lambda f: f.joint_value.__setitem__(5, np.nextafter(f.joint_value[5], 9.0)),
        lambda f: f.loads.append(("hand_r", np.zeros(3), np.zeros(3))),
        lambda f: f.gravity.__setitem__(2, -9.8),
        lambda f: f.joint_names.__setitem__(0, "other"),
    ]
    for edit in edits:
        assert not frame.same_pose(changed(edit))
    nan = changed(lambda f: f.link_com.__setitem__((0, 0), math.nan))
    assert nan.same_pose(copy.deepcopy(nan)) and not nan.same_pose(frame)  # the same bits give the same numbers
    radius = [changed(lambda f, r=r: setattr(f, "collision_shapes", [("x", np.zeros(3), np.ones(3), r)]))
              for r in (0.0, -0.0, math.nan)]  # fmt: skip
    assert [radius[i].same_pose(copy.deepcopy(radius[j])) for i, j in ((0, 0), (0, 1), (2, 2), (2, 0))] == [
        True, False, True, False]  # fmt: skip


class FrameNumber(Score):
    """Made up for the test: reads the frame's number, so it is not pose_only."""

    name = "frame_number_test"
    title = "Number"
    source = "test source"

    def evaluate(self, inputs: FrameInputs) -> dict:
        return dict(score=inputs.frame.number)


def test_a_score_reading_the_frame_number_turns_the_reuse_off(held_file: Path, monkeypatch) -> None:
    assert all(score.pose_only for score in SCORES.values())  # the shipped scores read the pose only
    monkeypatch.setitem(SCORES, FrameNumber.name, FrameNumber())
    frames, motion, model = _fresh(held_file)
    parts = HeldFrames(ErgoOptions(), model, working_area(model), motion)
    numbers = []
    for f in ResultStream(held_file):
        numbers.append(parts(f)[0][FrameNumber.name]["score"])
        assert not parts.held
        assert parts(f)[0] == frame_parts(f, ErgoOptions(), model, working_area(model), motion)[0]
    assert numbers == list(range(1, 8))
