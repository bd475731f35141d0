"""Scenario obstacles as objects in the scene (the import side of :mod:`.obstacles`): each shape becomes a mesh
object in the collection "Obstacles", marked as an obstacle with its clearance and shape (box, sphere, capsule,
plane or mesh: :mod:`solver.collision.placed`), placed in the armature's space, so that export
writes the same shape again. An object an earlier import made with the same name is replaced; any other object of
that name stays, and the new one gets Blender's next free name.
"""

from __future__ import annotations

import bpy
from mathutils import Matrix

from ...solver.collision import Obstacle
from ...solver.collision.placed import placed_mesh
from .schema import IMPORTED_KEY, OBSTACLES


def obstacle_collection(scene: bpy.types.Scene) -> bpy.types.Collection:
    """The collection "Obstacles" in ``scene`` (made, or linked into the scene, when it is not there)."""
    collection = bpy.data.collections.get(OBSTACLES)
    if collection is None:
        collection = bpy.data.collections.new(OBSTACLES)
    if collection not in scene.collection.children_recursive:
        scene.collection.children.link(collection)
    return collection


def _remove_imported(name: str) -> None:
    """Remove the object ``name`` if an import made it (its mesh too, when nothing else uses it)."""
    old = bpy.data.objects.get(name)
    if old is None or IMPORTED_KEY not in old:
        return
    mesh = old.data
    bpy.data.objects.remove(old, do_unlink=True)
    if isinstance(mesh, bpy.types.Mesh) and mesh.users == 0:
        bpy.data.meshes.remove(mesh)


def add_obstacles(scene: bpy.types.Scene, arm: bpy.types.Object, shapes: list[Obstacle], source: str) -> list[str]:
    """An object for each of ``shapes`` (in ``arm``'s space, m), tagged with ``source`` (the scenario's file name);
    a warning for each that could not keep its name or whose kind the shape menu does not offer (kept as a mesh)."""
    collection = obstacle_collection(scene) if shapes else None
    warnings = []
    for shape in shapes:
        _remove_imported(shape.name)
        vertices, faces, local, kind = placed_mesh(shape)
        mesh = bpy.data.meshes.new(shape.name)
        mesh.from_pydata(vertices.tolist(), [], faces.tolist())
        if shape.smooth:  # a round kind (sphere, capsule)
            mesh.shade_smooth()
        ob = bpy.data.objects.new(shape.name, mesh)
        collection.objects.link(ob)
        ob.matrix_world = arm.matrix_world @ Matrix(local.tolist())
        settings = ob.manikin_obstacle
        offered = settings.bl_rna.properties["shape"].enum_items.keys()
        if kind.upper() not in offered:  # a kind the shape menu does not list yet: its object's own triangles
            warnings.append(f"obstacle {shape.name!r}: no {kind} shape in Blender's menu; kept as its mesh")
        settings.enabled, settings.clearance = True, shape.clearance
        settings.shape = kind.upper() if kind.upper() in offered else "MESH"
        ob[IMPORTED_KEY] = source
        if ob.name != shape.name:
            warnings.append(f"obstacle {shape.name!r}: another object has that name; imported as {ob.name!r}")
    return warnings
