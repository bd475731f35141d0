"""A reach envelope computed from the sidebar (tests/blender/envelope_compute_session.py in a subprocess, the built
zip installed): Compute Envelope runs ``python -m solver envelope`` in the background with the panel's options
(nothing in Blender waits on it, its progress shows), imports the result onto the manikin as Import Reach Envelope
does, finds it again for the same settings, and a cancelled one imports nothing; Blender itself loads neither scipy
nor matplotlib. And two messages: a study varying a missing target, an OBJ that is not an envelope.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest

from solver.envelope import read_envelope

F32 = 2e-5  # m: Blender keeps vertices and matrices in single precision


@pytest.fixture(scope="module")
def session(tmp_path_factory, run_session) -> dict:
    return run_session(tmp_path_factory.mktemp("envelope_compute"), "envelope_compute_session.py")


def test_the_envelope_is_computed_in_the_background_with_progress(session: dict) -> None:
    start, run = session["start"], session["run"]
    assert start["result"] == ["FINISHED"] and start["armed"]  # the timer was registered
    assert start["execute_s"] < 3.0 and run["slowest_poll_s"] < 1.0  # nothing waits on the subprocess
    assert run["state"] == "done", run["lines"][-1]
    assert any(t.startswith("Computing: 0 of ") for t in session["running_panel"])
    assert any(line.startswith("Computing: ") and " directions, " in line for line in run["lines"])
    assert session["status"].startswith(f"Done: {start['total']} directions in ")
    assert not any(t.startswith("Computing") for t in session["idle_panel"] + session["done_panel"])
    assert session["status"] in session["done_panel"]


def test_it_was_computed_with_the_panel_s_options(session: dict) -> None:
    out = Path(session["run"]["output"])
    rows = list(csv.DictReader((out / "male_50_right.csv").open(encoding="utf-8")))
    assert len(rows) == session["start"]["total"] and 5 <= len(rows) < 12  # the front half of 12 directions
    assert all(float(r["load_kg"]) == 2.0 and r["feet"] == "planted" and r["hand"] == "right" for r in rows)
    assert all(float(r["dy"]) <= 1e-9 for r in rows)  # front: the manikin faces -y
    info = read_envelope(out / "male_50_right.obj").info
    assert info["manikin"] == "male_50" and info["hand"] == "right"


def test_a_manikin_renamed_while_it_runs_still_gets_its_envelope(session: dict) -> None:
    assert session["onto_renamed"] and all(session["onto_renamed"])


def test_the_result_is_imported_onto_the_manikin(session: dict) -> None:
    out = Path(session["run"]["output"])
    objects = session["objects"]
    assert sorted(objects) == ["male_50_right.balanced", "male_50_right.kinematic"]
    meshes = {m.name: m for m in read_envelope(out / "male_50_right.obj").meshes}
    matrix = np.array(session["matrix"])
    for name, ob in objects.items():
        assert ob["parent"] == "male_50" and Path(ob["source"]) == (out / "male_50_right.obj").resolve()
        world = meshes[name.split(".")[1]].vertices @ matrix[:3, :3].T + matrix[:3, 3]
        np.testing.assert_allclose(ob["vertices"], world, atol=F32)
    assert "male_50_right.balanced" in session["status"] and str(out) in session["status"]


def test_the_same_settings_again_import_the_finished_envelope(session: dict) -> None:
    again = session["again"]
    assert again["result"] == ["FINISHED"] and not again["armed"] and again["execute_s"] < 3.0
    assert session["again_status"].startswith("Computed before with these settings; imported male_50_right.")
    assert session["again_objects"] == sorted(session["objects"])  # replaced, not doubled


def test_a_cancelled_envelope_imports_nothing(session: dict) -> None:
    big, cancelled = session["big_start"], session["cancelled"]
    assert big["result"] == ["FINISHED"] and big["total"] == 92
    assert session["cancel"] == ["FINISHED"] and any(t.startswith("Computing: ") for t in session["cancel_panel"])
    assert cancelled["state"] == "cancelled" and cancelled["seconds"] < 10.0
    assert session["cancelled_status"].startswith("Cancelled after ")
    assert session["cancelled_objects"] == sorted(session["objects"])
    assert not any(Path(cancelled["output"]).glob("*.obj"))


def test_blender_itself_loads_no_scipy(session: dict) -> None:
    assert session["heavy_loaded"] == []


def test_disabling_the_add_on_stops_a_running_envelope(session: dict) -> None:
    assert session["disabled"] == dict(state="cancelled", timer=False, settings=False)


def test_a_study_varying_a_missing_target_says_so_before_writing_anything(session: dict) -> None:
    message = session["no_such_target"].strip()
    assert "hand_l" in message and "offset_z" in message and "hand_r" in message, message
    assert "\n" not in message and session["work"] not in message and "study.toml" not in message, message
    assert session["studies_written"] == []


def test_an_obj_manikin_did_not_write_is_not_an_envelope(session: dict) -> None:
    message = session["cube"].strip()
    assert "cube.obj: not a reach envelope written by Manikin" in message and "\n" not in message, message
    assert session["cube_objects"] == []


def test_no_traceback_and_the_session_stays_short(session: dict) -> None:
    assert "Traceback" not in session["log"]
    assert session["session_s"] < 120.0  # about 20 s on an idle 2-core machine: a runaway (a full sphere) fails
