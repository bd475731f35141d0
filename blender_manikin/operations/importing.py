"""An operations scenario file into the scene (bpy): what Import Scenario does with its manikin, supports and
obstacles (:func:`..scenario.read.apply_scenario`), then each ``[[objects]]`` as a marked mesh with its grasps as
child empties (:mod:`.objects`' names: ``grasp_NAME_r`` / ``grasp_NAME_l``; proposed grasps are not made: the
generator proposes them again), each ``[[operations]]`` as an item of the scene's list, a target empty
``opN.<do>`` where it has a point (``to``, ``at``), and ``[operate] fps``. Generate Motion then writes the same
tables again. The file is read and planned by the solver first, so a bad one is one line before anything changes.
"""

from __future__ import annotations

from pathlib import Path

import bpy
import numpy as np
from mathutils import Matrix

from ...solver.body.spatial import quat_to_matrix
from ...solver.collision.placed import placed_mesh
from ...solver.operations.objects import origin_of
from ..scene.carried_object import COLOR, MATERIAL
from ..scene.schema import IMPORTED_KEY

TARGET_SIZE = 0.1  # m: the target empties' axes


def _link(scene: bpy.types.Scene, ob: bpy.types.Object, like: bpy.types.Object) -> None:
    (like.users_collection[0] if like.users_collection else scene.collection).objects.link(ob)


def add_object(scene: bpy.types.Scene, arm: bpy.types.Object, obj, source: str) -> bpy.types.Object:
    """A marked mesh for the work object ``obj`` (``solver.operations.objects.WorkObject``) in ``arm``'s space, with
    an empty per hand of each grasp the file gave."""
    old = scene.objects.get(obj.name)
    if old is not None and IMPORTED_KEY in old:  # an earlier import's object of this name
        for child in list(old.children):
            bpy.data.objects.remove(child, do_unlink=True)
        bpy.data.objects.remove(old, do_unlink=True)
    vertices, faces, local, _ = placed_mesh(obj.shape)
    mesh = bpy.data.meshes.new(obj.name)
    mesh.from_pydata(vertices.tolist(), [], faces.tolist())
    material = bpy.data.materials.get(MATERIAL) or bpy.data.materials.new(MATERIAL)
    material.diffuse_color = COLOR  # cardboard, as a carried box: told apart from the grey obstacles
    mesh.materials.append(material)
    ob = bpy.data.objects.new(obj.name, mesh)
    scene.collection.objects.link(ob)
    ob.matrix_world = arm.matrix_world @ Matrix(local.tolist())
    ob.manikin_object.enabled, ob.manikin_object.mass = True, obj.mass
    ob[IMPORTED_KEY] = source
    origin = origin_of(obj.shape)
    for grasp in obj.grasps.values():
        if grasp.proposed:
            continue
        for tcp, hand in grasp.hands.items():
            empty = bpy.data.objects.new(f"grasp_{'_'.join(grasp.name.split())}_{tcp[-1]}", None)
            empty.empty_display_type, empty.empty_display_size = "ARROWS", 0.06
            _link(scene, empty, ob)
            world = np.eye(4)
            world[:3, :3] = obj.rotation @ hand.rotation
            world[:3, 3] = origin + obj.rotation @ hand.position
            empty.parent = ob
            empty.matrix_world = arm.matrix_world @ Matrix(world.tolist())
    return ob


def _target(scene: bpy.types.Scene, arm: bpy.types.Object, name: str, point, rotation, source: str):
    old = scene.objects.get(name)
    if old is not None and IMPORTED_KEY in old:
        bpy.data.objects.remove(old, do_unlink=True)
    empty = bpy.data.objects.new(name, None)
    empty.empty_display_type, empty.empty_display_size = "PLAIN_AXES", TARGET_SIZE
    _link(scene, empty, arm)
    world = np.eye(4)
    world[: len(point), 3] = point
    if rotation is not None:
        world[:3, :3] = quat_to_matrix(rotation) if np.shape(rotation) == (4,) else rotation
    empty.matrix_world = arm.matrix_world @ Matrix(world.tolist())
    empty[IMPORTED_KEY] = source
    return empty


def _named(scene: bpy.types.Scene, name: str, made: dict, source: str) -> bpy.types.Object | None:
    """The object the file calls ``name``: one this import made (it may have got Blender's ".001"), else the
    scene's of that name."""
    if name in made:
        return made[name]
    found = [ob for ob in scene.objects if ob.get(IMPORTED_KEY) == source and ob.name.rpartition(".")[0] == name]
    return found[0] if found else scene.objects.get(name)


def add_operations(scene: bpy.types.Scene, arm: bpy.types.Object, operations, source: str, made: dict) -> list[str]:
    """The scene's list made of ``operations`` (``solver.operations.schema.Operation``; ``made``: the objects this
    import made, by the file's names); warnings for what the panel has no setting for (a grasp, an MTM-1 case)."""
    settings = scene.manikin_operations
    settings.items.clear()
    warnings = []
    for i, op in enumerate(operations):
        item = settings.items.add()
        item.do = op.do.upper()
        label = op.label.partition("(")[2].rstrip(")")
        if label != op.do + (f" {op.object}" if op.object else ""):
            item.name = label
        if op.object is not None:
            item.object = _named(scene, op.object, made, source)
        if op.onto is not None:
            item.target = _named(scene, op.onto, made, source)
        point = op.at if op.do == "look" else op.to
        if point is not None:
            item.target = _target(scene, arm, f"op{i + 1}.{op.do}", point, op.rotation, source)
            item.use_rotation = op.rotation is not None
        item.hands = op.hands.upper()
        if op.duration is not None:
            item.use_duration, item.duration = True, op.duration
        item.hold = op.hold
        item.priority = "DEFAULT" if op.priority is None else str(op.priority)
        dropped = [f"grasp {op.grasp!r}" if op.grasp else "", f"case {op.case}" if op.case else ""]
        if any(dropped):
            warnings.append(f"operation {i + 1}: the panel has no {' or '.join(d for d in dropped if d)} setting; "
                            "the generator chooses")  # fmt: skip
    settings.index = 0
    return warnings


def import_operations(context: bpy.types.Context, path: str | Path, onto: bpy.types.Object | None,
                      planned=None) -> tuple:  # fmt: skip
    """Read the operations scenario ``path`` into the scene; (the manikin, objects made, operations, warnings).
    ManikinError (one line) for a bad file, before anything changes. ``planned``: the file's
    ``solver.operations.generate.Job`` when the caller has read and planned it already (batch.py)."""
    from ...solver.io.scenario.read import read_toml
    from ...solver.operations.generate import load_operations
    from ...solver.operations.schema import read_operations
    from ..scenario.read import apply_scenario

    path = Path(path)
    job = planned or load_operations(path)  # the whole file read and planned: a bad operation is one line here
    operations = read_operations(read_toml(path))
    done = apply_scenario(context, job.scenario, path.name, onto, replace=True)
    scene, arm = context.scene, done.arm
    made = {name: add_object(scene, arm, obj, path.name) for name, obj in job.objects.items()}
    warnings = done.warnings + [f"object {name!r}: another object has that name; imported as {ob.name!r}"
                                for name, ob in made.items() if ob.name != name]  # fmt: skip
    warnings += add_operations(scene, arm, operations, path.name, made)
    scene.manikin_operations.fps = int(round(job.operate.fps))
    scene.frame_start = job.operate.start
    for ob in context.view_layer.objects.selected:
        ob.select_set(False)
    arm.select_set(True)
    context.view_layer.objects.active = arm
    return arm, list(made.values()), operations, warnings
