"""Scenario obstacles written to disk (solver/io/scenario/obstacle_files.py, write_scenario): meshes as OBJ files
beside the
TOML, never over another file; parametric shapes stay in the TOML; the capsule meshes Blender recreates."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

from solver import Problem, ProblemSpec, dumps_scenario, load_scenario, scenario_to_dict, write_scenario
from solver.collision import Box, Capsule, HalfSpace, Mesh, Sphere
from solver.collision.generate import axis_frame, box_mesh, capsule_mesh
from solver.errors import ManikinError
from solver.io.scenario.bodies import PRESETS_DIR
from solver.io.scenario.obstacle_files import safe_name
from solver.io.scenario.write import write_scenario_files

BOX_LIFT = PRESETS_DIR / "scenarios" / "box_lift.toml"


def _data(*obstacles) -> dict:
    box = load_scenario(BOX_LIFT).problem
    problem = Problem(box.model, ProblemSpec(box.all_targets, box.loops, box.load_specs, obstacles=list(obstacles)))
    return scenario_to_dict(problem, {"preset": "male_50"})


def _shelf(name: str = "shelf", center=(0.0, -0.6, 0.9)) -> Mesh:
    return Mesh(*box_mesh(center, (0.8, 0.3, 0.02), 2), name=name, clearance=0.02)


def _every_kind() -> list:
    turn = axis_frame((0.0, 1.0, 1.0))
    return [
        Box((0.0, -0.55, 0.4), (0.8, 0.4, 0.8), turn, name="table", clearance=0.01),
        Sphere((1.0, 1.0, 1.0), 0.1, name="ball"),
        Capsule((1.0, 0.0, 1.0), (1.0, 1.0, 1.0), 0.02, name="rail"),
        HalfSpace((0.0, 2.0, 0.0), (0.0, -1.0, 0.0), name="wall"),
        _shelf(),
    ]


def test_meshes_go_to_files_beside_the_scenario_and_read_back_the_same(tmp_path: Path) -> None:
    written = write_scenario_files(tmp_path / "lift.toml", _data(*_every_kind()))
    assert written == [tmp_path / "lift_shelf.obj", tmp_path / "lift.toml"]
    text = (tmp_path / "lift.toml").read_text(encoding="utf-8")
    assert 'file = "lift_shelf.obj"' in text and "vertices" not in text and "faces" not in text
    assert 'kind = "box"' in text and 'kind = "plane"' in text  # the parametric shapes stay parametric
    back = load_scenario(tmp_path / "lift.toml").problem.obstacles
    for a, b in zip(_every_kind(), back, strict=True):
        assert (type(a), a.name, a.clearance) == (type(b), b.name, b.clearance)
    np.testing.assert_allclose(back[0].rotation, _every_kind()[0].rotation, atol=1e-12)
    np.testing.assert_allclose(back[4].vertices, _shelf().vertices, atol=1e-9)
    np.testing.assert_array_equal(back[4].faces, _shelf().faces)


def test_another_file_of_that_name_is_kept_and_our_own_is_replaced(tmp_path: Path) -> None:
    theirs = tmp_path / "lift_shelf.obj"
    theirs.write_text("# somebody's shelf\nv 0 0 0\n", encoding="utf-8")
    write_scenario(tmp_path / "lift.toml", _data(_shelf()))
    assert theirs.read_text(encoding="utf-8") == "# somebody's shelf\nv 0 0 0\n"
    assert 'file = "lift_shelf-2.obj"' in (tmp_path / "lift.toml").read_text(encoding="utf-8")
    write_scenario(tmp_path / "lift.toml", _data(_shelf(center=(0.0, -0.6, 1.2))))  # moved, written again
    assert sorted(p.name for p in tmp_path.iterdir()) == ["lift.toml", "lift_shelf-2.obj", "lift_shelf.obj"]
    assert load_scenario(tmp_path / "lift.toml").problem.obstacles[0].vertices[:, 2].max() == pytest.approx(1.21)
    write_scenario(tmp_path / "other.toml", _data(_shelf()))  # another scenario does not take lift's files
    assert 'file = "other_shelf.obj"' in (tmp_path / "other.toml").read_text(encoding="utf-8")


def test_names_are_made_safe_and_kept_apart(tmp_path: Path) -> None:
    assert safe_name("Cube.001/ä") == "Cube_001" and safe_name("../..") == "mesh" and safe_name("a-b_c") == "a-b_c"
    written = write_scenario_files(tmp_path / "s.toml", _data(_shelf("a b"), _shelf("a_b"), _shelf("../x")))
    assert [p.name for p in written] == ["s_a_b.obj", "s_a_b-2.obj", "s_x.obj", "s.toml"]
    names = [ob.name for ob in load_scenario(tmp_path / "s.toml").problem.obstacles]
    assert names == ["a b", "a_b", "../x"]


def test_text_and_standard_output_keep_meshes_inline(tmp_path: Path, capsys) -> None:
    data = _data(_shelf())
    assert "vertices = [[" in dumps_scenario(data)
    write_scenario("-", data)
    assert "vertices = [[" in capsys.readouterr().out
    write_scenario(tmp_path / "inline.toml", data, inline=True)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["inline.toml"]
    assert load_scenario(tmp_path / "inline.toml").problem.obstacles[0].faces.shape == (48, 3)


def test_a_failed_write_is_one_line_and_leaves_no_file(tmp_path: Path) -> None:
    (tmp_path / "lift.toml").mkdir()  # the TOML cannot be written: neither are the meshes
    with pytest.raises(ManikinError) as info:
        write_scenario(tmp_path / "lift.toml", _data(_shelf()))
    assert "lift.toml" in str(info.value) and "\n" not in str(info.value)
    assert sorted(os.listdir(tmp_path)) == ["lift.toml"]
    blocked = tmp_path / "blocked"
    blocked.write_text("", encoding="utf-8")  # a file where the folder should be
    with pytest.raises(ManikinError) as info:
        write_scenario(blocked / "lift.toml", _data(_shelf()))
    assert "blocked" in str(info.value) and "\n" not in str(info.value)


@pytest.mark.parametrize("ends", [((0, 0, 0), (0, 0, 0)), ((0.1, 0.2, 0.3), (0.4, -0.1, 0.9))])
def test_capsule_mesh_is_closed_outward_and_fits_its_box(ends) -> None:
    a, b = (np.array(e, dtype=float) for e in ends)
    mesh = Mesh(*capsule_mesh(a, b, 0.1, 32, 8))
    length = float(np.linalg.norm(b - a))
    assert mesh.is_closed()
    exact = 4.0 / 3.0 * np.pi * 0.1**3 + np.pi * 0.1**2 * length
    assert 0.97 * exact < mesh.signed_volume() < exact  # inscribed: a little smaller, and positive (outward)
    local = (mesh.vertices - 0.5 * (a + b)) @ axis_frame(b - a)
    np.testing.assert_allclose(local.max(axis=0), [0.1, 0.1, 0.5 * length + 0.1], atol=1e-12)
    np.testing.assert_allclose(local.min(axis=0), [-0.1, -0.1, -0.5 * length - 0.1], atol=1e-12)


def test_axis_frame_is_a_rotation_onto_the_direction() -> None:
    for d in ((0, 0, 1), (0, 1, 0), (1, 2, -3), (0, 0, -1)):
        r = axis_frame(d)
        np.testing.assert_allclose(r.T @ r, np.eye(3), atol=1e-12)
        assert np.linalg.det(r) == pytest.approx(1.0)
        np.testing.assert_allclose(r[:, 2], np.array(d) / np.linalg.norm(d), atol=1e-12)
    np.testing.assert_array_equal(axis_frame((0, 0, 0)), np.eye(3))
