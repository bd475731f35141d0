"""Retarget a manikin's baked motion onto another armature (bpy): every check first (nothing changes on bad input),
then each frame sampled from the evaluated scene, solved by :mod:`solver.retarget` and keyed in bulk on the
target's action (one F-curve per channel, in each bone's own rotation mode; location on the hips bone only).

Feet are pinned at the frames where the manikin's target empty for that foot is an enabled support (read at each
frame, so keyed supports count); hands when the target's ``pin_hands`` option is on, to goals chosen by its
``hand_goals`` option. A generated Rigify rig is refused; after keying, keyed bones whose evaluated pose is not
where their keys put them (driven by constraints) are named. The summary is stored on the target
(``manikin_retargeted`` JSON, :mod:`..scene.schema`).
"""

from __future__ import annotations

import json
from dataclasses import asdict, dataclass, field

import bpy
import numpy as np
from mathutils import Matrix

from ...solver.body.spatial import matrix_to_quat
from ...solver.errors import ManikinError, UsageError
from ...solver.retarget.bone_map import check_map
from ...solver.retarget.names import auto_map
from ...solver.retarget.skeleton import object_scale
from ...solver.retarget.transfer import LIMBS, Plan, basis_matrices, miss_cause, plan, solve_motion
from ..scene import keyframes
from ..scene.compat import object_fcurves
from ..scene.schema import RETARGET_KEY, is_manikin, last_bake, members
from .armatures import read_pose, read_skeleton, world_matrix
from .progress import Progress
from .properties import read_rows, write_rows
from .rig_checks import FOLLOW_M, check_not_generated, driven, off_keys


@dataclass
class Summary:
    """What a retarget did (stored on the target, shown in the panel)."""

    source: str
    frame_start: int
    frame_end: int
    bones: int  # target bones keyed
    ratio: float  # target leg length / the manikin's
    pinned_frames: int  # frames with at least one pinned limb
    max_miss: float  # m: the farthest a pinned limb end stayed from its goal (out of reach)
    missed: str = ""  # the limb of max_miss (hand_l, foot_r, ...)
    miss_cause: str = ""  # why it stayed short
    facing_deg: float = 0.0  # the motion's turn about world up onto the character's facing
    hand_goals: str = "body"  # the pinned hands' goals used: body (scaled about the ankles) or arm (about the shoulder)
    unfollowed: list[str] = field(default_factory=list)  # keyed bones driven by constraints, with their constraints
    unfollowed_m: float = 0.0  # m: the farthest a keyed bone's evaluated head or tail is from where its keys put it


def baked_range(source: bpy.types.Object) -> tuple[int, int]:
    """The manikin's baked frame range (its last bake's, else its action's); UsageError when nothing is baked."""
    curves = [fc for fc in object_fcurves(source) if fc.data_path.startswith("pose.bones")]
    if not curves:
        raise UsageError(f"'{source.name}' has no baked motion: bake one first (Motion > Bake Motion)")
    bake = last_bake(source)
    if bake is not None:
        return int(bake["frame_start"]), int(bake["frame_end"])
    frames = [k.co.x for fc in curves for k in fc.keyframe_points]
    return round(min(frames)), round(max(frames))


def source_of(target: bpy.types.Object, scene: bpy.types.Scene) -> bpy.types.Object:
    """The target's chosen manikin, else the scene's only one; UsageError otherwise."""
    chosen = target.manikin_retarget.source
    if chosen is not None and is_manikin(chosen) and chosen.name in scene.objects:
        return chosen
    found = [ob for ob in scene.objects if is_manikin(ob)]
    if len(found) != 1:
        names = ", ".join(ob.name for ob in found) or "none"
        raise UsageError(f"choose the manikin to retarget from in the Retarget panel (manikins in the scene: {names})")
    return found[0]


def check_target(target: bpy.types.Object | None) -> None:
    if target is None:
        raise UsageError("no target: select the character's armature")
    if target.type != "ARMATURE":
        raise UsageError(f"'{target.name}' is not an armature: select the character's armature")
    if is_manikin(target):
        raise UsageError(f"'{target.name}' is a manikin: select the character's armature to retarget onto")
    check_not_generated(target)
    object_scale(world_matrix(target))  # ModelError for a non-uniform scale


def bone_map_for(source: bpy.types.Object, target: bpy.types.Object) -> tuple[dict[str, str], bool]:
    """(the target's stored map, or one filled in from its bone names; whether it was filled in now), checked."""
    stored = read_rows(target)
    filled = not stored
    bone_map = auto_map(read_skeleton(source), read_skeleton(target)) if filled else stored
    theirs = {b.name: b.parent.name if b.parent else None for b in target.data.bones}
    check_map(bone_map, tuple(source.data.bones.keys()), theirs, target.name)
    return bone_map, filled


def _pinned(source: bpy.types.Object, pin_feet: bool, pin_hands: bool) -> set[str]:
    """The limbs to pin at the scene's current frame."""
    out = {"hand_l", "hand_r"} if pin_hands else set()
    if pin_feet:
        for ob in members(source):
            s = ob.manikin_target
            if s.role == "TARGET" and s.support and s.enabled and s.tcp in LIMBS:
                out.add(s.tcp)
    return out


def sample(scene: bpy.types.Scene, source: bpy.types.Object, target: bpy.types.Object, the_plan: Plan,
           frames: list[int], progress: Progress) -> tuple[np.ndarray, list[list[str]]]:  # fmt: skip
    """Per frame, our world poses and the limbs to pin. The scene returns to its frame."""
    settings = target.manikin_retarget
    current = (scene.frame_current, scene.frame_subframe)
    poses, pinned = [], []
    try:
        for frame in frames:
            scene.frame_set(frame)
            poses.append(read_pose(source, the_plan.source.names))
            pinned.append(sorted(_pinned(source, settings.pin_feet, settings.pin_hands)))
            progress.step("sampled", len(poses))
    finally:
        scene.frame_set(current[0], subframe=current[1])
    return np.array(poses), pinned


def _follow(scene: bpy.types.Scene, target: bpy.types.Object, the_plan: Plan, frames: list[int],
            poses: np.ndarray) -> tuple[list[str], float]:  # fmt: skip
    """(the keyed bones the evaluated scene puts elsewhere than their keys, with their constraints; the farthest
    (m)), checked at the first, middle and last frame. The scene returns to its frame."""
    keyed = list(the_plan.keyed)
    names = [the_plan.target.names[b] for b in keyed]
    lengths = the_plan.target.lengths[keyed]
    current = (scene.frame_current, scene.frame_subframe)
    off = np.zeros(len(keyed))
    try:
        for i in sorted({0, len(frames) // 2, len(frames) - 1}):
            scene.frame_set(frames[i])
            off = np.maximum(off, off_keys(poses[i][keyed], read_pose(target, tuple(names)), lengths))
    finally:
        scene.frame_set(current[0], subframe=current[1])
    moved = [n for n, d in zip(names, off, strict=True) if d > FOLLOW_M]
    if not moved:
        return [], float(off.max(initial=0.0))
    return driven(target, moved) or [f"{moved[0]} (no constraint found: drivers?)"], float(off.max())


def _rotation_values(pb: bpy.types.PoseBone, rotations: np.ndarray) -> tuple[str, np.ndarray]:
    """(data path, (frames, k) values) of ``rotations`` (frames, 3, 3) in the bone's own rotation mode."""
    mode = pb.rotation_mode
    quats = np.array([matrix_to_quat(r) for r in rotations])
    for i in range(1, len(quats)):  # the short way round from frame to frame
        if quats[i] @ quats[i - 1] < 0.0:
            quats[i] = -quats[i]
    if mode == "QUATERNION":
        return "rotation_quaternion", quats
    if mode == "AXIS_ANGLE":
        angles = 2.0 * np.arccos(np.clip(quats[:, 0], -1.0, 1.0))
        axes = quats[:, 1:] / np.maximum(np.linalg.norm(quats[:, 1:], axis=1, keepdims=True), 1e-12)
        axes[np.linalg.norm(quats[:, 1:], axis=1) < 1e-12] = (0.0, 1.0, 0.0)
        return "rotation_axis_angle", np.column_stack([angles, axes])
    eulers, previous = [], None
    for r in rotations:
        e = Matrix(r.tolist()).to_euler(mode) if previous is None else Matrix(r.tolist()).to_euler(mode, previous)
        eulers.append(tuple(e))
        previous = e
    return "rotation_euler", np.array(eulers)


def write_keys(target: bpy.types.Object, the_plan: Plan, frames: list[int], poses: np.ndarray) -> None:
    """Key the plan's bones: rotations in each bone's mode, the hips bone's location (object units)."""
    scale = object_scale(world_matrix(target))
    basis = np.array([basis_matrices(the_plan.target, p, scale) for p in poses])  # (frames, bones, 4, 4)
    keys = np.asarray(frames, dtype=float)
    for b in the_plan.keyed:
        name = the_plan.target.names[b]
        pb = target.pose.bones[name]
        base = f'pose.bones["{bpy.utils.escape_identifier(name)}"]'
        path, values = _rotation_values(pb, basis[:, b, :3, :3])
        channels = [(path, values)]
        if b == the_plan.hips[1]:
            channels.append(("location", basis[:, b, :3, 3]))
        for prop, array in channels:
            for i in range(array.shape[1]):
                keyframes.replace_keys(keyframes.fcurve(target, f"{base}.{prop}", i, name), keys, array[:, i])


def retarget(scene: bpy.types.Scene, target: bpy.types.Object, frame_range: tuple[int, int] | None = None,
             window_manager: object | None = None) -> Summary:  # fmt: skip
    """Key the baked motion of the target's manikin onto ``target`` over its baked range (or ``frame_range``);
    ManikinError (one line, nothing changed) for bad input. ``window_manager``: shows the progress in the UI."""
    check_target(target)
    source = source_of(target, scene)
    start, end = baked_range(source) if frame_range is None else frame_range
    if end < start:
        raise UsageError(f"frame range {start}..{end} is empty (end before start)")
    bone_map, filled = bone_map_for(source, target)
    the_plan = plan(read_skeleton(source), read_skeleton(target), bone_map, world_matrix(source)[:3, :3] /
                    object_scale(world_matrix(source)))  # fmt: skip
    frames = list(range(start, end + 1))
    settings = target.manikin_retarget
    with Progress(f"Retarget onto {target.name}", len(frames), window_manager) as progress:
        ours, pinned = sample(scene, source, target, the_plan, frames, progress)
        poses, misses, goals = solve_motion(the_plan, ours, pinned, settings.hand_goals.lower(),
                                            lambda done: progress.step("solved", done))  # fmt: skip
    if not np.isfinite(poses).all():
        raise ManikinError(f"'{target.name}': the retargeted poses are not finite (degenerate bones in the map?)")
    write_keys(target, the_plan, frames, poses)
    unfollowed, off = _follow(scene, target, the_plan, frames, poses)
    scene.frame_set(scene.frame_current, subframe=scene.frame_subframe)  # show the keyed pose now
    settings.source = source
    if filled:
        write_rows(target, list(source.data.bones.keys()), bone_map)
    worst = max(((m, k) for frame in misses for k, m in frame.items() if m > 0.0), default=(0.0, ""))
    summary = Summary(source.name, start, end, len(the_plan.keyed), the_plan.ratio, sum(1 for p in pinned if p),
                      worst[0], worst[1], miss_cause(the_plan, worst[1], goals) if worst[1] else "",
                      the_plan.facing_deg, goals, unfollowed, off)  # fmt: skip
    target[RETARGET_KEY] = json.dumps(asdict(summary))
    return summary
