"""Keyed targets between scenario files and the scene (bpy): ``[[targets.keys]]`` <-> keyframes on the empties.

Import keys each keyed target empty's location and quaternion at the scenario's key frames with linear
interpolation, so positions between keys are exactly the scenario's; rotations between keys are normalised
linear blends of the quaternions (Blender's), equal to the scenario's slerp at the keys and for constant or small
turns. The scene's frame range and the manikin's per-frame change bound come from ``[motion]``. Export writes
a key for every frame at which a target empty has a key, read from the evaluated scene (so constraints and
parents count), and ``[motion]`` from the scene's range.
"""

from __future__ import annotations

import bpy
import numpy as np
from mathutils import Matrix

from ...solver.body.spatial import matrix_to_quat
from ...solver.problem.scenario import Scenario
from ..scene import keyframes
from ..scene.schema import members

GROUP = "Object Transforms"  # Blender's own group name for an object's transform channels


def target_empties(arm: bpy.types.Object) -> list[bpy.types.Object]:
    """The target empties of ``arm`` in the order :func:`problem_io.read_problem` lists their targets."""
    return [ob for ob in members(arm) if ob.manikin_target.role == "TARGET"]


def key_target(ob: bpy.types.Object, arm: bpy.types.Object, keys: list[tuple[int, np.ndarray, np.ndarray]]) -> None:
    """Key ``ob`` at each (frame, position, rotation 3x3) given in the armature's space (its own space when it is
    parented to the armature, as imported targets are: they move with the manikin)."""
    ob.rotation_mode = "QUATERNION"
    space = Matrix.Identity(4) if ob.parent == arm else arm.matrix_world
    frames = np.array([k[0] for k in keys], dtype=float)
    locations, quats = [], []
    for _, position, rotation in keys:
        local = np.eye(4)
        local[:3, :3], local[:3, 3] = rotation, position
        loc, quat, _ = (space @ Matrix(local.tolist())).decompose()
        q = np.array(quat)
        if quats and float(q @ quats[-1]) < 0.0:  # the short way round between keys
            q = -q
        locations.append(np.array(loc))
        quats.append(q)
    for path, values in (("location", np.array(locations)), ("rotation_quaternion", np.array(quats))):
        for i in range(values.shape[1]):
            keyframes.replace_keys(keyframes.fcurve(ob, path, i, GROUP), frames, values[:, i])


def import_motion(scene: bpy.types.Scene, arm: bpy.types.Object, sc: Scenario, empties: list[bpy.types.Object]) -> int:
    """Key the target empties (``empties[i]`` holds scenario target i) of the keyed targets, set the frame range
    and the per-frame change bound; returns the number of keyed targets."""
    settings = arm.manikin
    settings.bound_motion = sc.limits is not None
    if sc.limits is not None:
        settings.max_joint_change, settings.max_root_shift = sc.limits.max_joint_change, sc.limits.max_root_shift
    if not sc.tracks:
        return 0
    zero = sc.model.forward(sc.model.zero_pose())
    for track in sc.tracks:
        target = sc.problem.all_targets[track.target]
        default = zero.tcp_frame(sc.model.tcp(target.tcp))[0]
        keys = [(k.frame, k.position, default if k.rotation is None else k.rotation) for k in track.keys]
        key_target(empties[track.target], arm, keys)
    scene.frame_start, scene.frame_end = sc.frames[0], sc.frames[-1]
    scene.frame_set(sc.frames[0])
    return len(sc.tracks)


def _short(value: float) -> float:
    """A single-precision number as the shortest float that reads back the same (0.35, not 0.3499999940395355)."""
    return float(f"{value:.7g}")


def _local_frame(arm: bpy.types.Object, ob: bpy.types.Object) -> tuple[list[float], list[float]]:
    loc, quat, _ = (arm.matrix_world.inverted() @ ob.matrix_world).decompose()
    return [_short(v) for v in loc], [_short(v) for v in matrix_to_quat(np.array(quat.to_matrix()))]


def export_motion(data: dict, scene: bpy.types.Scene, arm: bpy.types.Object) -> int:
    """Turn the target tables of ``data`` (from ``scenario_to_dict``) whose empties have keys into keyed targets
    and add ``[motion]``; returns the number of keyed targets. The scene's frame is restored."""
    empties = target_empties(arm)
    if len(empties) != len(data.get("targets", [])):
        raise RuntimeError("the target tables do not match the target empties")
    current = (scene.frame_current, scene.frame_subframe)
    keyed = 0
    try:
        for table, ob in zip(data.get("targets", []), empties, strict=True):
            frames = sorted({round(f) for f in keyframes.key_frames(ob)})
            if not frames:
                continue
            keys = []
            for frame in frames:
                scene.frame_set(frame)
                position, rotation = _local_frame(arm, ob)
                keys.append(dict(frame=frame, position=position, rotation=rotation))
            table.pop("position", None)
            table.pop("rotation", None)
            table["keys"] = keys
            keyed += 1
    finally:
        scene.frame_set(current[0], subframe=current[1])
    if keyed:
        s = arm.manikin
        data["motion"] = dict(
            start=scene.frame_start,
            end=scene.frame_end,
            bounded=s.bound_motion,
            max_joint_change=_short(s.max_joint_change),
            max_root_shift=_short(s.max_root_shift),
        )
    return keyed
