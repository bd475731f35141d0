"""Operators: add a manikin, its targets, loops and loads; solve; reset. Errors reach the user via report().

The solver and the scene code load inside ``execute`` (as Blender's own importers do), so enabling the add-on
imports neither; Solve Pose and Reset Pose call :mod:`.solve`, as headless scripts do.
"""

from collections.abc import Callable

import bpy
from bpy.props import BoolVectorProperty, EnumProperty, FloatProperty, StringProperty

from ...solver.errors import ManikinError
from ...solver.options import AXES
from ...solver.presets import list_presets
from ..scene.schema import TCP_KEY, last_result, orphan_hint, rig_of

_LOCK_DESCRIPTION = "Constrained axes of the target frame: x y z (position), rx ry rz (rotation)"


def _preset_items() -> list[tuple[str, str, str]]:
    names = list_presets() or ["male_50"]
    return [(n, n.replace("_", " ").title(), f"The {n} preset from presets/manikins") for n in names]


def _active_rig(context: bpy.types.Context) -> bpy.types.Object | None:
    return rig_of(context.active_object)


def _mode_ok(cls: type, context: bpy.types.Context, modes: set[str]) -> bool:
    """In one of ``modes``; else say so where the button's tooltip (and a script's error) shows it."""
    if context.mode in modes:
        return True
    wanted = " or ".join(m.title() for m in sorted(modes, reverse=True))
    mode = context.mode.replace("_", " ").title()
    cls.poll_message_set(f"Not in {mode} mode: switch to {wanted} mode first (Tab, or the mode menu)")
    return False


def _select_only(context: bpy.types.Context, ob: bpy.types.Object) -> None:
    for other in context.view_layer.objects.selected:
        other.select_set(False)
    if ob.name in context.view_layer.objects:
        ob.select_set(True)
        context.view_layer.objects.active = ob


class _RigOperator(bpy.types.Operator):
    """Base: needs a manikin (the active armature, or the active target/TCP empty's armature)."""

    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context: bpy.types.Context) -> bool:
        if _active_rig(context) is None:
            cls.poll_message_set(orphan_hint(context.active_object) or "Select a manikin, or one of its targets")
            return False
        return _mode_ok(cls, context, {"OBJECT", "POSE"})

    def add_empty(self, context: bpy.types.Context, add: Callable[[], bpy.types.Object]) -> set[str]:
        """Run ``add`` (a scene call making a target, loop or load empty) and select what it made; an error is
        reported, not raised."""
        try:
            ob = add()
        except ManikinError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        _select_only(context, ob)
        return {"FINISHED"}


class MANIKIN_OT_add_manikin(bpy.types.Operator):
    """Add a manikin: an armature with the solver's joints, a body, TCP empties and both feet on the floor"""

    bl_idname = "manikin.add_manikin"
    bl_label = "Add Manikin"
    bl_options = {"REGISTER", "UNDO"}

    preset: EnumProperty(name="Preset", items=_preset_items())
    # SKIP_SAVE: a body file given once must not override the preset of every later Add > Manikin
    filepath: StringProperty(name="Body file", subtype="FILE_PATH", description="A body TOML file (overrides preset)",
                             options={"SKIP_SAVE"})  # fmt: skip

    @classmethod
    def poll(cls, context: bpy.types.Context) -> bool:
        return _mode_ok(cls, context, {"OBJECT"})

    def execute(self, context: bpy.types.Context) -> set[str]:
        from ..scene import armature, targets

        preset, file = ("", self.filepath) if self.filepath else (self.preset, "")
        try:
            model = armature.load_model(preset, file)
            arm = armature.create_manikin(context, model, preset, file)
            targets.add_default_supports(arm)
        except ManikinError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        _select_only(context, arm)
        self.report({"INFO"}, f"Added {arm.name}: {model.n} joints, {len(arm.data.bones)} bones")
        return {"FINISHED"}


class MANIKIN_OT_add_target(_RigOperator):
    """Add a target empty for a TCP where the TCP is now (or snap its existing target back to it)"""

    bl_idname = "manikin.add_target"
    bl_label = "Add Target"

    tcp: StringProperty(name="TCP", default="hand_r", description="TCP name, e.g. hand_r, foot_l, head")
    lock: BoolVectorProperty(name="Locked axes", size=6, default=(True,) * 6, description=_LOCK_DESCRIPTION)
    support: bpy.props.BoolProperty(name="Support", description="Contact forces act at this target")

    def invoke(self, context: bpy.types.Context, event: bpy.types.Event) -> set[str]:
        ob = context.active_object  # a selected TCP empty (or target) says which TCP
        if ob is not None and TCP_KEY in ob:
            self.tcp = ob[TCP_KEY]
        elif ob is not None and ob.manikin_target.role == "TARGET":
            self.tcp = ob.manikin_target.tcp
        return self.execute(context)

    def execute(self, context: bpy.types.Context) -> set[str]:
        from ..scene import targets

        lock = tuple(a for a, on in zip(AXES, self.lock, strict=True) if on)
        return self.add_empty(
            context,
            lambda: targets.add_target(_active_rig(context), self.tcp, lock=lock, support=self.support, follow=True),
        )


class MANIKIN_OT_add_loop(_RigOperator):
    """Hold a TCP at its current offset from another TCP (e.g. two hands on one box)"""

    bl_idname = "manikin.add_loop"
    bl_label = "Add Loop"

    tcp: StringProperty(name="TCP", default="hand_l")
    other: StringProperty(name="Other TCP", default="hand_r")
    lock: BoolVectorProperty(
        name="Locked axes", size=6, default=(True, True, True, False, False, False), description=_LOCK_DESCRIPTION
    )

    def execute(self, context: bpy.types.Context) -> set[str]:
        from ..scene import targets

        lock = tuple(a for a, on in zip(AXES, self.lock, strict=True) if on)
        return self.add_empty(context, lambda: targets.add_loop(_active_rig(context), self.tcp, self.other, lock=lock))


class MANIKIN_OT_add_load(_RigOperator):
    """Hang a carried mass at a TCP (its weight acts there, straight down)"""

    bl_idname = "manikin.add_load"
    bl_label = "Add Load"

    tcp: StringProperty(name="TCP", default="hand_r")
    # soft_min, not min: a hard min would clamp -3 kg to 0 silently; add_load rejects it in one line instead
    mass: FloatProperty(name="Mass", default=5.0, soft_min=0.0, soft_max=50.0, unit="MASS", description="kg")

    def execute(self, context: bpy.types.Context) -> set[str]:
        from ..scene import targets

        return self.add_empty(context, lambda: targets.add_load(_active_rig(context), self.tcp, self.mass))


class MANIKIN_OT_solve_pose(_RigOperator):
    """Solve the manikin's pose for its targets, loops and loads, starting from the current pose"""

    bl_idname = "manikin.solve_pose"
    bl_label = "Solve Pose"

    def execute(self, context: bpy.types.Context) -> set[str]:
        from ..scene.supports import moved_text
        from .solve import kernels_note, solve_pose

        arm = _active_rig(context)
        try:
            result = solve_pose(arm)
        except ManikinError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        data = last_result(arm) or {}
        said = data.get("step_lines", []) + moved_text(data.get("moved", {})) + data.get("notes", [])  # steps, slid
        # feet and hints, with units
        said += [note] if (note := kernels_note()) else []  # NumPy kernels (Numba missing or off): said once
        tail = "".join(f"; {line}" for line in said)
        if result.converged:
            self.report({"INFO"}, f"Converged in {result.iterations} iterations ({result.time_s * 1e3:.0f} ms){tail}")
        else:
            self.report({"WARNING"}, "Not converged: " + result.verdict() + tail)
        return {"FINISHED"}


class MANIKIN_OT_reset_pose(_RigOperator):
    """Put the manikin back in the zero pose (standing upright, arms hanging)"""

    bl_idname = "manikin.reset_pose"
    bl_label = "Reset Pose"

    def execute(self, context: bpy.types.Context) -> set[str]:
        from .solve import reset_pose

        try:
            reset_pose(_active_rig(context))
        except ManikinError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        return {"FINISHED"}


classes = (
    MANIKIN_OT_add_manikin,
    MANIKIN_OT_add_target,
    MANIKIN_OT_add_loop,
    MANIKIN_OT_add_load,
    MANIKIN_OT_solve_pose,
    MANIKIN_OT_reset_pose,
)
