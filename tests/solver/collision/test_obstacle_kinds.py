"""The obstacle kinds' registry (solver/collision/kinds): every registered kind reads and writes its scenario table,
is shown as an object that reads back as it, answers distance queries by the common conventions, and is kept clear of
by the solver's rows; and the registry refuses a second kind of one name."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from solver.collision import KINDS, Box, Capsule, HalfSpace, Mesh, Obstacle, Sphere
from solver.collision.generate import axis_frame, box_mesh
from solver.collision.kinds import Cylinder, kind_of, register
from solver.collision.placed import placed_mesh, shape_from_bounds
from solver.io.scenario.obstacles import kind_keys, obstacle_table, read_obstacles
from solver.io.table_reader import TableReader

EXAMPLES = {
    "box": Box((0.1, -0.5, 0.4), (0.8, 0.4, 0.6), axis_frame((1.0, 2.0, 0.5)), name="table", clearance=0.01),
    "sphere": Sphere((0.3, -0.2, 1.0), 0.1, name="ball"),
    "capsule": Capsule((0.0, -0.4, 1.0), (0.4, -0.3, 0.7), 0.03, name="rail"),
    "plane": HalfSpace((0.0, 2.0, 0.3), (0.2, -1.0, 0.1), name="wall"),
    "mesh": Mesh(*box_mesh((0.0, -0.5, 0.9), (0.3, 0.2, 0.1), 2), name="crate", clearance=0.02),
    "cylinder": Cylinder((0.2, -0.6, 0.2), (0.1, -0.5, 1.3), 0.06, name="post"),
}


def test_every_registered_kind_has_an_example_here() -> None:
    """A new kind adds its example above: the checks below then cover it."""
    assert set(EXAMPLES) == set(KINDS) and all(type(EXAMPLES[k]) is KINDS[k] for k in KINDS)


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_a_kind_says_its_keys_and_is_written_and_read_back(kind, tmp_path: Path) -> None:
    shape = EXAMPLES[kind]
    init = [f.name for f in dataclasses.fields(shape) if f.init and f.name not in ("name", "clearance")]
    assert list(shape.keys) == init and shape.description and shape.kind == kind and kind_of(kind) is type(shape)
    table = obstacle_table(shape)
    assert list(table)[:2] == ["name", "kind"] and set(table) <= kind_keys(kind)
    (back,) = read_obstacles([TableReader(tmp_path / "s.toml", table)], tmp_path)
    assert type(back) is type(shape) and (back.name, back.clearance) == (shape.name, shape.clearance)
    for key in shape.keys:
        np.testing.assert_allclose(getattr(back, key), getattr(shape, key), atol=1e-12, err_msg=key)


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_the_object_of_a_kind_reads_back_as_it(kind) -> None:
    shape = EXAMPLES[kind]
    vertices, faces, matrix, named = placed_mesh(shape)
    assert named == kind and vertices.shape[1] == 3 and faces.shape[1] == 3
    if kind == Mesh.kind:  # the object's own triangles: nothing to read back from bounds
        return
    back = shape_from_bounds(kind, matrix, vertices.min(axis=0), vertices.max(axis=0), name=shape.name)
    for key in shape.keys:
        np.testing.assert_allclose(getattr(back, key), getattr(shape, key), atol=1e-9, err_msg=key)


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_a_kind_answers_by_the_common_conventions(kind) -> None:
    """Unit normals; the obstacle's point is the witness less (distance + radius) along the normal and on the shape's
    surface where apart; the distance inside its bounds grown by the margin, +inf only beyond it."""
    shape = EXAMPLES[kind]
    rng = np.random.default_rng(3)
    p0 = rng.uniform(-0.6, 1.4, (60, 3))
    p1 = p0 + rng.normal(scale=0.2, size=(60, 3))
    radii = rng.uniform(0.01, 0.06, 60)
    got = shape.distance(p0, p1, radii)
    assert np.isfinite(got.distance).all()
    np.testing.assert_allclose(np.linalg.norm(got.normal, axis=1), 1.0, atol=1e-9)
    np.testing.assert_allclose(got.point, p0 + got.t[:, None] * (p1 - p0), atol=1e-12)
    apart = got.distance > 1e-6
    np.testing.assert_allclose(got.closest[apart], (got.point - (got.distance + radii)[:, None] * got.normal)[apart],
                               atol=1e-9)  # fmt: skip
    again = shape.distance(got.closest[apart], got.closest[apart], 0.0)  # the surface point is on the surface
    np.testing.assert_allclose(again.distance, 0.0, atol=1e-9)
    low, high = shape.bounds()
    assert (low <= high).all()
    near = shape.distance(p0, p1, radii, margin=0.05)
    kept = np.isfinite(near.distance)
    np.testing.assert_array_equal(near.distance[kept], got.distance[kept])
    assert (got.distance[~kept] > 0.05).all()


def test_the_registry_refuses_a_second_kind_of_one_name() -> None:
    @dataclasses.dataclass(frozen=True, eq=False)
    class Ball(Sphere):
        kind = "sphere"

    with pytest.raises(ValueError, match="sphere"):
        register(Ball)
    with pytest.raises(KeyError, match="known"):
        kind_of("torus")
    assert issubclass(KINDS["box"], Obstacle) and register(Sphere) is Sphere  # the same kind again: no change


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_a_kind_says_whether_it_is_endless(kind) -> None:
    """``unbounded`` (the object showing it is a piece of it only: Blender's picture leaves it out of its framing)
    agrees with the shape's bounds."""
    low, high = EXAMPLES[kind].bounds()
    assert KINDS[kind].unbounded == (not (np.isfinite(low).all() and np.isfinite(high).all()))
