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
from .schema import in_obstacles, may_be_obstacle


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


class Source:
    """A mesh object that may be an obstacle (a mesh, no carried box), as :func:`scene_obstacles` reads it. A bake
    finds these once (:func:`obstacle_sources`) and keeps them: nobody edits the scene during a bake, but an object
    may be animated. So each frame reads its Obstacle setting (unless its collection makes it an obstacle), its
    shape, clearance and world matrix; its evaluated mesh is read once when nothing can change it with the frame
    (:func:`fixed_mesh`), else every frame."""

    __slots__ = ("ob", "collected", "fixed", "mesh", "last")

    def __init__(self, ob: bpy.types.Object, scripted: bool = False) -> None:
        self.ob = ob
        self.collected = in_obstacles(ob)  # an obstacle whatever its settings
        self.fixed = not scripted and fixed_mesh(ob)
        self.mesh: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray] | None = None  # points, faces, low, high
        self.last: tuple[tuple, Obstacle, list[np.ndarray]] | None = None  # the last shape: its inputs, it, its numbers

    def read_mesh(self, depsgraph: bpy.types.Depsgraph) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """(points, faces, their lowest and highest corner) of the evaluated mesh, in the object's own axes (m)."""
        if self.mesh is not None:
            return self.mesh
        points, faces = _mesh_data(self.ob, depsgraph)
        low, high = (points.min(axis=0), points.max(axis=0)) if len(faces) else (None, None)
        mesh = points, faces, low, high
        if self.fixed:
            self.mesh = mesh
        return mesh


def fixed_mesh(ob: bpy.types.Object) -> bool:
    """Whether ``ob``'s evaluated mesh is its mesh data, unchanged by the frame: no modifiers (which may be keyed,
    driven, read other objects or the time), no shape keys, no animation or drivers on the mesh data."""
    data = ob.data
    return not len(ob.modifiers) and data.shape_keys is None and data.animation_data is None


def obstacle_sources(scene: bpy.types.Scene) -> list[Source]:
    """``scene``'s objects that may be obstacles, in the scene's order. With a frame change handler (a script that
    may edit a mesh on each frame) every mesh is read every frame."""
    handlers = bpy.app.handlers
    scripted = bool(handlers.frame_change_pre or handlers.frame_change_post)
    return [Source(ob, scripted) for ob in scene.objects if may_be_obstacle(ob)]


def scene_obstacles(
    arm: bpy.types.Object, sources: list[Source] | None = None
) -> tuple[list[Obstacle], list[np.ndarray]]:
    """(the obstacles in ``arm``'s space (m), the numbers they came from, for noticing a change). A mesh without
    faces is skipped; a shape's error (a flat box) is a ManikinError naming the object. ``sources``: the scene's
    (:func:`obstacle_sources`; a bake's, kept through its frames), default: found now."""
    to_local = np.array(arm.matrix_world.inverted())
    depsgraph = None  # got when a mesh is read (a bake's fixed meshes are read once)
    shapes, numbers = [], []
    for source in obstacle_sources(bpy.context.scene) if sources is None else sources:
        ob = source.ob
        settings = ob.manikin_obstacle
        if not source.collected and not settings.enabled:
            continue
        if source.mesh is None and depsgraph is None:
            depsgraph = bpy.context.evaluated_depsgraph_get()
        points, faces, low, high = source.read_mesh(depsgraph)
        if not len(faces):
            continue
        world = to_local @ np.array(ob.matrix_world)
        given = (world.tobytes(), settings.shape, settings.clearance)
        last = source.last if source.mesh is not None else None  # a fixed mesh: the same inputs, the same shape
        if last is None or last[0] != given:
            last = source.last = (given, *_shape(ob, points, faces, low, high, world))
        shapes.append(last[1])
        numbers += last[2]
    return shapes, numbers


def _shape(
    ob: bpy.types.Object, points: np.ndarray, faces: np.ndarray, low: np.ndarray, high: np.ndarray, world: np.ndarray
) -> tuple[Obstacle, list[np.ndarray]]:
    """``ob``'s obstacle from its mesh (own axes) and ``world`` (its matrix in the armature's space), and the numbers
    it came from."""
    settings = ob.manikin_obstacle
    try:
        kind = obstacle_kind(settings.shape).kind
    except KeyError:  # saved with a kind no longer registered (its menu item is gone: the shape reads "")
        raise ManikinError(f"obstacle {ob.name!r}: its shape is no registered obstacle kind; choose one in its "
                           "Obstacle panel") from None  # fmt: skip
    counts = np.array([len(points), len(faces), list(KINDS).index(kind), settings.clearance])
    numbers = [world.ravel(), low, high, counts]
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
        key = (ob.name, np.concatenate(numbers).tobytes())  # all a shape made from bounds depends on
    shape = _MADE.get(key)
    if shape is None:
        shape = Mesh(points, faces, **common) if kind == Mesh.kind else \
            shape_from_bounds(kind, world, low, high, **common)  # fmt: skip
        if len(_MADE) >= _KEPT:
            _MADE.pop(next(iter(_MADE)))
        _MADE[key] = shape
    return shape, numbers


# Shapes made lately, by object name and what they came from: a bake reads the scene every frame, and an unchanged
# obstacle is then the same object, made once (so the solver's rows for it can be kept).
_MADE: dict[tuple[str, bytes], Obstacle] = {}
_KEPT = 64
