"""A scenario's carried box (``[carried]``, :mod:`solver.collision.carried`) as an object: a box mesh made by scenario
import,
placed between its two TCPs after every solve (Solve Pose, live mode), keyed with the hands by every bake (the
sidebar's and the batch's: :meth:`.bake.Baker.write`), written back by scenario export.

The object is no scene obstacle (it moves with the hands; it sits in the manikin's collection, never in
"Obstacles"); :func:`.problem_io.read_problem` hands it to the solver as the carried box, which the body but the
holding hands keeps out of. It remembers what it is in the custom property ``CARRIED_KEY``: JSON with its size
(m), TCPs and manikin's name (for files saved before the pointer), and its manikin in ``CARRIED_RIG_KEY``: a
pointer, so renaming the armature or the box changes nothing but the name.
"""

from __future__ import annotations

import json

import bpy
import numpy as np
from mathutils import Matrix

from ...solver.body.model import Kinematics, Model
from ...solver.body.spatial import matrix_to_quat
from ...solver.collision.carried import Carried, carried_frame
from . import keyframes
from .armature import model_of
from .schema import CARRIED_KEY, CARRIED_RIG_KEY, tcp_empty

MATERIAL = "manikin.carried"  # a name of OUR_MATERIALS: the key-pose picture renders it matte
COLOR = (0.62, 0.42, 0.22, 1.0)  # cardboard
GROUP = "Object Transforms"  # the F-curve group Blender itself keys an object's transform in
_FACES = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]


def find_carried(arm: bpy.types.Object) -> bpy.types.Object | None:
    """The carried box of ``arm`` (by the pointer it holds; a box saved before the pointer: by the manikin's name),
    or None. Writes nothing (draw callbacks and handlers call it)."""
    for ob in bpy.data.objects:
        if CARRIED_KEY not in ob:
            continue
        if CARRIED_RIG_KEY in ob:
            if ob[CARRIED_RIG_KEY] == arm:
                return ob
        elif json.loads(ob[CARRIED_KEY]).get("armature") == arm.name:
            return ob
    return None


def remove_carried(arm: bpy.types.Object) -> bool:
    """Remove ``arm``'s box (and its mesh when nothing else uses it); False when it has none."""
    old = find_carried(arm)
    if old is None:
        return False
    mesh = old.data
    bpy.data.objects.remove(old, do_unlink=True)
    if mesh.users == 0:
        bpy.data.meshes.remove(mesh)
    return True


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
    remove_carried(arm)
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
    ob[CARRIED_RIG_KEY] = arm  # the box's identity: a pointer, not the name in the JSON
    place_carried(ob, arm)
    return ob


def box_world(model: Model, tcps: tuple[str, str], theta: np.ndarray, world: np.ndarray) -> np.ndarray:
    """The box's 4x4 world matrix for the joint values ``theta`` with the armature object at ``world`` (4x4): its
    centre midway between the two TCPs (m), its axes as :func:`solver.collision.carried.carried_frame` says."""
    kin = model.forward(np.asarray(theta, dtype=float)[: model.n])
    return _box_at([kin.tcp_frame(model.tcp(tcp))[1] for tcp in tcps], world)


def tcp_points(model: Model, tcps: tuple[str, str], kin: Kinematics) -> list[np.ndarray]:
    """The positions (m, armature space) of the box's two TCPs in the pose ``kin`` (a solve's kinematics)."""
    return [kin.tcp_frame(model.tcp(tcp))[1] for tcp in tcps]


def _box_at(points: list[np.ndarray] | np.ndarray, world: np.ndarray) -> np.ndarray:
    """The box's 4x4 world matrix, its TCPs at ``points`` (m, armature space), the armature object at ``world``."""
    return _matrix(*carried_frame(*[world[:3, :3] @ p + world[:3, 3] for p in points]))


def _matrix(centre: np.ndarray, rotation: np.ndarray) -> np.ndarray:
    out = np.eye(4)
    out[:3, :3], out[:3, 3] = rotation, centre
    return out


def _solved_tcps(ob: bpy.types.Object, arm: bpy.types.Object) -> tuple[str, str] | None:
    """The box's TCPs when the manikin's model has both (a renamed body file may not), else None."""
    tcps = carried_spec(ob).tcps
    return tcps if all(tcp in model_of(arm).tcps for tcp in tcps) else None


def keyed_tcps(arm: bpy.types.Object) -> tuple[str, str] | None:
    """The TCPs between which :func:`key_carried` keys ``arm``'s box, or None: no box (or TCPs the model lacks)."""
    ob = find_carried(arm)
    return None if ob is None else _solved_tcps(ob, arm)


def place_carried(ob: bpy.types.Object, arm: bpy.types.Object, x: np.ndarray | None = None) -> bool:
    """Put the box between its TCPs: where the solver variables ``x`` put them, or (``x`` None) where their
    empties are now. False (left where it is) when a TCP or its empty is missing."""
    if x is not None:
        tcps = _solved_tcps(ob, arm)
        if tcps is None:
            return False
        box = box_world(model_of(arm), tcps, x, np.array(arm.matrix_world))
    else:
        empties = [tcp_empty(arm, tcp) for tcp in carried_spec(ob).tcps]
        if None in empties:
            return False
        box = _matrix(*carried_frame(*(np.array(e.matrix_world.translation) for e in empties)))
    ob.matrix_world = Matrix(box.tolist())
    return True


def follow_solve(arm: bpy.types.Object, x: np.ndarray) -> None:
    """After a solve of ``arm`` (solver variables ``x``): its box, if it has one, between the solved TCPs."""
    ob = find_carried(arm)
    if ob is not None:
        place_carried(ob, arm, x)


def key_carried(
    arm: bpy.types.Object,
    frames: np.ndarray,
    thetas: np.ndarray,
    worlds: np.ndarray,
    thin: bool = False,
    points: np.ndarray | None = None,
) -> int:
    """Key ``arm``'s box (location, quaternion; linear, as the joints) at each of ``frames`` between its TCPs where
    the joint values ``thetas`` (frames, n) put them, the armature object at ``worlds`` (frames, 4, 4) there. Keys
    outside the frames' range stay; ``thin`` as :func:`.keyframes.replace_keys`. ``points``: the TCPs' positions
    in those poses (frames, 2, 3; :func:`tcp_points` of each frame's solve, in :func:`keyed_tcps`' order), which
    saves a forward kinematics per frame. Returns the frames keyed."""
    ob = find_carried(arm)
    tcps = None if ob is None else _solved_tcps(ob, arm)
    if tcps is None or not len(frames):
        return 0
    if points is not None:
        boxes = [_box_at(at, world) for at, world in zip(points, worlds, strict=True)]
    else:
        model = model_of(arm)
        boxes = [box_world(model, tcps, theta, world) for theta, world in zip(thetas, worlds, strict=True)]
    quats = np.array([matrix_to_quat(box[:3, :3]) for box in boxes])
    for i in range(1, len(quats)):  # q and -q are one turn: keep neighbours on one side so keys interpolate short
        if quats[i] @ quats[i - 1] < 0.0:
            quats[i] = -quats[i]
    ob.rotation_mode = "QUATERNION"
    locations = np.array([box[:3, 3] for box in boxes])
    for path, values in (("location", locations), ("rotation_quaternion", quats)):
        for k in range(values.shape[1]):
            keyframes.replace_keys(keyframes.fcurve(ob, path, k, GROUP), frames, values[:, k], thin)
    return len(frames)
