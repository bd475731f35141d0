"""Motion ergonomics in the sidebar after a bake (issue 33; tests/blender/motion_ergo_session.py in a subprocess,
the built zip installed): per-frame entries and graph curves stored by Bake Motion, the Motion Ergonomics panel
(the NIOSH lift, each score's worst frame naming the item at fault, worst frames that set the scene's frame, the
current frame's worksheet), the Result panel following the frame until a later solve, and the messages: frame
numbers on out-of-reach lines, discomfort shown non-negative. The bpy-free side: tests/blender_manikin/
test_frame_store.py and tests/solver/ergonomics/test_verdicts.py."""

from __future__ import annotations

import re

import numpy as np
import pytest

from solver.ergonomics.registry import SCORES, frame_scores

FRAMES = [1, 2, 3, 4, 5, 6]
FLOAT32 = 1e-5


@pytest.fixture(scope="module")
def session(tmp_path_factory, run_session) -> dict:
    return run_session(tmp_path_factory.mktemp("motion_ergo"), "motion_ergo_session.py")


def test_the_bake_stores_each_frame_and_keys_the_scores_as_curves(session: dict) -> None:
    assert session["bake"] == ["FINISHED"]
    stored = session["stored"]
    assert session["stored_keys"] == sorted([*map(str, FRAMES), "head"])
    for frame in FRAMES:
        entry = stored[str(frame)]
        assert entry["frame"] == frame and entry["converged"]
        assert [v["score"] for v in entry["verdicts"]] == [s.name for s in frame_scores()]
    head = stored["head"]
    assert (head["frame_start"], head["frame_end"]) == (1, 6)
    graphed = [name for name, _, _ in head["graphs"]]
    assert graphed == [s.name for s in frame_scores() if stored["1"]["graph"].get(s.name) is not None]
    assert {"rula", "reba", "owas", "worksheet"} <= set(graphed)
    curves = session["graph_curves"]  # on the armature's data: the Graph Editor's curves, not in the exported action
    assert set(curves) == {f'["{prop}"]' for _, _, prop in head["graphs"]}
    for name, title, prop in head["graphs"]:
        assert title == SCORES[name].title
        keys = np.array(curves[f'["{prop}"]'])
        assert keys[:, 0].tolist() == FRAMES
        np.testing.assert_allclose(keys[:, 1], [stored[str(f)]["graph"][name] for f in FRAMES], atol=FLOAT32)
    assert session["arm_other_curves"] == []  # the object's action holds the bones only
    assert all(size > 10_000 for size in session["exported"].values())  # the exports still write the bones


def test_the_panel_shows_the_lift_and_where_each_score_is_worst(session: dict) -> None:
    panel, head = session["ergo_panel"], session["stored"]["head"]
    assert panel[0] == "Baked frames 1-6" and panel[1].startswith("Graph Editor (armature data): manikin_rula")
    assert any(re.fullmatch(r"NIOSH lift: RWL [\d.]+ kg, load 10\.0 kg, LI [\d.]+", line) for line in panel)
    sheet = next(text for text, _, _ in head["worst_of_each"] if "worksheet" in text)
    # not "Worst level: red": the level, the frame and the items at that level with their values
    assert re.fullmatch(
        r"L4/L5 \d+ N, worksheet (red|yellow) at frame \d \(worst level \1: back bend [\d.]+ deg.*\)", sheet
    )
    assert sheet in panel


def test_the_worst_frames_are_buttons_that_set_the_frame(session: dict) -> None:
    head = session["stored"]["head"]
    buttons = [(text, frame) for text, idname, frame in session["ergo_buttons"] if text.startswith("Frame ")]
    assert [frame for _, frame in buttons] == head["worst"] and len(buttons) == 5
    worst = session["stored"][str(head["worst"][0])]
    top = max(v["severity"] for v in worst["verdicts"])
    assert buttons[0][0] == f"Frame {head['worst'][0]}: " + ", ".join(
        v["text"] for v in worst["verdicts"] if v["severity"] == top
    )
    assert all(idname == "manikin.go_to_frame" for _, idname, _ in session["ergo_buttons"])
    assert session["jumps"] and all(asked == now for asked, now in session["jumps"])  # pressing one sets the frame


def test_the_current_frame_s_worksheet_item_by_item(session: dict) -> None:
    panel, entry = session["ergo_at_4"], session["stored"]["4"]
    start = panel.index("Frame 4")
    lines = panel[start + 1 :]
    assert lines[: len(entry["verdicts"])] == [f"{v['text']}: {v['level']}" for v in entry["verdicts"]]
    items = lines[lines.index("worksheet, item by item:") + 1 :]
    assert items == ["  " + text for text, _ in entry["details"]["worksheet"]] and len(items) >= 8
    assert session["ergo_outside"][-1] == "Frame 9 is outside the baked frames"


@pytest.mark.parametrize("frame", [3, 5])
def test_the_result_panel_follows_the_frame(session: dict, frame: int) -> None:
    shown, entry = session["result_at"][str(frame)], session["stored"][str(frame)]
    panel = shown["panel"]
    assert panel[0] == f"Baked frame {frame}"
    assert panel[1].startswith(f"Converged: {entry['iterations']} it, ")
    words = panel[panel.index("Ergonomics (this pose)") + 1 :][: len(entry["scores"])]
    assert words == entry["scores"]
    assert f"Discomfort {-entry['comfort']:.3f} (0 = best; parts before weights: " in " ".join(panel)
    drawn = {text: (icon, red) for text, icon, red in shown["lines"]}
    for v in entry["verdicts"]:  # the icon and the red of each score's words, then what its level means
        assert drawn[v["text"]] == ({0: "CHECKMARK", 1: "ERROR", 2: "ERROR"}[v["severity"]], v["severity"] == 2)
        assert f"{v['title']}: {v['level']}" in panel
    assert any(line.startswith("OWAS: action category ") for line in panel)


def test_outside_the_bake_or_after_a_solve_the_result_panel_shows_the_last_solve(session: dict) -> None:
    assert not session["result_outside"][0].startswith("Baked frame")
    assert session["solve"] == ["FINISHED"]
    after, last = session["result_after_solve"], session["last_result"]
    assert after[0] == f"Converged: {last['iterations']} it, {last['time_ms']:.0f} ms"
    assert [v["text"] for v in last["verdicts"]] == last["scores"]  # the solve stores the verdicts too


def test_discomfort_is_never_negative(session: dict) -> None:
    panels = [
        session["result_outside"],
        session["result_after_solve"],
        *(r["panel"] for r in session["result_at"].values()),
    ]
    values = [float(line.split()[1]) for p in panels for line in p if line.startswith("Discomfort ")]
    assert len(values) == len(panels) and min(values) >= 0
    assert not any(line.startswith("Comfort ") for p in panels for line in p)


def test_out_of_reach_lines_name_their_frame(session: dict) -> None:
    ((frame, converged, unmet, notes, why),) = session["far_records"]
    assert (frame, converged) == (8, False) and "head" in unmet
    assert why.startswith("frame 8: out of reach: ") and "head short by" in why
    assert session["far_finish"] == ["FINISHED"]
    assert session["far_reports"][0] == ["WARNING", "Baked 1 frames; 1 did not converge: 8"]
    assert session["far_reports"][1:] == [["WARNING", why]]  # the note itself had no frame number
    assert why in session["motion_panel"]


def test_no_traceback(session: dict) -> None:
    assert "Traceback" not in session["log"]
