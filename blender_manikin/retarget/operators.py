"""Retarget operators: add a shipped target rig, fill in / load / save a bone map, and Retarget (a manikin's baked
motion keyed onto the selected armature). Errors are reported in one line and change nothing. The scene code and
the solver's numerics load inside ``execute``."""

from __future__ import annotations

from pathlib import Path

import bpy
from bpy.props import EnumProperty, IntProperty, StringProperty
from bpy_extras.io_utils import ExportHelper, ImportHelper

from ...solver.errors import ManikinError
from ..scene.schema import is_manikin, rig_of

_rig_items: list[tuple[str, str, str]] = []  # kept alive: Blender holds on to the strings of dynamic enum items


def rig_items(_self, _context) -> list[tuple[str, str, str]]:
    """The shipped rigs, read when the menu opens (the add-on enables without loading the retarget package)."""
    if not _rig_items:
        from ...solver.retarget.bone_map import SHIPPED_RIGS

        _rig_items.extend((name, label, f"MPFB 2's {label} rig, placed on the manikin's body")
                          for name, (_, label) in SHIPPED_RIGS.items())  # fmt: skip
    return _rig_items


def _target(context: bpy.types.Context, name: str = "") -> bpy.types.Object | None:
    return bpy.data.objects.get(name) if name else context.active_object


class MANIKIN_OT_add_retarget_rig(bpy.types.Operator):
    """Add a shipped rig (MPFB default, game engine, Mixamo, CMU, Rigify metarig) on the manikin's body beside it,
    with its bone map: a target for Retarget without external files"""

    bl_idname = "manikin.add_retarget_rig"
    bl_label = "Add Target Rig"
    bl_options = {"REGISTER", "UNDO"}

    rig: EnumProperty(name="Rig", items=rig_items)

    @classmethod
    def poll(cls, context: bpy.types.Context) -> bool:
        if rig_of(context.active_object) is None:
            cls.poll_message_set("Select a manikin, or one of its targets")
            return False
        return context.mode == "OBJECT"

    def execute(self, context: bpy.types.Context) -> set[str]:
        from .armatures import add_shipped_rig

        try:
            arm = add_shipped_rig(context, rig_of(context.active_object), self.rig)
        except ManikinError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        self.report({"INFO"}, f"Added {arm.name} ({len(arm.data.bones)} bones); Retarget keys the baked motion on it")
        return {"FINISHED"}


class _TargetOperator(bpy.types.Operator):
    """Base: acts on the armature named by ``target`` (default: the active object)."""

    bl_options = {"REGISTER", "UNDO"}

    target: StringProperty(
        name="Target", description="The armature to act on (default: the active object)", options={"SKIP_SAVE"}
    )

    @classmethod
    def poll(cls, context: bpy.types.Context) -> bool:
        if context.mode not in {"OBJECT", "POSE"}:
            return False
        if context.active_object is None and not any(is_manikin(ob) for ob in context.scene.objects):
            cls.poll_message_set("Select the armature to retarget onto")
            return False
        return True

    def fail(self, message: str) -> set[str]:
        self.report({"ERROR"}, message)
        return {"CANCELLED"}


class MANIKIN_OT_retarget(_TargetOperator):
    """Key the manikin's baked motion onto the selected armature: rest poses aligned, the hips carrying the
    translation (scaled by the leg-length ratio), turned to the character's facing, supported feet pinned (and
    hands, if chosen) by IK"""

    bl_idname = "manikin.retarget"
    bl_label = "Retarget"

    # SKIP_SAVE: a later call (a click in the panel) must not reuse an earlier call's target or range
    frame_start: IntProperty(name="Start", description="First frame (default: the manikin's baked range)",
                             options={"SKIP_SAVE"})  # fmt: skip
    frame_end: IntProperty(name="End", description="Last frame (default: the manikin's baked range)",
                           options={"SKIP_SAVE"})  # fmt: skip

    def execute(self, context: bpy.types.Context) -> set[str]:
        from .motion import retarget

        frames = None
        if self.properties.is_property_set("frame_start") or self.properties.is_property_set("frame_end"):
            frames = (self.frame_start, self.frame_end)
        target = _target(context, self.target)
        try:
            s = retarget(context.scene, target, frames, context.window_manager)
        except ManikinError as exc:
            return self.fail(str(exc))
        pins = f", limbs pinned in {s.pinned_frames} frames" if s.pinned_frames else ""
        turned = f", motion turned {s.facing_deg:.0f} deg to the character's facing" if abs(s.facing_deg) >= 1 else ""
        hands = ", hands arm-relative" if s.hand_goals == "arm" and s.pinned_frames else ""
        done = f"{s.bones} bones keyed, leg-length ratio {s.ratio:.3f}{pins}{turned}{hands}"
        self.report({"INFO"}, f"Retargeted {s.source} frames {s.frame_start}-{s.frame_end} onto {target.name}: {done}")
        if s.unfollowed:
            self.report({"WARNING"}, f"{target.name} does not follow its keys (up to {s.unfollowed_m * 1e3:.0f} mm "
                                     f"off): bones driven by constraints: {', '.join(s.unfollowed[:3])}; mute them "
                                     "or map the bones that drive them")  # fmt: skip
        if s.max_miss > 1e-3:
            self.report({"WARNING"}, f"The pinned {s.missed} stayed up to {s.max_miss * 1e3:.0f} mm short of its "
                                     f"goal: {s.miss_cause}")  # fmt: skip
        return {"FINISHED"}


class MANIKIN_OT_auto_fill_bone_map(_TargetOperator):
    """Fill in the bone map from the target's bone names (Mixamo, Rigify, Unreal, MPFB, CMU, 3ds Max, VRoid,
    SMPL conventions) and its spine's geometry, replacing the rows"""

    bl_idname = "manikin.auto_fill_bone_map"
    bl_label = "Auto-Fill Bone Map"

    def execute(self, context: bpy.types.Context) -> set[str]:
        from ...solver.retarget.bone_map import REQUIRED
        from ...solver.retarget.names import auto_map
        from .armatures import read_skeleton
        from .motion import check_target, source_of
        from .properties import write_rows

        target = _target(context, self.target)
        try:
            check_target(target)
            source = source_of(target, context.scene)
            bone_map = auto_map(read_skeleton(source), read_skeleton(target))
        except ManikinError as exc:
            return self.fail(str(exc))
        write_rows(target, list(source.data.bones.keys()), bone_map)
        target.manikin_retarget.source = source
        missing = [k for k in REQUIRED if k not in bone_map]
        if missing:
            self.report({"WARNING"}, f"Mapped {len(bone_map)} bones; fill in {', '.join(missing)} by hand")
        else:
            self.report({"INFO"}, f"Mapped {len(bone_map)} bones of {target.name}")
        return {"FINISHED"}


class MANIKIN_OT_load_bone_map(_TargetOperator, ImportHelper):
    """Load a bone map TOML (our bone = "their bone") into the target's rows (the shipped ones are in
    presets/bone_maps)"""

    bl_idname = "manikin.load_bone_map"
    bl_label = "Load Bone Map"

    filename_ext = ".toml"
    filter_glob: StringProperty(default="*.toml", options={"HIDDEN"})

    def invoke(self, context: bpy.types.Context, event: bpy.types.Event) -> set[str]:
        from ...solver.retarget.bone_map import BONE_MAPS_DIR

        self.filepath = str(BONE_MAPS_DIR) + "/"
        return super().invoke(context, event)

    def execute(self, context: bpy.types.Context) -> set[str]:
        from ...solver.retarget.bone_map import load_map
        from .motion import check_target, source_of
        from .properties import write_rows

        target = _target(context, self.target)
        try:
            check_target(target)
            source = source_of(target, context.scene)
            _, bone_map = load_map(self.filepath)
        except ManikinError as exc:
            return self.fail(str(exc))
        write_rows(target, list(source.data.bones.keys()), bone_map)
        self.report({"INFO"}, f"Loaded {len(bone_map)} bone pairs from {Path(self.filepath).name}")
        return {"FINISHED"}


class MANIKIN_OT_save_bone_map(_TargetOperator, ExportHelper):
    """Save the target's bone map as TOML (to reuse it on another character with the same bone names)"""

    bl_idname = "manikin.save_bone_map"
    bl_label = "Save Bone Map"

    filename_ext = ".toml"
    filter_glob: StringProperty(default="*.toml", options={"HIDDEN"})

    def execute(self, context: bpy.types.Context) -> set[str]:
        from ...solver.retarget.bone_map import dumps_map
        from .properties import read_rows

        target = _target(context, self.target)
        if target is None or target.type != "ARMATURE":
            return self.fail("select the armature whose bone map to save")
        bone_map = read_rows(target)
        try:
            Path(self.filepath).write_text(dumps_map(bone_map, target.manikin_retarget.rig or None), encoding="utf-8")
        except OSError as exc:
            return self.fail(f"{self.filepath}: cannot write ({exc.strerror or exc})")
        self.report({"INFO"}, f"Saved {len(bone_map)} bone pairs to {Path(self.filepath).name}")
        return {"FINISHED"}


classes = (MANIKIN_OT_add_retarget_rig, MANIKIN_OT_retarget, MANIKIN_OT_auto_fill_bone_map, MANIKIN_OT_load_bone_map,
           MANIKIN_OT_save_bone_map)  # fmt: skip
