"""The add-on follows the solver's registries (tests/blender/registries_session.py in a subprocess, the built zip
installed): an obstacle kind and a standard comfort term made up in the session and registered in the installed
solver are, once the add-on is enabled again, in the shape menu and the solver settings, read from the scene, solved
with, exported and imported, without a line of the Blender layer changed; before that, and after they are gone,
the user meets one line, not a traceback. The bpy-free half:
tests/blender_manikin/test_settings_follow_registries.py."""

from __future__ import annotations

from pathlib import Path

import pytest

from solver.collision import KINDS, Mesh
from solver.comfort.standard import STANDARD_TERMS

PEBBLE = ["PEBBLE_TEST", "Pebble Test", "A made-up ball (test)"]
IDLE = ["comfort_idle_test", "Idle Test", 0.25, "Weight: nothing at all (test)"]


@pytest.fixture(scope="module")
def session(tmp_path_factory, run_session) -> dict:
    return run_session(tmp_path_factory.mktemp("registries"), "registries_session.py")


def test_the_installed_menus_are_the_registries(session: dict) -> None:
    """Every registered kind, the mesh first (as saved files number them), and a weight per registered term."""
    before = session["before"]
    kinds = [Mesh.kind, *(k for k in KINDS if k != Mesh.kind)]
    assert [[i, title] for i, title, _ in before["shapes"]] == [[k.upper(), k.title()] for k in kinds]
    assert [d for _, _, d in before["shapes"]] == [KINDS[k].description for k in kinds]
    assert [i for i, _, _ in before["shapes"]][:5] == ["MESH", "BOX", "SPHERE", "CAPSULE", "PLANE"]
    weights = {name: (title, default) for name, title, default, _ in before["weights"]}
    registered = [f"comfort_{name}" for name in STANDARD_TERMS]
    assert list(weights) == registered == ["comfort_range", "comfort_load", "comfort_contact", "comfort_trunk",
                                                "comfort_gaze"]
    for name, term in STANDARD_TERMS.items():
        assert weights[f"comfort_{name}"] == (name.title(), pytest.approx(term.weight))


def test_a_kind_registered_after_the_add_on_is_refused_in_one_line(session: dict) -> None:
    assert session["early_weights"]["idle_test"] == 0.25  # the new term at its default: no setting yet
    line = session["too_early"].strip()
    assert "obstacle 'stone': the pebble_test kind was registered after Manikin was enabled" in line
    assert "\n" not in line
    assert session["unchanged"] and "Traceback" not in session["log"]


def test_enabled_again_the_add_on_offers_the_new_kind_and_weight(session: dict) -> None:
    before, after = session["before"], session["after"]
    assert after["shapes"] == [*before["shapes"], PEBBLE]  # the others keep their place (saved files hold it)
    assert after["weights"][:-1] == before["weights"] and after["weights"][-1] == IDLE
    assert session["panel"] == ["comfort_range", "comfort_load", "comfort_contact", "comfort_trunk",
                                "comfort_gaze", "comfort_idle_test"]


def test_the_new_kind_and_weight_reach_the_problem_the_solve_and_the_files(session: dict) -> None:
    read = session["read"]
    assert read["kinds"] == {"pebble": "Pebble"}
    assert read["weights"] == dict(range=1.0, load=1.0, contact=0.01, trunk=5.0, gaze=0.0, idle_test=2.0)  # as typed
    assert session["solve"] == ["FINISHED"] and session["comfort_parts"]["idle_test"] == 0.0
    assert session["export"] == ["FINISHED"]
    text = (Path(session["work"]) / "registered.toml").read_text(encoding="utf-8")
    assert "\ncontact = 0.01\ntrunk = 5.0\ngaze = 0.0\nidle_test = 2.0\n" in text and 'kind = "pebble_test"' in text
    assert session["import"] == ["FINISHED"] and session["imported"] == dict(shape="PEBBLE_TEST", weight=2.0)


def test_gone_again_the_menus_are_as_installed_and_a_stale_shape_is_one_line(session: dict) -> None:
    assert session["restored"] == session["before"]
    assert session["restored_weights"] == dict(range=1.0, load=1.0, contact=0.01, trunk=5.0, gaze=0.0)
    assert session["stale_shape"] == ""  # saved as the 7th item, which the menu no longer has
    line = session["stale_solve"].strip()
    assert "obstacle 'pebble': its shape is no registered obstacle kind" in line and "\n" not in line
