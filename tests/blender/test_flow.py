"""The rest of the user flow (tests/blender/flow_session.py in a subprocess, the built zip installed): enable time,
every preset, reset, the overlay's shaders in this Blender, and bad states reported instead of raised."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest
from environments import ROOT, selected

from solver.presets import list_presets


@pytest.fixture(scope="module")
def session(tmp_path_factory, run_session) -> dict:
    return run_session(tmp_path_factory.mktemp("flow"), "flow_session.py")


def registry_modules() -> set[str]:
    """The solver's modules that importing the obstacle kinds' and standard comfort terms' registries loads (here,
    apart from Blender): collision shapes and comfort terms, NumPy only."""
    code = (
        "import json, sys, solver.collision.kinds, solver.comfort.standard\n"
        "print(json.dumps([m for m in sys.modules if m.startswith(('solver', 'scipy', 'matplotlib'))]))"
    )
    done = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    return set(json.loads(done.stdout))


def test_enabling_loads_nothing_heavy(session: dict) -> None:
    """Enabled afresh, the add-on imports neither the solver's solve nor scipy or matplotlib: only its light modules
    and the two registries its settings are made from (the shape menu, the comfort weights; about 40 ms more)."""
    assert session["enabled"] and session["heavy_on_enable"] == []
    light = {"solver", "solver.errors", "solver.lazy", "solver.options", "solver.presets"}
    registries = registry_modules()
    assert {"solver.collision.kinds", "solver.comfort.standard"} <= registries
    assert not any(m.startswith(("scipy", "matplotlib", "solver.iteration", "solver.problem")) for m in registries)
    assert set(session["loaded_on_enable"]) <= light | registries


def test_every_preset_adds_a_manikin_that_solves(session: dict) -> None:
    assert sorted(session["presets"]) == list_presets()
    for name, preset in session["presets"].items():
        assert preset["done"] == ["FINISHED"] and preset["solve"] == ["FINISHED"], name
        assert preset["bones"] > 5 and preset["tcps"] >= 2 and preset["bodies"] == 1, name
        expected = ["floor"] if name == "snake" else ["foot_l", "foot_r"]
        assert preset["supports"] == expected, name


def test_reset_stands_the_manikin_up_again(session: dict) -> None:
    assert session["solve"] == ["FINISHED"] and session["converged"]
    assert session["reset"] == ["FINISHED"] and session["reset_channels"] < 1e-6 and session["reset_result_gone"]


def test_a_target_out_of_reach_ends_short_with_the_feet_held(session: dict) -> None:
    """The sidebar's result names the short target and its shortfall; a "Must hold" target is reported not held."""
    far = session["far"]
    assert session["far_solve"] == ["FINISHED"] and not far["converged"]
    assert far["unmet"] == ["hand_r"] and far["broken"] == [] and " mm" in far["shortfall"]["hand_r"]
    assert "hand_r" in session["far_must_hold"]


def test_a_mesh_marked_as_an_obstacle_keeps_the_hand_out(session: dict) -> None:
    marked, unmarked, collected = (session[k] for k in ("obstacle_marked", "obstacle_unmarked", "obstacle_collection"))
    assert marked["done"] == ["FINISHED"] and not marked["converged"]
    assert marked["unmet"] == ["hand_r"] and marked["broken"] == []
    assert unmarked["converged"]
    assert collected["unmet"] == ["hand_r"] and collected["broken"] == []


def test_overlay_uses_shaders_this_blender_has(session: dict) -> None:
    overlay = session["overlay"]
    assert overlay["asked"] == ["POLYLINE_UNIFORM_COLOR"] and overlay["known"]["POLYLINE_UNIFORM_COLOR"], overlay
    if selected() == "4.2":  # the check can fail: 4.2 lacks the point shader the overlay used to ask for
        assert not overlay["known"]["POINT_UNIFORM_COLOR"]
    assert len(overlay["drawn"]) >= 3 and all(n % 2 == 0 for n in overlay["drawn"])  # line pairs


def test_a_renamed_bone_is_reported(session: dict) -> None:
    for key in ("renamed_solve", "renamed_reset", "renamed_bake"):
        assert "bone 'upper_arm_r' is missing (renamed or deleted?)" in session[key], key


def test_deleted_empties_and_bad_selections_are_reported(session: dict) -> None:
    assert session["deleted_target_solve"] == ["FINISHED"]
    assert session["deleted_tcp_load"] == "FINISHED" and session["deleted_tcp_solve"] == "FINISHED"
    nothing = session["nothing_selected"]
    assert not nothing["solve"] and not nothing["bake"] and "Select a manikin" in nothing["error"]
    assert "must stay upright and unscaled" in session["scaled"]
    assert "Traceback" not in session["log"]
