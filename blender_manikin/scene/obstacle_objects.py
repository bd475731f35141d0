"""Scenario obstacles as objects in the scene (the import side of :mod:`.obstacles`): each shape becomes a mesh
object in the collection "Obstacles", marked as an obstacle with its clearance and shape (its kind's item of the
shape menu, which lists every registered kind: :mod:`.registries`; the mesh and matrix from
:mod:`solver.collision.placed`), placed in the armature's space, so that export
writes the same shape again. An object an earlier import made with the same name is replaced; any other object of
that name stays, and the new one gets Blender's next free name.
"""

from __future__ import annotations

import bpy
from mathutils import Matrix

from ...solver.collision import Obstacle
from ...solver.collision.placed import placed_mesh
from ...solver.errors import ManikinError
from .registries import shape_of
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


def check_shapes(shapes: list[Obstacle]) -> None:
    """ManikinError (one line) if a shape's kind is not in the shape menu: registered after the add-on was."""
    menu = bpy.types.Object.bl_rna.properties["manikin_obstacle"].fixed_type.properties["shape"].enum_items.keys()
    for shape in shapes:
        if shape_of(shape.kind) not in menu:
            raise ManikinError(f"obstacle {shape.name!r}: the {shape.kind} kind was registered after Manikin was "
                               "enabled; enable Manikin again to add it to the shape menu")  # fmt: skip


def add_obstacles(scene: bpy.types.Scene, arm: bpy.types.Object, shapes: list[Obstacle], source: str) -> list[str]:
    """An object for each of ``shapes`` (in ``arm``'s space, m), tagged with ``source`` (the scenario's file name);
    a warning for each that could not keep its name (:func:`check_shapes` first)."""
    check_shapes(shapes)
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
        settings.enabled, settings.clearance, settings.shape = True, shape.clearance, shape_of(kind)
        ob[IMPORTED_KEY] = source
        if ob.name != shape.name:
            warnings.append(f"obstacle {shape.name!r}: another object has that name; imported as {ob.name!r}")
    return warnings
