"""Scene meshes as the solver's obstacles: every mesh object marked as an obstacle (its Manikin panel) or in a
collection named "Obstacles" (:func:`.schema.is_obstacle`), evaluated (modifiers applied) and put in the
armature's space.

An obstacle's ``shape`` (Object.manikin_obstacle: a registered kind's name in upper case, from the menu
:mod:`.registries` makes of :data:`solver.collision.KINDS`) says what the solver keeps clear of: the mesh itself,
or a box, sphere, capsule, plane (half-space), cylinder or any other kind made from the mesh's bounds in the
object's own axes and its transform (:func:`solver.collision.placed.shape_from_bounds`; :mod:`.obstacle_objects`
builds objects from shapes so that this gives them back).
"""

from __future__ import annotations

import hashlib

import bpy
import numpy as np

from ...solver.collision import KINDS, Mesh, Obstacle, degenerate_faces
from ...solver.collision.placed import shape_from_bounds
from ...solver.errors import ManikinError
from .registries import obstacle_kind
from .schema import is_obstacle


def _mesh_data(ob: bpy.types.Object, depsgraph: bpy.types.Depsgraph) -> tuple[np.ndarray, np.ndarray]:
    """(vertices (V, 3) in the object's own axes, triangles (F, 3)) of the evaluated mesh."""
    evaluated = ob.evaluated_get(depsgraph)
    data = evaluated.to_mesh()
    try:
        data.calc_loop_triangles()
        points = np.empty(3 * len(data.vertices))
        data.vertices.foreach_get("co", points)
        faces = np.empty(3 * len(data.loop_triangles), dtype=np.int32)
        data.loop_triangles.foreach_get("vertices", faces)
    finally:
        evaluated.to_mesh_clear()
    return points.reshape(-1, 3), faces.reshape(-1, 3).astype(np.int64)


def scene_obstacles(arm: bpy.types.Object) -> tuple[list[Obstacle], list[np.ndarray]]:
    """(the obstacles in ``arm``'s space (m), the numbers they came from, for noticing a change). A mesh without
    faces is skipped; a shape's error (a flat box) is a ManikinError naming the object."""
    to_local = np.array(arm.matrix_world.inverted())
    depsgraph = bpy.context.evaluated_depsgraph_get()
    shapes, numbers = [], []
    for ob in bpy.context.scene.objects:
        if not is_obstacle(ob):
            continue
        points, faces = _mesh_data(ob, depsgraph)
        if not len(faces):
            continue
        world = to_local @ np.array(ob.matrix_world)
        settings = ob.manikin_obstacle
        try:
            kind = obstacle_kind(settings.shape).kind
        except KeyError:  # saved with a kind no longer registered (its menu item is gone: the shape reads "")
            raise ManikinError(f"obstacle {ob.name!r}: its shape is no registered obstacle kind; choose one in its "
                               "Obstacle panel") from None  # fmt: skip
        counts = np.array([len(points), len(faces), list(KINDS).index(kind), settings.clearance])
        low, high = points.min(axis=0), points.max(axis=0)
        numbers += [world.ravel(), low, high, counts]
        # the property is single precision: 0.03 typed is 0.0299999993; its shortest decimal is what was meant
        common = dict(name=ob.name, clearance=float(f"{settings.clearance:.7g}"))
        if kind == Mesh.kind:  # the object's own triangles, not a shape made from their bounds
            points = points @ world[:3, :3].T + world[:3, 3]
            faces = faces[~degenerate_faces(points, faces)]  # zero-area triangles (collapsed by a modifier)
            if not len(faces):
                raise ManikinError(f"obstacle {ob.name!r}: every triangle has zero area (a flattened object? give it"
                                   " some thickness, or untick Obstacle)")  # fmt: skip
            key = (ob.name, hashlib.blake2b(points.tobytes() + faces.tobytes() + counts.tobytes()).digest())
        else:
            key = (ob.name, np.concatenate(numbers[-4:]).tobytes())  # all a shape made from bounds depends on
        shape = _MADE.get(key)
        if shape is None:
            shape = Mesh(points, faces, **common) if kind == Mesh.kind else \
                shape_from_bounds(kind, world, low, high, **common)  # fmt: skip
            if len(_MADE) >= _KEPT:
                _MADE.pop(next(iter(_MADE)))
            _MADE[key] = shape
        shapes.append(shape)
    return shapes, numbers


# Shapes made lately, by object name and what they came from: a bake reads the scene every frame, and an unchanged
# obstacle is then the same object, made once (so the solver's rows for it can be kept).
_MADE: dict[tuple[str, bytes], Obstacle] = {}
_KEPT = 64
