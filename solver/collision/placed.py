"""Obstacle shapes placed as a 3D scene keeps objects: a mesh in the object's own axes and a 4x4 matrix (m).

:func:`placed_mesh` gives a shape's mesh, matrix and kind (the scenario's: box, sphere, capsule, plane, mesh, or
any other registered kind); :func:`shape_from_bounds` reads a shape back from an object's mesh bounds and matrix.
The two are inverse (each kind's :meth:`~solver.collision.kinds.base.Obstacle.placed` and
:meth:`~solver.collision.kinds.base.Obstacle.from_bounds`): a box is its bounds, a sphere and a capsule (along local
z) touch theirs, a plane is a square through its point with its normal along local z. Blender's obstacles use both
(``blender_manikin/scene``).
"""

from __future__ import annotations

import numpy as np

from .kinds import KINDS, Obstacle


def placed_mesh(shape: Obstacle) -> tuple[np.ndarray, np.ndarray, np.ndarray, str]:
    """(vertices (V, 3) in the object's axes, triangles (F, 3), the object's matrix (4x4), the kind) that show
    ``shape`` and that :func:`shape_from_bounds` reads back as it (a mesh: its own triangles in place)."""
    return (*shape.placed(), shape.kind)


def shape_from_bounds(kind: str, matrix: np.ndarray, low: np.ndarray, high: np.ndarray, **common) -> Obstacle:
    """The ``kind`` (box, sphere, capsule, plane or another kind made from bounds) of an object whose mesh spans
    ``low``-``high`` (3,) in its own axes, placed by ``matrix`` (4x4, scale allowed, no shear): box = the bounds;
    sphere = the bounds' middle, half their largest dimension; capsule = along local z, as long as the bounds,
    radius half their largest x/y dimension; plane = through the bounds' middle, the free side along local z (m).
    ``common``: name, clearance."""
    if kind not in KINDS:
        raise ValueError(f"unknown obstacle shape {kind!r}")
    scale = np.linalg.norm(matrix[:3, :3], axis=0)
    rotation = matrix[:3, :3] / np.where(scale > 0, scale, 1.0)
    if np.linalg.det(rotation) < 0:  # mirrored: turn one axis back, the box is the same
        rotation[:, 0] *= -1.0
    center = matrix[:3, :3] @ (0.5 * (np.asarray(low) + high)) + matrix[:3, 3]
    size = (np.asarray(high) - low) * scale
    return KINDS[kind].from_bounds(center, rotation, size, **common)
