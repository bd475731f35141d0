"""The manikin in the scene: building the armature, body and TCP empties, and writing/reading its pose (bpy).

The custom properties it writes (preset, body file, last solution) are named in :mod:`.schema`.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import bpy
import numpy as np
from mathutils import Matrix

from ...solver.body.model import Model
from ...solver.ergonomics.worksheet import STRENGTH_BANDS
from ...solver.errors import ManikinError
from ...solver.io.scenario.bodies import load_body
from ..rigging.bones import RigLayout
from . import display
from .schema import FILE_KEY, PRESET_KEY, TCP_KEY, TCP_PREFIX, X_KEY
from .twist import add_twist_bones, drive_twist_bones

_models: dict[tuple, Model] = {}
_layouts: dict[int, RigLayout] = {}


def clear_caches() -> None:
    """Forget cached models and layouts (on unregister, or after a body file changed)."""
    _models.clear()
    _layouts.clear()
    display.clear_cache()


def load_model(preset: str = "", file: str = "") -> Model:
    """The solver model of a preset or body file, built once per file version; raises ManikinError."""
    key = (preset, file, Path(file).stat().st_mtime if file and Path(file).is_file() else 0.0)
    if key not in _models:
        _models[key] = load_body(preset=preset) if preset else load_body(file=bpy.path.abspath(file))
    return _models[key]


def layout_of(model: Model) -> RigLayout:
    if id(model) not in _layouts:
        _layouts[id(model)] = RigLayout(model)
    return _layouts[id(model)]


def model_of(arm: bpy.types.Object) -> Model:
    return load_model(arm.get(PRESET_KEY, ""), arm.get(FILE_KEY, ""))


def _matrix(m: np.ndarray) -> Matrix:
    return Matrix([list(map(float, row)) for row in m])


def create_manikin(
    context: bpy.types.Context, model: Model, preset: str, file: str, at_cursor: bool = True
) -> bpy.types.Object:
    """Armature (one bone per joint group, and the twist helpers), the skinned human (or the solids for a model
    without one) and ``tcp.<name>`` empties in a new collection, standing on the floor below the 3D cursor (or at
    the world origin)."""
    layout = layout_of(model)
    name = preset or Path(file).stem
    collection = bpy.data.collections.new(name)
    context.scene.collection.children.link(collection)
    data = bpy.data.armatures.new(name)
    data.display_type = "STICK"
    arm = bpy.data.objects.new(name, data)
    arm.show_in_front = True
    cursor = context.scene.cursor.location if at_cursor else (0.0, 0.0, 0.0)
    arm.matrix_world = Matrix.Translation((cursor[0], cursor[1], 0.0))  # on the floor; read back at once
    arm[PRESET_KEY] = preset
    arm[FILE_KEY] = file
    collection.objects.link(arm)
    helpers = _build_bones(context, arm, layout)
    drive_twist_bones(arm, helpers)
    for bone in layout.bones:
        pb = arm.pose.bones[bone.name]
        pb.rotation_mode = bone.rotation_mode
        pb.lock_location = bone.lock_location
        pb.lock_rotation = bone.lock_rotation if bone.exact else (False, False, False)
        pb.lock_scale = (True, True, True)
    arm.manikin.display = display.show(arm, model, layout, "HUMAN")
    for tcp in model.tcps:
        _add_tcp_empty(arm, layout, tcp, collection)
    write_pose(arm, model.zero_pose())
    return arm


@contextmanager
def editing_bones(context: bpy.types.Context, arm: bpy.types.Object) -> Iterator[bpy.types.ArmatureEditBones]:
    """``arm``'s edit bones, with ``arm`` alone selected and active in edit mode; back in object mode after."""
    for obj in context.view_layer.objects.selected:
        obj.select_set(False)
    context.view_layer.objects.active = arm
    arm.select_set(True)
    bpy.ops.object.mode_set(mode="EDIT")
    try:
        yield arm.data.edit_bones
    finally:
        bpy.ops.object.mode_set(mode="OBJECT")


def _build_bones(context: bpy.types.Context, arm: bpy.types.Object, layout: RigLayout) -> list[str]:
    """The layout's bones and the twist helpers (their names returned)."""
    with editing_bones(context, arm) as edit:
        made = []
        for bone in layout.bones:
            eb = edit.new(bone.name)
            eb.head = tuple(bone.head)
            eb.tail = tuple(bone.head + np.array([0.0, bone.length, 0.0]))
            eb.matrix = _matrix(bone.matrix())  # keeps the length, sets direction and roll
            eb.use_deform = True
            if bone.parent >= 0:
                eb.parent = made[bone.parent]
            made.append(eb)
        return add_twist_bones(arm, layout)


def _add_tcp_empty(arm: bpy.types.Object, layout: RigLayout, tcp: str, collection: bpy.types.Collection) -> None:
    b, offset = layout.tcp_in_bone(tcp)
    bone = layout.bones[b]
    empty = bpy.data.objects.new(TCP_PREFIX + tcp, None)
    empty.empty_display_type = "PLAIN_AXES"
    empty.empty_display_size = 0.04
    empty.parent = arm
    empty.parent_type = "BONE"
    empty.parent_bone = bone.name
    # A bone child sits at the bone's tail: undo that shift, then place the TCP in the bone frame.
    to_tail = np.eye(4)
    to_tail[1, 3] = -bone.length
    empty.matrix_parent_inverse = Matrix.Identity(4)
    empty.matrix_basis = _matrix(to_tail @ offset)
    empty.lock_location = empty.lock_rotation = empty.lock_scale = (True, True, True)
    empty[TCP_KEY] = tcp
    collection.objects.link(empty)


def pose_bones(arm: bpy.types.Object, layout: RigLayout) -> list[bpy.types.PoseBone]:
    """The armature's pose bone for every bone of the layout; ManikinError naming a renamed or deleted bone."""
    bones = arm.pose.bones
    found = [bones.get(bone.name) for bone in layout.bones]
    missing = [bone.name for bone, pb in zip(layout.bones, found, strict=True) if pb is None]
    if missing:
        raise ManikinError(
            f"{arm.name}: bone {missing[0]!r} is missing (renamed or deleted?); rename it back or add a new manikin"
        )
    return found


def write_pose(arm: bpy.types.Object, x: np.ndarray) -> None:
    """Pose the armature with joint values ``x[:n]`` and remember ``x`` (with forces) for warm starts."""
    model = model_of(arm)
    layout = layout_of(model)
    theta = np.asarray(x[: model.n], dtype=float)
    loc, euler = layout.channel_values(theta)
    basis = None if all(b.exact for b in layout.bones) else layout.basis_matrices(model.forward(theta))
    for b, (bone, pb) in enumerate(zip(layout.bones, pose_bones(arm, layout), strict=True)):
        if bone.exact:
            pb.location = loc[b]
            pb.rotation_euler = euler[b]
        else:
            pb.matrix_basis = _matrix(basis[b])
    arm[X_KEY] = [float(v) for v in x]


def color_bones_by_load(arm: bpy.types.Object, joint_percent: dict[str, float]) -> None:
    """Colour every pose bone by the highest percent of strength among its joints (the worksheet's bands)."""
    model = model_of(arm)
    for bone in layout_of(model).bones:
        pb = arm.pose.bones.get(bone.name)
        if pb is None or not hasattr(pb, "color"):  # bone colours exist from Blender 4.0 on
            continue
        percents = [joint_percent.get(model.joint_names[j]) for j in bone.joints]
        percents = [p for p in percents if p is not None]
        if not percents:
            pb.color.palette = "DEFAULT"
            continue
        pb.color.palette = "CUSTOM"
        rgb = load_color(max(percents))
        pb.color.custom.normal = rgb
        pb.color.custom.select = tuple(min(1.0, c + 0.3) for c in rgb)
        pb.color.custom.active = tuple(min(1.0, c + 0.5) for c in rgb)


def load_color(percent: float) -> tuple[float, float, float]:
    """Green up to STRENGTH_BANDS[0] % of strength, yellow up to STRENGTH_BANDS[1] %, red above."""
    green, yellow = STRENGTH_BANDS
    if percent <= green:
        return (0.2, 0.75, 0.3)
    return (0.95, 0.8, 0.15) if percent <= yellow else (0.9, 0.2, 0.15)


def read_x(arm: bpy.types.Object) -> np.ndarray:
    """The current pose as solver variables: joint values read from the bone channels, forces remembered."""
    model = model_of(arm)
    layout = layout_of(model)
    stored = np.asarray(arm.get(X_KEY, []), dtype=float)
    fallback = stored[: model.n] if len(stored) >= model.n else model.zero_pose()
    bones = pose_bones(arm, layout)
    loc = np.array([tuple(pb.location) for pb in bones])
    euler = np.array([tuple(pb.rotation_euler) for pb in bones])
    theta = layout.theta_from_channels(loc, euler, fallback)
    return np.concatenate([theta, stored[model.n :]]) if len(stored) > model.n else theta


def tcp_world_frame(arm: bpy.types.Object, x: np.ndarray, tcp: str) -> Matrix:
    """World matrix of a TCP for the solver variables ``x`` (armature object transform included)."""
    model = model_of(arm)
    rot, pos = model.forward(np.asarray(x[: model.n], dtype=float)).tcp_frame(model.tcp(tcp))
    local = np.eye(4)
    local[:3, :3], local[:3, 3] = rot, pos
    return arm.matrix_world @ _matrix(local)
