"""Armatures as the retarget sees them (bpy): any armature read into a :class:`solver.retarget.Skeleton` and its
posed bones, and the shipped MPFB rigs built in the scene on a manikin's fitted body.

A shipped rig is a new armature object ``<manikin>.<rig>`` beside the manikin (``RIG_OFFSET`` to its left), in its
collection, its bones where :func:`solver.retarget.shipped.rig_bones` puts them, each bone's roll carried over
from MPFB's A-pose (Blender computes the roll: the bone is laid out in MPFB's rest with MPFB's roll, then turned
by the smallest rotation onto its fitted direction). Rigify's metarig gets its rig types when Rigify is enabled.
"""

from __future__ import annotations

import bpy
import numpy as np
from mathutils import Matrix

from ...solver.retarget.shipped import rig_bones, rig_map
from ...solver.retarget.skeleton import Skeleton, object_scale, rigid_world, rotation_between, skeleton
from ..scene.armature import editing_bones, model_of
from .properties import write_rows

RIG_OFFSET = (1.0, 0.0, 0.0)  # m, world: where a new shipped rig stands relative to its manikin
_bodies: dict[int, object] = {}  # model id -> FittedBody (fitting takes a fraction of a second)


def world_matrix(ob: bpy.types.Object) -> np.ndarray:
    return np.array(ob.matrix_world, dtype=float)


def read_skeleton(arm: bpy.types.Object) -> Skeleton:
    """The armature's bones at rest in world space (m), parents first."""
    bones = arm.data.bones
    local = np.array([np.array(b.matrix_local, dtype=float) for b in bones])
    world = world_matrix(arm)
    return skeleton(
        [b.name for b in bones],
        [b.parent.name if b.parent else None for b in bones],
        rigid_world(world, local),
        np.array([b.length for b in bones]) * object_scale(world),
    )


def read_pose(arm: bpy.types.Object, names: tuple[str, ...]) -> np.ndarray:
    """(B, 4, 4) world frames of the pose bones ``names`` as the scene is now (evaluated)."""
    pose = arm.pose.bones
    local = np.array([np.array(pose[n].matrix, dtype=float) for n in names])
    return rigid_world(world_matrix(arm), local)


def fitted_body(manikin: bpy.types.Object):
    """The manikin's FittedBody (solver.bodymesh), fitted once per model."""
    from ...solver.bodymesh import fit_body

    model = model_of(manikin)
    if id(model) not in _bodies:
        _bodies.clear()
        _bodies[id(model)] = fit_body(model)
    return _bodies[id(model)]


def _roll_matrix(head: np.ndarray, tail: np.ndarray, rest_head: np.ndarray, rest_tail: np.ndarray, roll: float,
                 eb: bpy.types.EditBone) -> Matrix:  # fmt: skip
    """The 4x4 bone matrix at ``head`` pointing to ``tail`` whose x axis is MPFB's (rolled in its rest) turned
    by the smallest rotation from the rest direction onto this one."""
    eb.head, eb.tail, eb.roll = tuple(rest_head), tuple(rest_tail), roll
    axes = np.array(eb.matrix.to_3x3(), dtype=float)
    turned = rotation_between(rest_tail - rest_head, tail - head) @ axes
    m = np.eye(4)
    m[:3, :3], m[:3, 3] = turned, head
    return Matrix(m.tolist())


def add_shipped_rig(context: bpy.types.Context, manikin: bpy.types.Object, rig: str) -> bpy.types.Object:
    """Build shipped rig ``rig`` (``mixamo``, ...) on the manikin's body beside it; the new armature object
    (selected and active, in object mode). Its bone map is the shipped one."""
    bones = rig_bones(fitted_body(manikin), rig)
    bone_map = rig_map(rig)
    name = f"{manikin.name}.{rig}"
    arm = bpy.data.objects.new(name, bpy.data.armatures.new(name))
    arm.matrix_world = Matrix.Translation(RIG_OFFSET) @ manikin.matrix_world
    arm.show_in_front = True
    collection = manikin.users_collection[0] if manikin.users_collection else context.scene.collection
    collection.objects.link(arm)
    with editing_bones(context, arm) as edit:
        for b in bones:
            eb = edit.new(b.name)
            eb.matrix = _roll_matrix(b.head, b.tail, b.rest_head, b.rest_tail, b.roll, eb)
            eb.length = float(np.linalg.norm(b.tail - b.head))
        for b in bones:
            if b.parent is not None:
                edit[b.name].parent = edit[b.parent]
                edit[b.name].use_connect = b.connect
    for b in bones:
        pb = arm.pose.bones[b.name]
        if b.rigify_type and hasattr(pb, "rigify_type"):  # only while the Rigify add-on is enabled
            pb.rigify_type = b.rigify_type
    settings = arm.manikin_retarget
    settings.source = manikin
    settings.rig = rig
    write_rows(arm, list(manikin.data.bones.keys()), bone_map)
    return arm
