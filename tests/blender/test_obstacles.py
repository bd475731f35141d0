"""Obstacles in Blender (tests/blender/obstacle_session.py in a subprocess, the built zip installed): shapes read
from objects, the overlay's distances and capsules, scenario export with mesh files beside it, import onto a turned
manikin and export again giving the same obstacles, a cylinder marked in the sidebar and one imported (kept clear of
by the solve, checked by the independent collision_check), and failures reported in one line."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from collision_check import axis_distance

from solver import load_scenario
from solver.collision import Box, Capsule, HalfSpace, Mesh, Sphere
from solver.collision.kinds import Cylinder

F32 = 1e-5  # m: Blender keeps matrices and vertices in single precision


@pytest.fixture(scope="module")
def session(tmp_path_factory, run_session) -> dict:
    return run_session(tmp_path_factory.mktemp("obstacles"), "obstacle_session.py")


def test_objects_are_read_as_their_shapes_in_the_armatures_space(session: dict) -> None:
    read = session["read"]
    kinds = {"shelf.top": "Mesh", "table": "Box", "ball": "Sphere", "rail": "Capsule", "wall": "HalfSpace",
             "drum": "Cylinder"}  # fmt: skip
    assert read["kinds"] == kinds
    np.testing.assert_allclose(read["ball"]["center"], read["ball_local"], atol=F32)
    assert read["ball"]["radius"] == pytest.approx(0.1, abs=F32)
    # Blender's cylinder (radius 0.3 m, depth 0.9 m along its local z), as the cylinder of its bounds
    drum, matrix = read["drum"], np.array(read["drum_matrix"])
    np.testing.assert_allclose(np.subtract(drum["b"], drum["a"]), 0.9 * matrix[:3, 2], atol=F32)
    np.testing.assert_allclose(np.add(drum["a"], drum["b"]) / 2.0, matrix[:3, 3], atol=F32)
    assert drum["radius"] == pytest.approx(0.3, abs=F32)


def test_a_scene_read_again_shares_the_obstacle_rows_until_an_obstacle_moves(session: dict) -> None:
    reuse = session["reuse"]
    assert reuse["shared"] and reuse["fresh"]
    assert reuse["ball_moved"] == pytest.approx(0.05, abs=F32)


def test_overlay_draws_each_close_pair_and_its_distance(session: dict) -> None:
    result, geometry = session["result"], session["geometry"]
    assert session["solve"] == ["FINISHED"] and result["unmet"] == ["hand_r"]
    closest = result["closest"]
    assert any(pair["other"] == "shelf.top" for pair in closest)
    assert all(pair["distance"] - pair["clearance"] < 0.05 for pair in closest)
    below = [pair for pair in closest if pair["below"]]
    assert all(pair["distance"] < pair["clearance"] - 1e-3 for pair in below)
    # two body parts resting at their allowed distance are in the result, not drawn (only when below it)
    assert any(pair["body"] and not pair["below"] for pair in closest)
    assert all(pair["body"] == (pair["other"] not in ("floor", "shelf.top", "table")) for pair in closest)
    drawn_pairs = [pair for pair in closest if pair["below"] or not pair["body"]]
    near = [pair for pair in drawn_pairs if not pair["below"]]
    assert len(geometry["near"]) == 2 * len(near) and len(geometry["below"]) == 2 * len(below)
    matrix = np.array(session["matrix"])
    lines = np.array(geometry["near"] + geometry["below"])[:, :3]
    ends = [p for pair in near for p in (pair["point"], pair["other_point"])]
    ends += [p for pair in below for p in (pair["point"], pair["other_point"])]
    world = np.array(ends) @ matrix[:3, :3].T + matrix[:3, 3]  # the result is in the armature's space
    np.testing.assert_allclose(lines, world, atol=F32)
    labels = session["labels"]
    assert [text for _, text, _ in labels] == [f"{round(1e3 * pair['distance']):d} mm" for pair in drawn_pairs]
    for (point, _, color), pair in zip(labels, drawn_pairs, strict=True):
        middle = matrix[:3, :3] @ (0.5 * (np.array(pair["point"]) + pair["other_point"])) + matrix[:3, 3]
        np.testing.assert_allclose(point, middle, atol=F32)
        assert (color[0] == 1.0 and color[1] < 0.5) == pair["below"]  # red below the clearance
    drawn = [entry[1] for entry in session["drawn_labels"] if entry[0] == "text"]
    assert drawn == [text for _, text, _ in labels]
    assert session["handlers"] == "added" and session["handlers_removed"] == "removed"


def test_capsules_are_drawn_with_their_toggle(session: dict) -> None:
    overlay_keys = ["com", "polygon", "contact", "load", "near", "below"]
    assert session["shown"] == [overlay_keys, [*overlay_keys, "capsules"], ["capsules"]]
    wires = np.array(session["geometry"]["capsules"])
    capsules = session["result"]["capsules"]
    assert len(capsules) > 10 and len(wires) % (2 * len(capsules)) == 0
    matrix = np.array(session["matrix"])
    for chunk, capsule in zip(np.split(wires, len(capsules)), capsules, strict=True):
        a, b = (matrix[:3, :3] @ capsule[key] + matrix[:3, 3] for key in ("start", "end"))
        t = np.clip((chunk - a) @ (b - a) / max((b - a) @ (b - a), 1e-12), 0.0, 1.0)
        off_axis = np.linalg.norm(chunk - (a + t[:, None] * (b - a)), axis=1)
        np.testing.assert_allclose(off_axis, capsule["radius"], atol=F32)  # every wire point on the capsule


def _by_name(path: Path) -> dict:
    return {ob.name: ob for ob in load_scenario(path).problem.obstacles}


def _same(a, b) -> None:
    assert (type(a), a.name) == (type(b), b.name) and a.clearance == pytest.approx(b.clearance, abs=1e-7)
    fields = dict(Box=("center", "size", "rotation"), Sphere=("center", "radius"), Capsule=("a", "b", "radius"),
                  HalfSpace=("point", "normal"), Mesh=("vertices", "faces"),
                  Cylinder=("a", "b", "radius"))[type(a).__name__]  # fmt: skip
    for field in fields:
        np.testing.assert_allclose(getattr(a, field), getattr(b, field), atol=F32, err_msg=f"{a.name}.{field}")


def test_export_writes_meshes_beside_and_shapes_inside(session: dict) -> None:
    work = Path(session["work"])
    assert session["export"] == ["FINISHED"]
    assert session["files"] == ["exported.toml", "exported_shelf_top.obj"]
    text = (work / "exported.toml").read_text(encoding="utf-8")
    assert 'file = "exported_shelf_top.obj"' in text and "vertices" not in text
    shapes = _by_name(work / "exported.toml")
    assert isinstance(shapes["shelf.top"], Mesh) and len(shapes["shelf.top"].faces) == 12
    table, ball, rail, wall, drum = (shapes[name] for name in ("table", "ball", "rail", "wall", "drum"))
    assert isinstance(table, Box) and isinstance(ball, Sphere) and isinstance(rail, Capsule)
    assert isinstance(wall, HalfSpace) and isinstance(drum, Cylinder) and drum.clearance == 0.03
    assert 'kind = "cylinder"' in text and drum.radius == pytest.approx(0.3, abs=F32)
    np.testing.assert_allclose(table.size, [0.8, 0.4, 0.8], atol=F32)
    assert rail.radius == pytest.approx(0.02, abs=F32)
    assert np.linalg.norm(rail.b - rail.a) == pytest.approx(0.5 - 2 * 0.02, abs=F32)
    assert table.clearance == 0.02 and "clearance = 0.02\n" in text  # as typed, not its single-precision value


def test_import_recreates_the_obstacles_and_export_gives_them_again(session: dict) -> None:
    work = Path(session["work"])
    assert session["import"] == ["FINISHED"] and session["import_onto"] and session["export_again"] == ["FINISHED"]
    first, again = _by_name(work / "exported.toml"), _by_name(work / "again.toml")
    assert sorted(first) == sorted(again) == ["ball", "drum", "rail", "shelf.top", "table", "wall"]
    for name in first:
        _same(first[name], again[name])
    imported = session["imported"]
    shapes = {name: item["shape"] for name, item in imported.items()}
    assert shapes == {"shelf.top": "MESH", "table": "BOX", "ball": "SPHERE", "rail": "CAPSULE", "wall": "PLANE",
                      "drum": "CYLINDER"}  # fmt: skip
    assert all(item["enabled"] for item in imported.values())
    box = np.array(imported["table"]["local"])  # placed in the armature's space: its matrix there is the box's
    np.testing.assert_allclose(box[:3, :3], first["table"].rotation, atol=F32)
    np.testing.assert_allclose(box[:3, 3], first["table"].center, atol=F32)
    np.testing.assert_allclose(np.array(imported["wall"]["local"])[:3, 2], first["wall"].normal, atol=F32)


def test_importing_again_replaces_its_own_objects_only(session: dict) -> None:
    assert session["import_twice"] == ["FINISHED"]
    assert session["after_twice"] == ["ball", "drum", "rail", "shelf.top", "table", "wall", "wall.001"]
    assert "obstacle 'wall': another object has that name; imported as 'wall.001'" in session["log"]


def test_failures_are_one_line_reports(session: dict) -> None:
    missing = session["missing_mesh"].strip()
    assert "nowhere.obj: cannot read the mesh file" in missing and "\n" not in missing
    flat = session["flat"].strip()
    assert "obstacle 'flat': every triangle has zero area" in flat and "\n" not in flat
    unwritable = session["unwritable"].strip()
    assert "blocked" in unwritable and "cannot write" in unwritable and "\n" not in unwritable
    assert "Traceback" not in session["log"]


def test_the_sidebar_shows_the_obstacle_and_capsule_settings(session: dict) -> None:
    """The panels drew against a recording layout that fails on unknown properties and icons (shape, Capsules)."""
    assert (
        '(or put it in a collection named "Obstacles")' in session["panel"] and "male_50 (male_50)" in session["panel"]
    )


def _draws(batches: list) -> list[list]:
    """The recorded batches split at each draw call: [[(colour, count), ...], ...]."""
    out: list[list] = []
    for color, count in batches:
        if color == "draw":
            out.append([])
        else:
            out[-1].append((tuple(color), count))
    return out


def test_the_draw_callback_draws_what_the_toggles_show(session: dict) -> None:
    overlay_only, with_capsules, nothing = _draws(session["batches"])
    geometry = session["geometry"]
    near = (0.95, 0.95, 0.95, 1.0)
    capsule = (0.3, 0.85, 1.0, 0.7)
    assert (near, len(geometry["near"])) in overlay_only and all(color != capsule for color, _ in overlay_only)
    assert with_capsules == [*overlay_only, (capsule, len(geometry["capsules"]))]
    assert nothing == []


def test_a_scenarios_cylinder_is_imported_as_a_cylinder_and_kept_clear_of(session: dict) -> None:
    """The post is a cylinder obstacle again when read from the scene; a hand target in it ends short, and no capsule
    of the body is inside the post's 2 cm clearance by more than the solver's 1 mm (measured by collision_check)."""
    assert session["import_post"] == ["FINISHED"] and "no cylinder shape" not in session["log"]
    post = session["post"]
    assert (post["shape"], post["read"], post["clearance"]) == ("CYLINDER", "Cylinder", pytest.approx(0.02))
    np.testing.assert_allclose([post["a"], post["b"]], [[-0.2, -0.45, 0.0], [-0.2, -0.45, 1.4]], atol=F32)
    assert post["radius"] == pytest.approx(0.05, abs=F32)
    result = session["post_result"]
    assert session["post_solve"] == ["FINISHED"] and result["unmet"] == ["hand_r"] and not result["broken"]
    capsules = result["capsules"]
    p0, p1 = (np.array([c[key] for c in capsules]) for key in ("start", "end"))
    table = dict(kind="cylinder", a=post["a"], b=post["b"], radius=post["radius"])
    gaps = axis_distance(table, p0, p1) - np.array([c["radius"] for c in capsules])
    assert gaps.min() > 0.02 - 1e-3 and gaps.min() < 0.02 + 0.01  # at the clearance: the hand reaches for the axis
    near = [pair for pair in result["closest"] if pair["other"] == "post"]
    assert near and all(pair["distance"] > 0.02 - 1e-3 for pair in near)
