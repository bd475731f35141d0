"""``ergo`` streamed (solver.ergonomics.stream): each frame's JSON text and CSV row are those of the frame's whole
report (:func:`solver.ergonomics.report.frame_report`) character for character, though the joint loads are written
from their arrays; the frames handed back for the summary hold their joint loads as dicts."""

from __future__ import annotations

import csv
import json
from itertools import islice
from pathlib import Path

import pytest

import solver
from solver.ergonomics import ErgoOptions, run
from solver.ergonomics.manikin import resolve_model, working_area
from solver.ergonomics.report import csv_cells, csv_header, csv_row, frame_report
from solver.ergonomics.stream import motion_of
from solver.io.result.read import ResultStream

BOX_LIFT_MOTION = Path(__file__).resolve().parents[3] / "presets" / "scenarios" / "box_lift_motion.toml"


@pytest.fixture(scope="module")
def result_file(tmp_path_factory) -> Path:
    scenario = solver.load_motion(BOX_LIFT_MOTION)
    solved = list(islice(solver.solve_motion(scenario), 4))
    return solver.write_result(tmp_path_factory.mktemp("stream") / "four.jsonl", solved, scenario.path)


def test_streamed_frames_are_the_text_of_their_whole_reports(result_file: Path, tmp_path: Path) -> None:
    summary = run(result_file, tmp_path / "e.json", plots=False)
    stream, options = ResultStream(result_file), ErgoOptions()
    motion, first = motion_of(stream, options)
    model = resolve_model(None, stream.scenario, result_file.parent)[0]
    whole = [frame_report(f, options, model, working_area(model), motion)[0] for f in stream]
    text = (tmp_path / "e.json").read_text(encoding="utf-8")
    frames = text[text.index('"frames": [\n') + len('"frames": [\n') : text.index("\n], ")].split(",\n")
    assert frames == [json.dumps(r, allow_nan=False) for r in whole]
    rows = list(csv.reader((tmp_path / "e.csv").read_text(encoding="utf-8").splitlines()))
    joints = rows[0][len(csv_header(whole[0], [])) :]
    assert joints and [j.removeprefix("pct_") for j in joints] != joints
    joints = [j.removeprefix("pct_") for j in joints]
    expected = [csv_header(whole[0], joints)] + [csv_cells(csv_row(r, joints)) for r in whole]
    assert rows == [[str(v) for v in row] for row in expected]
    assert summary["frames"] == whole and summary["highest_reba"] in whole
    assert all(isinstance(f["joint_loads"]["l4_l5"], dict) and len(f["joint_loads"]) > 1 for f in summary["frames"])
