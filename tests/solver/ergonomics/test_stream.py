"""``ergo`` streamed (solver.ergonomics.stream): each frame's JSON text and CSV row are those of the frame's whole
report (:func:`solver.ergonomics.report.frame_report`) character for character, though the joint loads are written
from their arrays; the frames handed back for the summary hold their joint loads as dicts."""

from __future__ import annotations

import csv
import dataclasses
import io
import json
import math
from itertools import islice
from pathlib import Path

import numpy as np
import pytest

import solver
from solver.body.spatial import cross
from solver.ergonomics import ErgoOptions, postures, run
from solver.ergonomics.base import FrameInputs
from solver.ergonomics.loads import load_arrays, subtree_sums
from solver.ergonomics.manikin import feet_frame, resolve_model, strengths, working_area
from solver.ergonomics.registry import in_frame_order
from solver.ergonomics.report import clean, csv_cells, csv_header, csv_row, frame_parts, frame_report
from solver.ergonomics.report_text import LoadsText
from solver.ergonomics.stream import JointColumns, array_csv_cells, motion_of, rounded_texts
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


def test_feet_frame_handed_to_the_scores_gives_what_each_computes_itself(result_file: Path) -> None:
    """frame_parts computes a frame's feet frame once (FrameInputs.feet): the posture and every score are what
    they are when each computes it again."""
    stream = ResultStream(result_file)
    model = resolve_model(None, stream.scenario, result_file.parent)[0]
    options, area = ErgoOptions(), working_area(model)
    motion, _ = motion_of(stream, options)
    for f in stream:
        feet = feet_frame(f.tcp_position, f.tcp_rotation)
        loads = load_arrays(f, strengths(f, model)[0])
        posture = postures.measure(f)
        assert postures.measure(f, feet) == posture
        given = FrameInputs(f, posture, 0.0, loads, area, options, motion, feet)
        again = FrameInputs(f, posture, 0.0, loads, area, options, motion)
        for score in in_frame_order():
            assert score.evaluate(given) == score.evaluate(again), score.name


def test_posture_rounded_and_made_json_safe_in_one_walk_is_clean_of_rounded(result_file: Path) -> None:
    frame = next(iter(ResultStream(result_file)))
    posture = postures.measure(frame)
    posture["trunk_flexion"], posture["l"]["weight_share"] = math.nan, np.float64(0.123456)
    posture["r"]["hand_lateral"], posture["r"]["elbow_flexion"] = -math.inf, np.float64(math.inf)
    got = postures.rounded(posture, clean)
    assert json.dumps(got, allow_nan=False) == json.dumps(clean(postures.rounded(posture)), allow_nan=False)
    assert got["trunk_flexion"] is None and type(got["l"]["weight_share"]) is float


def test_csv_cells_of_the_arrays_and_joint_indices_kept_per_layout(result_file: Path) -> None:
    """The CSV row written from the arrays is the row of the whole report (NaN and inf percents empty), and the
    joints' indices are found again for a frame whose joints come in another order."""
    frame = next(iter(ResultStream(result_file)))
    stream = ResultStream(result_file)
    model = resolve_model(None, stream.scenario, result_file.parent)[0]
    report, loads, _ = frame_parts(frame, ErgoOptions(), model, working_area(model), None)
    loads.percent = loads.percent.copy()
    loads.percent[[0, 1, 2]] = [math.nan, math.inf, -math.inf]
    joints = frame.joint_names[:5] + frame.joint_names[-3:]
    shown_at = JointColumns(joints)
    whole = report | {"joint_loads": loads.as_dict()}
    texts = [
        [str(v) for v in row]
        for row in (array_csv_cells(report, loads, shown_at(frame)), csv_cells(csv_row(whole, joints)))
    ]
    assert texts[0] == texts[1]
    order = frame.joint_names[::-1]
    turned = dataclasses.replace(frame, joint_names=order)
    assert shown_at(turned) == [order.index(j) for j in joints] and shown_at(frame) == [frame.index[j] for j in joints]


def test_loads_text_writes_every_not_finite_percent_as_null(result_file: Path) -> None:
    frame = next(iter(ResultStream(result_file)))
    stream = ResultStream(result_file)
    model = resolve_model(None, stream.scenario, result_file.parent)[0]
    loads = frame_parts(frame, ErgoOptions(), model, working_area(model), None)[1]
    loads.percent = loads.percent.copy()
    loads.percent[[3, 4, 5]] = [math.nan, math.inf, -math.inf]
    text = LoadsText()(loads)
    assert text == json.dumps(loads.as_dict(), allow_nan=False) and text.count('"percent_strength": null') >= 3


def _csv_line(row: list) -> str:
    out = io.StringIO()
    csv.writer(out, lineterminator="\n").writerow(row)
    return out.getvalue()


def test_rounded_texts_are_the_text_of_each_value_rounded() -> None:
    """rounded_texts's one-pass text is what the CSV writer writes of round(v, 4) ("" where not finite): values of
    every size around the bound, ties of 4 decimals (exact binary halves), signed zeros, tiny values, NaN, inf."""
    rng = np.random.default_rng(7)
    spread = rng.uniform(-1.0, 1.0, 4000) * 10.0 ** rng.uniform(-7, 12, 4000)
    ties = np.arange(-2000, 2000) / 2.0**5 + rng.integers(0, 1000, 4000)  # k/32: ties at the 4th decimal
    edges = np.array([0.0, -0.0, 5e-5, -5e-5, 4.9999e-5, 0.99995, 9.99995, 1e11 - 1e-3, 1e11, 1.5e11, 1e16, 1e-300])
    cases = (spread, np.abs(spread[np.abs(spread) < 1e11]), ties, edges, edges[:8], np.array([math.nan, 1.25, -0.0]),
             np.array([math.inf, 2.0]), np.array([]))  # fmt: skip
    for values in cases:
        one_by_one = [round(v, 4) if math.isfinite(v) else "" for v in values.tolist()]
        assert _csv_line(rounded_texts(values)) == _csv_line(one_by_one)
