"""A scenario's carried box (``[carried]``, :mod:`solver.carried`) as an object: a box mesh made by scenario import,
moved and keyed per frame from its two TCPs' empties after a bake, written back by scenario export.

The object is no obstacle (it moves with the hands; it sits in the manikin's collection, never in "Obstacles").
It remembers what it is in the custom property ``CARRIED_KEY``: JSON with its size (m), TCPs and manikin's name.
"""

from __future__ import annotations

import json

import bpy
import numpy as np
from mathutils import Matrix

from ...solver.carried import Carried, carried_frame
from .schema import tcp_empty

CARRIED_KEY = "manikin_carried"
MATERIAL = "manikin.carried"  # a name of OUR_MATERIALS: the key-pose picture renders it matte
COLOR = (0.62, 0.42, 0.22, 1.0)  # cardboard
_FACES = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]


def find_carried(arm: bpy.types.Object) -> bpy.types.Object | None:
    """The carried box of ``arm`` (by the manikin's name in its property), or None."""
    for ob in bpy.data.objects:
        text = ob.get(CARRIED_KEY)
        if text and json.loads(text).get("armature") == arm.name:
            return ob
    return None


def carried_spec(ob: bpy.types.Object) -> Carried:
    """What the box object ``ob`` is, read from its property."""
    data = json.loads(ob[CARRIED_KEY])
    return Carried(np.asarray(data["size"], dtype=float), tuple(data["tcps"]), data["name"])


def carried_table(arm: bpy.types.Object) -> dict | None:
    """The ``[carried]`` table of ``arm``'s box for scenario export, or None when it has none."""
    ob = find_carried(arm)
    if ob is None:
        return None
    spec = carried_spec(ob)
    return dict(name=spec.name, size=[float(v) for v in spec.size], tcps=list(spec.tcps))


def add_carried(arm: bpy.types.Object, carried: Carried) -> bpy.types.Object:
    """A box object for ``carried`` beside ``arm`` (an earlier one of ``arm`` is replaced), placed between its
    TCPs as they are now."""
    old = find_carried(arm)
    if old is not None:
        mesh = old.data
        bpy.data.objects.remove(old, do_unlink=True)
        if mesh.users == 0:
            bpy.data.meshes.remove(mesh)
    half = np.asarray(carried.size, dtype=float) / 2.0
    corners = [(x * half[0], y * half[1], z * half[2]) for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]
    mesh = bpy.data.meshes.new(carried.name)
    mesh.from_pydata(corners, [], _FACES)
    material = bpy.data.materials.get(MATERIAL) or bpy.data.materials.new(MATERIAL)
    material.diffuse_color = COLOR
    mesh.materials.append(material)
    ob = bpy.data.objects.new(carried.name, mesh)
    collections = arm.users_collection or (bpy.context.scene.collection,)
    collections[0].objects.link(ob)
    ob.rotation_mode = "QUATERNION"
    data = dict(name=carried.name, size=[float(v) for v in carried.size], tcps=list(carried.tcps), armature=arm.name)
    ob[CARRIED_KEY] = json.dumps(data)
    place_carried(ob, arm)
    return ob


def place_carried(ob: bpy.types.Object, arm: bpy.types.Object) -> bool:
    """Put the box between its TCPs' empties as they are now; False (left where it is) when one is missing."""
    empties = [tcp_empty(arm, tcp) for tcp in carried_spec(ob).tcps]
    if None in empties:
        return False
    centre, rotation = carried_frame(*(np.array(e.matrix_world.translation) for e in empties))
    world = np.eye(4)
    world[:3, :3], world[:3, 3] = rotation, centre
    ob.matrix_world = Matrix(world.tolist())
    return True


def key_carried(scene: bpy.types.Scene, arm: bpy.types.Object, frames: list[int]) -> int:
    """Key ``arm``'s box (location and rotation) at each of ``frames`` from its TCPs there; the frames keyed."""
    ob = find_carried(arm)
    if ob is None or not frames:
        return 0
    current, keyed = scene.frame_current, 0
    for frame in frames:
        scene.frame_set(frame)
        if place_carried(ob, arm):
            ob.keyframe_insert("location", frame=frame)
            ob.keyframe_insert("rotation_quaternion", frame=frame)
            keyed += 1
    scene.frame_set(current)
    return keyed
