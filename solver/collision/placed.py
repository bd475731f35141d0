"""Obstacle shapes placed as a 3D scene keeps objects: a mesh in the object's own axes and a 4x4 matrix (m).

:func:`placed_mesh` gives a shape's mesh, matrix and kind (the scenario's: box, sphere, capsule, plane, mesh);
:func:`shape_from_bounds` reads a box, sphere, capsule or plane back from an object's mesh bounds and matrix. The
two are inverse: a box is its bounds, a sphere and a capsule (along local z) touch theirs, a plane is a square
through its point with its normal along local z. Blender's obstacles use both (``blender_manikin/scene``).
"""

from __future__ import annotations

import numpy as np

from .generate import axis_frame, box_mesh, capsule_mesh
from .shapes import Box, Capsule, HalfSpace, Obstacle, Sphere

PLANE_SIZE = 4.0  # m: the edge of the square that shows a plane (a half-space has no edges)
SEGMENTS = 24  # around a sphere or capsule
RINGS = 6  # latitudes per half sphere


def _placed(rotation: np.ndarray, position: np.ndarray) -> np.ndarray:
    matrix = np.eye(4)
    matrix[:3, :3], matrix[:3, 3] = rotation, position
    return matrix


def placed_mesh(shape: Obstacle) -> tuple[np.ndarray, np.ndarray, np.ndarray, str]:
    """(vertices (V, 3) in the object's axes, triangles (F, 3), the object's matrix (4x4), the kind: box, sphere,
    capsule, plane or mesh) that show ``shape`` and that :func:`shape_from_bounds` reads back as it."""
    if isinstance(shape, Box):
        vertices, faces = box_mesh(np.zeros(3), shape.size)
        return vertices, faces, _placed(shape.rotation, shape.center), "box"
    if isinstance(shape, Sphere):
        vertices, faces = capsule_mesh(np.zeros(3), np.zeros(3), shape.radius, SEGMENTS, RINGS)
        return vertices, faces, _placed(np.eye(3), shape.center), "sphere"
    if isinstance(shape, Capsule):
        half = 0.5 * float(np.linalg.norm(shape.b - shape.a))
        vertices, faces = capsule_mesh((0.0, 0.0, -half), (0.0, 0.0, half), shape.radius, SEGMENTS, RINGS)
        return vertices, faces, _placed(axis_frame(shape.b - shape.a), 0.5 * (shape.a + shape.b)), "capsule"
    if isinstance(shape, HalfSpace):
        corners = 0.5 * PLANE_SIZE * np.array([[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0], [-1.0, 1.0, 0.0]])
        faces = np.array([[0, 1, 2], [0, 2, 3]], dtype=np.int64)  # counter-clockwise seen from the free side
        return corners, faces, _placed(axis_frame(shape.normal), shape.point), "plane"
    return np.array(shape.vertices), np.array(shape.faces), np.eye(4), "mesh"


def shape_from_bounds(kind: str, matrix: np.ndarray, low: np.ndarray, high: np.ndarray, **common) -> Obstacle:
    """The ``kind`` (box, sphere, capsule or plane) of an object whose mesh spans ``low``-``high`` (3,) in its own
    axes, placed by ``matrix`` (4x4, scale allowed, no shear): box = the bounds; sphere = the bounds' middle, half
    their largest dimension; capsule = along local z, as long as the bounds, radius half their largest x/y
    dimension; plane = through the bounds' middle, the free side along local z (m). ``common``: name, clearance."""
    scale = np.linalg.norm(matrix[:3, :3], axis=0)
    rotation = matrix[:3, :3] / np.where(scale > 0, scale, 1.0)
    if np.linalg.det(rotation) < 0:  # mirrored: turn one axis back, the box is the same
        rotation[:, 0] *= -1.0
    center = matrix[:3, :3] @ (0.5 * (np.asarray(low) + high)) + matrix[:3, 3]
    size = (np.asarray(high) - low) * scale
    if kind == "box":
        return Box(center, size, rotation, **common)
    if kind == "sphere":
        return Sphere(center, 0.5 * float(size.max()), **common)
    if kind == "capsule":
        radius = 0.5 * float(size[:2].max())
        half = max(0.5 * float(size[2]) - radius, 0.0)
        return Capsule(center - half * rotation[:, 2], center + half * rotation[:, 2], radius, **common)
    if kind == "plane":
        return HalfSpace(center, rotation[:, 2], **common)
    raise ValueError(f"unknown obstacle shape {kind!r}")
