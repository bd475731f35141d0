"""Scenario obstacles as objects in the scene (the import side of :mod:`.obstacles`): each shape becomes a mesh
object in the scene's obstacle collection, marked as an obstacle with its clearance and shape (its kind's item of
the shape menu, which lists every registered kind: :mod:`.registries`; the mesh and matrix from
:mod:`solver.collision.placed`), placed in the armature's space, so that export writes the same shape again.

Each scene has its own obstacle collection ("Obstacles" in the first, "Obstacles.001" in the next: marked with
``OBSTACLES_KEY``, so a rename keeps it), and an import's objects are found by the mark ``IMPORTED_KEY`` among the
scene's objects: :func:`remove_imported` clears what earlier imports brought into a scene (Import Scenario's
"Replace" option); without it, an object an earlier import made in the scene with the same name is replaced. Any
other object of that name stays, and the new one gets Blender's next free name.
"""

from __future__ import annotations

import bpy
from mathutils import Matrix

from ...solver.collision import Obstacle
from ...solver.collision.placed import placed_mesh
from ...solver.errors import ManikinError
from .registries import shape_of
from .schema import IMPORTED_KEY, OBSTACLES, OBSTACLES_KEY


def obstacle_collection(scene: bpy.types.Scene) -> bpy.types.Collection:
    """``scene``'s own obstacle collection: the marked one in it (or one named "Obstacles"), else a new one (named
    "Obstacles", or "Obstacles.001" when another scene has that name) linked into it."""
    for collection in scene.collection.children_recursive:
        if OBSTACLES_KEY in collection or collection.name == OBSTACLES:
            break
    else:
        collection = bpy.data.collections.new(OBSTACLES)
        scene.collection.children.link(collection)
    if OBSTACLES_KEY not in collection:
        collection[OBSTACLES_KEY] = True
    return collection


def _remove(ob: bpy.types.Object) -> None:
    """Remove ``ob`` (its mesh too, when nothing else uses it)."""
    mesh = ob.data
    bpy.data.objects.remove(ob, do_unlink=True)
    if isinstance(mesh, bpy.types.Mesh) and mesh.users == 0:
        bpy.data.meshes.remove(mesh)


def remove_imported(scene: bpy.types.Scene) -> int:
    """Remove every object of ``scene`` a scenario import made (other scenes' stay); how many."""
    found = [ob for ob in scene.objects if IMPORTED_KEY in ob]
    for ob in found:
        _remove(ob)
    return len(found)


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
        old = scene.objects.get(shape.name)
        if old is not None and IMPORTED_KEY in old:  # an earlier import's object of this name, in this scene
            _remove(old)
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
