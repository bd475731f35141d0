"""Reach envelopes in Blender (tests/blender/envelope_session.py in a subprocess, the built zip installed): an
envelope GLB imported onto a turned manikin away from the origin stands where the manikin's frame puts it (origin at
the shoulder, parented), importing it again replaces its objects, an OBJ with no manikin active lands in the world,
another body's envelope is imported with a warning, broken and missing files are one-line errors, and the import
loads neither scipy nor matplotlib beyond what a manikin in the scene loaded."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from solver.envelope import read_envelope

F32 = 2e-5  # m: Blender keeps vertices and matrices in single precision


@pytest.fixture(scope="module")
def session(tmp_path_factory, run_session) -> dict:
    return run_session(tmp_path_factory.mktemp("envelope"), "envelope_session.py")


def _expected(session: dict, name: str) -> tuple:
    """The envelope file's meshes (read here, by the solver) and its shoulder."""
    got = read_envelope(Path(session["work"]) / name)
    return {m.name: m for m in got.meshes}, got.shoulder


def test_the_envelope_is_parented_to_the_manikin_at_its_shoulder(session: dict) -> None:
    assert session["import"] == ["FINISHED"]
    meshes, shoulder = _expected(session, "env.glb")
    matrix = np.array(session["matrix"])
    onto = session["onto"]
    assert sorted(onto) == ["env.balanced", "env.kinematic"]
    for name, ob in onto.items():
        which = name.removeprefix("env.")
        assert ob["parent"] == "male_50"
        assert ob["display"] == ("SOLID" if which == "balanced" else "WIRE")
        world = meshes[which].vertices @ matrix[:3, :3].T + matrix[:3, 3]  # the manikin's frame, turned and moved
        np.testing.assert_allclose(ob["vertices"], world, atol=F32)
        np.testing.assert_allclose(ob["origin"], matrix[:3, :3] @ shoulder + matrix[:3, 3], atol=F32)
        assert ob["faces"] == meshes[which].faces.tolist()


def test_importing_again_replaces_its_objects(session: dict) -> None:
    assert session["again"] == ["FINISHED"]
    assert session["after_again"] == ["env.balanced", "env.kinematic"]


def test_without_a_manikin_the_obj_lands_in_the_world(session: dict) -> None:
    assert session["world_import"] == ["FINISHED"]
    meshes, shoulder = _expected(session, "env.obj")
    assert sorted(session["world"]) == ["env.balanced", "env.kinematic"]
    for name, ob in session["world"].items():
        which = name.removeprefix("env.")
        assert ob["parent"] is None
        np.testing.assert_allclose(ob["vertices"], meshes[which].vertices, atol=F32)
        np.testing.assert_allclose(ob["origin"], shoulder, atol=F32)


def test_another_body_s_envelope_is_imported_with_a_warning(session: dict) -> None:
    assert session["other"] == ["FINISHED"]
    assert "the envelope is female_5's, placed on male_50 (male_50)" in session["log"]


def test_failures_are_one_line_reports_and_nothing_heavy_is_loaded(session: dict) -> None:
    bad, missing = session["bad"].strip(), session["missing"].strip()
    assert "bad.glb: not a readable envelope file" in bad and "\n" not in bad
    assert "nowhere.glb: cannot read" in missing and "\n" not in missing
    assert "Traceback" not in session["log"]
    assert session["heavy_loaded"] == []
