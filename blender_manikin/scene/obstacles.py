"""Scene meshes as the solver's obstacles: every mesh object marked as an obstacle (its Manikin panel) or in a
collection named "Obstacles", evaluated (modifiers applied) and put in the armature's space."""

from __future__ import annotations

import bpy
import numpy as np

from ...solver.collision import Mesh, degenerate_faces

COLLECTION = "Obstacles"  # every mesh in a collection of this name is an obstacle


def is_obstacle(ob: bpy.types.Object) -> bool:
    """A mesh object marked as an obstacle, or in the "Obstacles" collection."""
    if ob.type != "MESH":
        return False
    return bool(ob.manikin_obstacle.enabled) or any(c.name == COLLECTION for c in ob.users_collection)


def scene_obstacles(arm: bpy.types.Object) -> tuple[list[Mesh], list[np.ndarray]]:
    """(the obstacles as meshes in ``arm``'s space (m), the numbers they came from, for noticing a change)."""
    to_local = np.array(arm.matrix_world.inverted())
    depsgraph = bpy.context.evaluated_depsgraph_get()
    meshes, numbers = [], []
    for ob in bpy.context.scene.objects:
        if not is_obstacle(ob):
            continue
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
        if not len(faces):
            continue
        world = to_local @ np.array(ob.matrix_world)
        points = points.reshape(-1, 3) @ world[:3, :3].T + world[:3, 3]
        faces = faces.reshape(-1, 3).astype(np.int64)
        faces = faces[~degenerate_faces(points, faces)]  # zero-area triangles (collapsed by a modifier) carry nothing
        clearance = float(ob.manikin_obstacle.clearance)
        meshes.append(Mesh(points, faces, name=ob.name, clearance=clearance))
        numbers += [world.ravel(), np.array([len(points), len(faces), clearance])]
    return meshes, numbers
