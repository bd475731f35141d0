"""The baked motion through Blender's own exporters (bpy): FBX, BVH and glTF (.glb / .gltf).

Each exporter gets the manikin's armature (active), the body mesh on display and, for FBX and glTF, the carried box
(its own object with its own animation; BVH holds one skeleton only) selected, nothing else; the bake's frame range
as the scene range; and its settings for a sampled, unsimplified skeletal animation: every frame is written as the
armature has it, so a re-import reproduces the joint rotations and positions (tests/blender/test_bake.py and
test_export.py check it). The scene's selection and frame range are restored afterwards.

Frames: glTF stores frame f at f / fps and Blender's glTF import keys it at f again. Blender's FBX exporter stores
frame f at f / fps too, but its FBX import adds an "Animation Offset" of 1 frame (the default), so a plain export
re-imports one frame late; the FBX is therefore written with the keys moved one frame earlier (frame f at
(f - 1) / fps: Blender's frame 1 is the FBX time 0, where Unity and Unreal start a take). BVH stores no start frame:
the importer's Start Frame puts the first frame (docs/guide/exports.md lists every importer's settings).

Each file is written to a temporary file beside it, checked and renamed onto it (:mod:`.written`): a full disk or
an exporter's error leaves the old file as it was, and says so in one line naming it.
"""

from __future__ import annotations

import json
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import bpy
import numpy as np

from ...solver.errors import ManikinError
from ..scene.compat import call_known, object_fcurves
from ..scene.schema import CARRIED_KEY
from .job_input import FORMATS, check_path
from .written import written_by_path

FBX_IMPORT_OFFSET = 1  # frames Blender's FBX import adds by default ("Animation Offset")
GLTF = {".glb", ".gltf"}
WITH_BOX = {".fbx", ".glb", ".gltf"}  # formats that hold more than one skeleton: the carried box goes along


def _fbx(path: Path, start: int, end: int) -> set[str]:
    return call_known(
        bpy.ops.export_scene.fbx,
        filepath=str(path), check_existing=False, use_selection=True, object_types={"ARMATURE", "MESH"},
        add_leaf_bones=False, bake_anim=True, bake_anim_use_all_bones=True, bake_anim_use_nla_strips=False,
        bake_anim_use_all_actions=False, bake_anim_force_startend_keying=True, bake_anim_step=1.0,
        bake_anim_simplify_factor=0.0,
    )  # fmt: skip


def _bvh(path: Path, start: int, end: int) -> set[str]:
    return call_known(
        bpy.ops.export_anim.bvh,
        filepath=str(path), check_existing=False, frame_start=start, frame_end=end, rotate_mode="NATIVE",
        root_transform_only=False,
    )  # fmt: skip


def _gltf(path: Path, start: int, end: int) -> set[str]:
    # the armature's and the box's actions as one glTF animation: an import plays both
    return call_known(
        bpy.ops.export_scene.gltf,
        filepath=str(path), check_existing=False, export_format="GLB" if path.suffix.lower() == ".glb" else
        "GLTF_SEPARATE", use_selection=True, export_animations=True, export_frame_range=True,
        export_force_sampling=True, export_anim_single_armature=True, export_skins=True, export_yup=True,
        export_optimize_animation_size=False, export_animation_mode="ACTIVE_ACTIONS",
        export_nla_strips_merged_animation_name="Manikin motion",
    )  # fmt: skip


@contextmanager
def _keys_moved(objects: list[bpy.types.Object], frames: float) -> Iterator[None]:
    """Every key (and handle) of the objects' F-curves moved by ``frames`` while inside, moved back afterwards."""
    curves = list({fc.as_pointer(): fc for ob in objects for fc in object_fcurves(ob)}.values())  # shared actions once
    actions = {ob.animation_data.action for ob in objects if ob.animation_data and ob.animation_data.action}

    def move(by: float) -> None:
        for fc in curves:
            for attribute in ("co", "handle_left", "handle_right"):
                xy = np.empty(2 * len(fc.keyframe_points), dtype=np.float32)
                fc.keyframe_points.foreach_get(attribute, xy)
                xy[0::2] += by
                fc.keyframe_points.foreach_set(attribute, xy)
        for action in actions:
            action.update_tag()  # else the evaluated copy keeps the old keys (4.2)

    move(frames)
    try:
        yield
    finally:
        move(-frames)


def carried_box(arm: bpy.types.Object) -> bpy.types.Object | None:
    """The carried box of ``arm`` in the view layer (scene/carried_object.py marks it), or None."""
    view_layer = bpy.context.view_layer
    for ob in bpy.data.objects:
        text = ob.get(CARRIED_KEY)
        if text and json.loads(text).get("armature") == arm.name and ob.name in view_layer.objects:
            return ob
    return None


_WRITERS = {".fbx": _fbx, ".bvh": _bvh, ".glb": _gltf, ".gltf": _gltf}


def export(arm: bpy.types.Object, path: str | Path, frame_start: int, frame_end: int) -> Path:
    """Write the armature's animation over ``frame_start..frame_end`` to ``path`` (format by suffix)."""
    path = check_path(path).resolve()
    suffix = path.suffix.lower()
    shift = -FBX_IMPORT_OFFSET if suffix == ".fbx" else 0
    if frame_start + shift < 0:
        raise ManikinError(f"{path}: FBX needs the motion to start at frame {-shift} or later, not {frame_start}")
    context = bpy.context
    scene, view_layer = context.scene, context.view_layer
    selected, active = list(context.selected_objects), view_layer.objects.active
    saved_range = (scene.frame_start, scene.frame_end, scene.frame_current)
    for ob in selected:
        ob.select_set(False)
    shown = [c for c in arm.children if c.type == "MESH" and not c.hide_viewport]  # the body on display, not the rest
    bodies = [c for c in shown if c.name in view_layer.objects]
    box = carried_box(arm) if suffix in WITH_BOX else None
    objects = [arm, *bodies, *([box] if box is not None else [])]
    unselectable = [ob for ob in objects if ob.hide_select]
    for ob in objects:
        ob.hide_select = False  # the body is click-through in the viewport; exporters skip unselectable objects
        ob.select_set(True)
    view_layer.objects.active = arm
    scene.frame_start, scene.frame_end = frame_start + shift, frame_end + shift
    added = suffix if suffix in GLTF else ""  # the glTF exporter puts its suffix on the temporary file's name
    try:  # into a temporary file, checked, then renamed: a failure (a full disk) leaves the old file as it was
        with written_by_path(path, added) as work, _keys_moved([arm, *([box] if box is not None else [])], shift):
            done = _WRITERS[suffix](work, frame_start + shift, frame_end + shift)
            if done != {"FINISHED"} or not work.is_file():
                raise ManikinError(f"{path}: the {FORMATS[suffix]} exporter wrote nothing")
    finally:
        scene.frame_start, scene.frame_end = saved_range[:2]
        scene.frame_set(saved_range[2])
        for ob in context.selected_objects:
            ob.select_set(False)
        for ob in selected:
            ob.select_set(True)
        view_layer.objects.active = active
        for ob in unselectable:
            ob.hide_select = True
    return path
