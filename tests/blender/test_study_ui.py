"""A population study from the sidebar (tests/blender/study_session.py in a subprocess, the built zip installed): it
runs in the background while the timer is driven, fills the table, loads a row's manikin and pose, reports bad
input in one line, and a cancelled study leaves a journal the next start goes on from. The rows and poses are
checked here against the solver itself (the study file the session wrote, solved in this process).
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from environments import ROOT

from blender_manikin.study.table import score_cell
from solver import load_scenario, solve_motion
from solver.ergonomics.registry import SCORES
from solver.population import read_family
from solver.study import load_study
from solver.study.export import row_scenario
from solver.study.groups import panels
from solver.study.plan import plan

CM = 0.01
SHOWN = [(SCORES[group].title, column) for group, column, *_ in panels() if group in SCORES]  # the scores' columns


@pytest.fixture(scope="module")
def session(tmp_path_factory, run_session) -> dict:
    work = tmp_path_factory.mktemp("study_ui")
    family = [sys.executable, "-m", "solver", "family", "--sex", "both", "--points", "0", "-o", str(work / "family")]
    subprocess.run(family, cwd=ROOT, check=True, capture_output=True, timeout=120)
    return run_session(work, "study_session.py")


def _journal(study_file: str) -> list[dict]:
    path = Path(study_file).parent / "out" / "runs.jsonl"
    return [json.loads(line) for line in path.read_text(encoding="utf-8").splitlines() if line.strip()]


def test_the_study_runs_in_the_background_with_progress(session: dict) -> None:
    start, tiny = session["start"], session["tiny"]
    assert start["result"] == ["FINISHED"] and start["armed"]  # the timer was registered
    assert tiny["state"] == "done" and (tiny["done"], tiny["total"]) == (4, 4)
    # the operator and each look at the journal returned while the study was still running: nothing waits on it
    assert any(line.startswith("Running: ") and "runs/s" in line for line in tiny["lines"])
    assert not any("Running" in t for t in session["idle_panel"])
    assert any(t.startswith("Running: 0 of 4 runs") for t in session["running_panel"])
    assert session["status"].startswith("Done: 4 of 4 runs")
    python_path = session["python_path"]
    assert python_path[0].endswith("manikin") and any(".local" in p and "site-packages" in p for p in python_path)


def test_the_table_holds_each_run_with_its_member_values_and_scores(session: dict) -> None:
    rows = session["rows"]
    family = read_family(Path(session["work"]) / "family")
    names = sorted(f"family/{m.name}" for m in family.members)  # the study takes the folder's files in name order
    assert [r["name"] for r in rows] == [n for n in names for _ in range(2)]
    assert [r["role"] for r in rows] == ["mean"] * 4
    assert [r["parameters"] for r in rows] == ["offset_z=0", "offset_z=0.1"] * 2
    journal = {r["run_id"]: r for r in _journal(session["study_file"])}
    for row in rows:
        truth = journal[row["run_id"]]
        assert row["converged"] == truth["converged"]
        cells = row["scores"].split("\t")
        assert cells == [score_cell(truth[column]) for _, column in SHOWN] and cells[0] == str(truth["rula_peak"])
        assert row["l4_l5"] == f"{truth['l4_l5_peak_N']:.0f}"
        assert row["shortfall"] == f"{truth['shortfall_m'] * 1e3:.0f}"
    assert len(session["drawn_rows"]) == 4 and all(len(cells) == 5 + len(SHOWN) for cells in session["drawn_rows"])
    assert session["drawn_rows"][0][:3] == ["female_mean", "mean", "offset_z=0"]
    assert "Manikin" in session["done_panel"] and "Manikin" not in session["idle_panel"]  # the table's header
    titles = [title for title, _ in SHOWN]
    assert session["score_titles"].split("\t") == titles and titles[:2] == ["RULA", "REBA"]
    start = session["done_panel"].index("Manikin")
    header = ["Manikin", "Role", "Values", *titles, "L4/L5 N", "Short mm"]
    assert session["done_panel"][start : start + len(header)] == header


def test_loading_a_row_poses_its_manikin_where_the_study_s_stands(session: dict) -> None:
    assert session["load"] == ["FINISHED"]
    loaded, rows = session["loaded"], session["rows"]
    assert loaded["name"] == "male_mean" and Path(loaded["file"]).name == "male_mean.toml"
    np.testing.assert_allclose(loaded["matrix"], session["arm"], atol=1e-6)
    scenario = load_scenario_of(session, rows[-1]["run_id"])
    result = list(solve_motion(scenario))[-1][1]
    arm = np.array(session["arm"])
    model = scenario.model
    hand = model.forward(result.x[: model.n]).tcp_frame(model.tcp("hand_r"))[1]
    solved = arm[:3, :3] @ hand + arm[:3, 3]
    assert np.linalg.norm(np.array(loaded["hand"])[:3, 3] - solved) < CM
    if result.converged:  # the hand on the target raised by the row's 10 cm
        goal = np.array(session["target"])[:3, 3] + [0.0, 0.0, 0.1]
        assert np.linalg.norm(solved - goal) < CM
    assert loaded["result"]["converged"] == rows[-1]["converged"] == bool(result.converged)
    assert session["load_again"] == ["FINISHED"]  # the same body again: the same armature, no new one
    assert session["manikins_after_load_again"].count("male_mean") == 1


def load_scenario_of(session: dict, run_id: str):
    path = Path(session["work"]) / "row.toml"
    path.write_text(row_scenario(session["study_file"], run_id), encoding="utf-8")
    return load_scenario(path)


@pytest.mark.parametrize(
    "case, words",
    [
        ("no_index", ["family.toml", "not found"]),
        ("broken_index", ["family.toml"]),
        ("no_folder", ["Family folder"]),
        ("bad_values", ["Values", "0.1, high"]),
        ("no_such_target", ["hand_l", "offset_z"]),
        ("no_targets", ["female_5", "nothing to solve"]),
    ],
)
def test_bad_input_is_one_line(session: dict, case: str, words: list[str]) -> None:
    message = session["errors"][case]
    assert message and "\n" not in message.strip() and "Traceback" not in message, message
    assert all(w in message for w in words), message
    assert session["job_after_errors"] == "done"  # nothing else was started


def test_a_study_that_fails_in_its_subprocess_says_why_in_one_line(session: dict) -> None:
    failed = session["failed_job"]
    assert failed["state"] == "failed" and failed["line"].startswith("Study failed: ")
    assert "study.toml" in failed["line"] and "\n" not in failed["line"] and "Traceback" not in failed["line"]


def test_a_cancelled_study_keeps_its_rows_and_goes_on_from_them(session: dict) -> None:
    big, cancelled = session["big"], session["cancelled"]
    assert session["big_start"]["result"] == ["FINISHED"] and big["total"] == 18 * 3
    assert session["cancel"] == ["FINISHED"] and any(t.startswith("Running: ") for t in session["cancel_panel"])
    assert cancelled["state"] == "cancelled" and 1 <= cancelled["done"] < cancelled["total"]
    assert session["cancelled_status"].startswith("Cancelled: ") and session["cancelled_rows"] == cancelled["done"]
    runs = {r.run_id for r in plan(load_study(session["big_study_file"]))}
    kept = session["again_kept"]
    assert kept == cancelled["done"]  # the second start found every kept row ...
    again = session["again_cancelled"]
    assert again["state"] == "cancelled" and kept < again["done"] < again["total"]
    ids = [r["run_id"] for r in _journal(session["big_study_file"])]
    assert set(ids) <= runs and len(ids) == len(set(ids)) == again["done"]  # ... and ran none of them again


def test_disabling_the_add_on_stops_a_running_study(session: dict) -> None:
    assert session["disabled"] == dict(state="cancelled", timer=False, settings=False)


def test_no_traceback(session: dict) -> None:
    assert "Traceback" not in session["log"]
