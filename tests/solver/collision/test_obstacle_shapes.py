"""Obstacle shapes as a scene keeps objects and back (solver/collision/placed.py, used by Blender's obstacles): the
object made for a shape reads back as that shape, also after the object is scaled instead of its mesh."""

from __future__ import annotations

import numpy as np
import pytest

from solver.collision import Box, Capsule, HalfSpace, Mesh, Sphere
from solver.collision.generate import axis_frame, box_mesh
from solver.collision.placed import placed_mesh, shape_from_bounds

SHAPES = [
    Box((0.1, -0.5, 0.4), (0.8, 0.4, 0.6), axis_frame((1.0, 2.0, 0.5)), name="table", clearance=0.01),
    Sphere((1.0, 1.0, 1.0), 0.1, name="ball"),
    Capsule((1.0, 0.0, 1.0), (1.2, 0.8, 0.7), 0.03, name="rail"),
    Capsule((0.5, 0.5, 0.5), (0.5, 0.5, 0.5), 0.05, name="knob"),  # ends that meet
    HalfSpace((0.0, 2.0, 0.3), (0.2, -1.0, 0.1), name="wall"),
]


def _same(a, b) -> None:
    assert (type(a), a.name, a.clearance) == (type(b), b.name, b.clearance)
    for field in ("center", "size", "rotation", "radius", "a", "b", "point", "normal"):
        if hasattr(a, field):
            np.testing.assert_allclose(getattr(b, field), getattr(a, field), atol=1e-9, err_msg=field)


@pytest.mark.parametrize("shape", SHAPES, ids=lambda s: s.name)
def test_the_object_of_a_shape_reads_back_as_the_shape(shape) -> None:
    vertices, faces, matrix, kind = placed_mesh(shape)
    assert kind == type(shape).__name__.lower().replace("halfspace", "plane")
    common = dict(name=shape.name, clearance=shape.clearance)
    _same(shape, shape_from_bounds(kind, matrix, vertices.min(axis=0), vertices.max(axis=0), **common))
    if kind != "plane":
        closed = Mesh(vertices, faces)
        assert closed.is_closed() and closed.signed_volume() > 0


@pytest.mark.parametrize("shape", [s for s in SHAPES if not isinstance(s, HalfSpace)], ids=lambda s: s.name)
def test_scaling_the_object_instead_of_its_mesh_gives_the_same_shape(shape) -> None:
    vertices, _, matrix, kind = placed_mesh(shape)
    scale = np.array([2.0, 0.5, 4.0])
    scaled = matrix.copy()
    scaled[:3, :3] = matrix[:3, :3] * scale  # the object scaled, its mesh shrunk to match
    low, high = vertices.min(axis=0) / scale, vertices.max(axis=0) / scale
    _same(shape, shape_from_bounds(kind, scaled, low, high, name=shape.name, clearance=shape.clearance))


def test_a_mirrored_object_is_the_same_box_and_a_mesh_stays_as_it_is() -> None:
    box = SHAPES[0]
    vertices, _, matrix, _ = placed_mesh(box)
    mirrored = matrix.copy()
    mirrored[:3, 0] *= -1.0
    back = shape_from_bounds("box", mirrored, vertices.min(axis=0), vertices.max(axis=0), name="table")
    assert np.linalg.det(back.rotation) == pytest.approx(1.0)
    corners = box_mesh(back.center, back.size, 1, back.rotation)[0]
    np.testing.assert_allclose(np.sort(corners, axis=0), np.sort(box_mesh(box.center, box.size, 1, box.rotation)[0],
                                                                 axis=0), atol=1e-9)  # fmt: skip
    mesh = Mesh(*box_mesh((0.0, 0.0, 0.0), (1.0, 1.0, 1.0)), name="crate")
    vertices, faces, matrix, kind = placed_mesh(mesh)
    assert kind == "mesh"
    np.testing.assert_array_equal(matrix, np.eye(4))
    np.testing.assert_array_equal(vertices, mesh.vertices)
    np.testing.assert_array_equal(faces, mesh.faces)
    with pytest.raises(ValueError, match="cone"):
        shape_from_bounds("cone", np.eye(4), np.zeros(3), np.ones(3))
