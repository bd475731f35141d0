"""What a bake saves gives what it stands for (tests/blender/bake_shortcuts_session.py in a subprocess): the carried
box keyed from the TCP positions kept from each frame's solve has the keys that a forward kinematics per frame
gives; a new F-curve keyed without reading back Blender's defaults has every attribute the full path writes; the
human's mesh filled from arrays is the mesh ``from_pydata`` makes."""

from __future__ import annotations

import pytest


@pytest.fixture(scope="module")
def session(tmp_path_factory, run_session) -> dict:
    return run_session(tmp_path_factory.mktemp("bake_shortcuts"), "bake_shortcuts_session.py")


def test_box_keys_from_the_solves_are_those_from_the_joint_values(session: dict) -> None:
    assert session["tcps"] and session["kept"]
    assert {path for path in session["kept"]} >= {f"location[{k}]" for k in range(3)}
    assert session["kept"] == session["recomputed"]  # the same numbers, bit for bit
    assert session["shifted"] != session["recomputed"]  # other positions would show


def test_a_new_curve_keyed_as_the_full_path_keys_it(session: dict) -> None:
    fresh, rewritten = session["fresh_curve"], session["rewritten_curve"]
    assert fresh == rewritten
    assert len(fresh["co"]) // 2 == 6  # 7 keys, the inner key of the run of three equal values left out


def test_the_human_mesh_from_arrays_is_that_of_from_pydata(session: dict) -> None:
    assert session["mesh_arrays"] == session["mesh_lists"]
    assert len(session["mesh_arrays"]["vertices.co"]) > 30000 and session["mesh_valid"]
