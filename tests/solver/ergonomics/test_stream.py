"""``ergo`` streamed (solver.ergonomics.stream): each frame's JSON text and CSV row are those of the frame's whole
report (:func:`solver.ergonomics.report.frame_report`) character for character, though the joint loads are written
from their arrays; the frames handed back for the summary hold their joint loads as dicts."""

from __future__ import annotations

import csv
import dataclasses
import json
from itertools import islice
from pathlib import Path

import numpy as np
import pytest

import solver
from solver.body.spatial import cross
from solver.ergonomics import ErgoOptions, run
from solver.ergonomics.loads import subtree_sums
from solver.ergonomics.manikin import resolve_model, working_area
from solver.ergonomics.report import csv_cells, csv_header, csv_row, frame_parts, frame_report
from solver.ergonomics.report_text import LoadsText
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


def _subtree_sums_again(frame) -> tuple[np.ndarray, np.ndarray]:
    """:func:`solver.ergonomics.loads.subtree_sums` as written before its columns were kept across frames."""
    link = [*range(len(frame.link_names)), *(frame.tcp_link[c[0]] for c in frame.contacts)]
    link += [frame.tcp_link[ld[0]] for ld in frame.loads]
    q = np.vstack([frame.link_com, *(c[1] for c in frame.contacts), *(ld[1] for ld in frame.loads)])
    f = np.vstack(
        [frame.link_mass[:, None] * frame.gravity, *(c[2] for c in frame.contacts), *(ld[2] for ld in frame.loads)]
    )
    free = np.zeros((len(frame.link_names), 3))
    for tcp, _, _, moment in frame.contacts:
        free[frame.tcp_link[tcp]] += moment
    acts = np.array(frame.below_weights)[:, link]
    return acts @ f, acts @ cross(q, f) + frame.below_weights @ free


def test_subtree_columns_kept_across_frames_are_those_taken_again(result_file: Path) -> None:
    """The subtree matrix's columns for the point forces, kept from frame to frame, are what each frame's contacts
    and loads give, also when they move to other links or there are fewer of them."""
    frames = list(ResultStream(result_file))
    fewer = dataclasses.replace(frames[1], contacts=frames[1].contacts[:1], loads=[])
    moved = dataclasses.replace(frames[2], loads=[(frames[2].contacts[0][0], *frames[2].loads[0][1:])])
    assert frames[0].contacts and frames[0].loads
    for frame in [*frames, fewer, moved, frames[0]]:
        for got, again in zip(subtree_sums(frame), _subtree_sums_again(frame), strict=True):
            np.testing.assert_allclose(got, again, rtol=1e-12, atol=1e-9)


def test_working_area_box_shown_per_frame_is_the_rounded_box_and_a_new_dict(result_file: Path) -> None:
    stream = ResultStream(result_file)
    area = working_area(resolve_model(None, stream.scenario, result_file.parent)[0])
    expected = {k: [round(v, 3) for v in b] for k, b in area.as_dict().items()}
    first = area.rounded()
    first["x"].append(1.0)  # a report changing its copy changes no other frame's
    assert area.rounded() == expected and area.rounded() is not area.rounded()
    assert area.outside_by(np.zeros(3)) == pytest.approx(np.linalg.norm(np.maximum([-area.x_half, area.y_back,
                                                                               area.z_low], 0.0)))  # fmt: skip


def test_joint_moments_written_once_per_run_of_equal_rows_keep_their_own_text(result_file: Path) -> None:
    """A joint's moment is written once for a run of rows with the same bits: rows equal but for the sign of a
    zero, equal rows apart, a NaN and an inf are each the text :meth:`JointLoads.as_dict` gives."""
    frame = next(iter(ResultStream(result_file)))
    stream = ResultStream(result_file)
    model = resolve_model(None, stream.scenario, result_file.parent)[0]
    loads = frame_parts(frame, ErgoOptions(), model, working_area(model), None)[1]
    rows = [[0.0, 1.5, -2.0], [-0.0, 1.5, -2.0], [-0.0, 1.5, -2.0], [0.0, 1.5, -2.0], [1e-17, 1e16, 0.1]]
    loads.moment = loads.moment.copy()
    loads.moment[: len(rows)] = rows
    loads.moment[-1] = loads.moment[0]
    text = LoadsText()
    assert text(loads) == json.dumps(loads.as_dict(), allow_nan=False) and '"moment": [-0.0, 1.5, -2.0]' in text(loads)
    for bad in (np.nan, np.inf):
        loads.moment[7, 1] = bad
        assert text(loads) == json.dumps(loads.as_dict(), allow_nan=False) and '"moment": [' in text(loads)
