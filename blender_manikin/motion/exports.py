"""The baked motion through Blender's own exporters (bpy): FBX, BVH and glTF (.glb / .gltf).

Each exporter gets the manikin's armature (active) and the body mesh on display (selected), the bake's frame range
as the scene range, and its settings for a sampled, unsimplified skeletal animation: every frame is written as the
armature has it, so a re-import reproduces the joint rotations and positions (tests/blender/test_bake.py checks BVH and
glTF). The scene's selection and frame range are restored afterwards.
"""

from __future__ import annotations

from pathlib import Path

import bpy

from ...solver.errors import ManikinError
from ..scene.compat import call_known

FORMATS = {".fbx": "FBX", ".bvh": "BVH", ".glb": "glTF binary", ".gltf": "glTF (separate .bin)"}


def check_path(path: str | Path) -> Path:
    """``path`` if its suffix is an export format, else ManikinError naming the formats."""
    path = Path(path)
    if path.suffix.lower() not in FORMATS:
        known = ", ".join(FORMATS)
        raise ManikinError(f"{path}: cannot export {path.suffix or 'a file without suffix'} (use {known})")
    return path


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
    return call_known(
        bpy.ops.export_scene.gltf,
        filepath=str(path), check_existing=False, export_format="GLB" if path.suffix.lower() == ".glb" else
        "GLTF_SEPARATE", use_selection=True, export_animations=True, export_frame_range=True,
        export_force_sampling=True, export_anim_single_armature=True, export_skins=True, export_yup=True,
        export_optimize_animation_size=False,
    )  # fmt: skip


_WRITERS = {".fbx": _fbx, ".bvh": _bvh, ".glb": _gltf, ".gltf": _gltf}


def export(arm: bpy.types.Object, path: str | Path, frame_start: int, frame_end: int) -> Path:
    """Write the armature's animation over ``frame_start..frame_end`` to ``path`` (format by suffix)."""
    path = check_path(path).resolve()
    path.parent.mkdir(parents=True, exist_ok=True)
    context = bpy.context
    scene, view_layer = context.scene, context.view_layer
    selected, active = list(context.selected_objects), view_layer.objects.active
    saved_range = (scene.frame_start, scene.frame_end, scene.frame_current)
    for ob in selected:
        ob.select_set(False)
    shown = [c for c in arm.children if c.type == "MESH" and not c.hide_viewport]  # the body on display, not the rest
    bodies = [c for c in shown if c.name in view_layer.objects]
    unselectable = [ob for ob in bodies if ob.hide_select]
    for ob in [arm, *bodies]:
        ob.hide_select = False  # the body is click-through in the viewport; exporters skip unselectable objects
        ob.select_set(True)
    view_layer.objects.active = arm
    scene.frame_start, scene.frame_end = frame_start, frame_end
    try:
        done = _WRITERS[path.suffix.lower()](path, frame_start, frame_end)
    except RuntimeError as exc:  # an exporter's error report
        raise ManikinError(f"{path}: export failed ({str(exc).strip()})") from None
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
    if done != {"FINISHED"} or not path.is_file():
        raise ManikinError(f"{path}: the {FORMATS[path.suffix.lower()]} exporter wrote nothing")
    return path
