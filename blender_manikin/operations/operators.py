"""Operators of the "Operations" panel: propose an object's grasps, edit the operation list (add, remove, move) and
Generate Motion (in the background, cancellable). The work is :mod:`.control`'s; errors reach the user via
report(), one line naming the operation."""

from __future__ import annotations

from pathlib import Path

import bpy
from bpy.props import EnumProperty, StringProperty
from bpy_extras.io_utils import ImportHelper

from ...solver.errors import ManikinError
from ..scene.schema import rig_of
from ..scene.watch import CancelJob
from . import control
from .properties import is_work_object


def _settings(context: bpy.types.Context):
    return getattr(context.scene, "manikin_operations", None)


class MANIKIN_OT_propose_grasps(bpy.types.Operator):
    """Make the solver's proposed grasp of this object (both palms on its side faces, at mid height) as child empties
    grasp_r and grasp_l, for you to move"""

    bl_idname = "manikin.propose_grasps"
    bl_label = "Propose Grasps"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context: bpy.types.Context) -> bool:
        if not is_work_object(context.active_object):
            cls.poll_message_set("Select a mesh marked as an object (Operations panel)")
            return False
        return context.mode == "OBJECT"

    def execute(self, context: bpy.types.Context) -> set[str]:
        from .objects import propose_grasps

        ob = context.active_object
        try:
            made = propose_grasps(ob)
        except ManikinError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        self.report({"INFO"}, f"{ob.name}: proposed grasp {' and '.join(e.name for e in made)} (its side faces)")
        return {"FINISHED"}


class MANIKIN_OT_operation_add(bpy.types.Operator):
    """Add an operation after the selected one: after a Get, a Place of the same object; else a Get of the selected
    object (or a Wait when there is none)"""

    bl_idname = "manikin.operation_add"
    bl_label = "Add Operation"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context: bpy.types.Context) -> set[str]:
        s = _settings(context)
        items = s.items
        before = items[s.index] if 0 <= s.index < len(items) else None
        item = items.add()
        active = context.active_object
        if before is not None and before.do == "GET" and before.object is not None:
            item.do, item.object = "PLACE", before.object
        elif is_work_object(active):
            item.do, item.object = "GET", active
        else:
            item.do = "WAIT"
        at = s.index + 1 if before is not None else len(items) - 1
        items.move(len(items) - 1, at)
        s.index = at
        return {"FINISHED"}


class MANIKIN_OT_operation_remove(bpy.types.Operator):
    """Remove the selected operation"""

    bl_idname = "manikin.operation_remove"
    bl_label = "Remove Operation"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context: bpy.types.Context) -> bool:
        s = _settings(context)
        return s is not None and 0 <= s.index < len(s.items)

    def execute(self, context: bpy.types.Context) -> set[str]:
        s = _settings(context)
        s.items.remove(s.index)
        s.index = max(0, min(s.index, len(s.items) - 1))
        return {"FINISHED"}


class MANIKIN_OT_operation_move(bpy.types.Operator):
    """Move the selected operation up or down the list"""

    bl_idname = "manikin.operation_move"
    bl_label = "Move Operation"
    bl_options = {"REGISTER", "UNDO"}

    direction: EnumProperty(items=(("UP", "Up", "Earlier"), ("DOWN", "Down", "Later")), options={"SKIP_SAVE"})

    @classmethod
    def poll(cls, context: bpy.types.Context) -> bool:
        s = _settings(context)
        return s is not None and 0 <= s.index < len(s.items)

    def execute(self, context: bpy.types.Context) -> set[str]:
        s = _settings(context)
        to = s.index + (-1 if self.direction == "UP" else 1)
        if not 0 <= to < len(s.items):
            return {"CANCELLED"}
        s.items.move(s.index, to)
        s.index = to
        return {"FINISHED"}


class MANIKIN_OT_operations_generate(bpy.types.Operator):
    """Plan the operations (steps, ways, MTM-1 timing), solve every frame in the background (balance, obstacles)
    and key the manikin and the objects from the scene's start frame"""

    bl_idname = "manikin.operations_generate"
    bl_label = "Generate Motion"

    @classmethod
    def poll(cls, context: bpy.types.Context) -> bool:
        if control.is_running():
            cls.poll_message_set("A motion is being generated")
            return False
        if control.manikin_for(context) is None:
            cls.poll_message_set("Select a manikin, or one of its targets")
            return False
        s = _settings(context)
        return s is not None and len(s.items) > 0 and context.mode == "OBJECT"

    def execute(self, context: bpy.types.Context) -> set[str]:
        arm = control.manikin_for(context)
        try:
            job = control.start_generate(context.scene, arm)
        except (ManikinError, OSError) as exc:
            self.report({"ERROR"}, " ".join(str(exc).split()))
            return {"CANCELLED"}
        planned = job.plan[0]
        self.report({"INFO"}, f"Generating {job.total} frames ({len(planned.plan.spans)} operations, cycle time "
                              f"{planned.plan.duration:.2f} s) in the background")  # fmt: skip
        return {"FINISHED"}


class MANIKIN_OT_operations_cancel(CancelJob, bpy.types.Operator):
    """Stop generating the motion (nothing is keyed)"""

    bl_idname = "manikin.operations_cancel"
    bl_label = "Cancel"
    watch = control.WATCH
    stopping = "Stopping: {job.done} of {job.total} frames solved; nothing will be keyed"


class MANIKIN_OT_import_operations(bpy.types.Operator, ImportHelper):
    """Load a scenario with [[objects]] and [[operations]] (presets/operations/): the manikin, its supports and
    obstacles, the objects with their grasps and the operation list with its target empties"""

    bl_idname = "manikin.import_operations"
    bl_label = "Import Operations"
    bl_options = {"REGISTER", "UNDO"}

    filename_ext = ".toml"
    filter_glob: StringProperty(default="*.toml", options={"HIDDEN"})

    @classmethod
    def poll(cls, context: bpy.types.Context) -> bool:
        return context.mode == "OBJECT" and not control.is_running()

    def execute(self, context: bpy.types.Context) -> set[str]:
        from .importing import import_operations

        try:
            arm, objects, operations, warnings = import_operations(context, self.filepath,
                                                                   rig_of(context.active_object))  # fmt: skip
        except (ManikinError, OSError) as exc:
            self.report({"ERROR"}, " ".join(str(exc).split()))
            return {"CANCELLED"}
        for warning in warnings:
            self.report({"WARNING"}, warning)
        self.report({"INFO"}, f"Imported {Path(self.filepath).name} onto {arm.name}: {len(objects)} objects, "
                              f"{len(operations)} operations")  # fmt: skip
        return {"FINISHED"}


def draw_import_menu(self: bpy.types.Menu, context: bpy.types.Context) -> None:
    self.layout.operator("manikin.import_operations", text="Manikin Operations (.toml)")


MENUS = (("TOPBAR_MT_file_import", draw_import_menu),)

classes = (MANIKIN_OT_propose_grasps, MANIKIN_OT_import_operations, MANIKIN_OT_operation_add,
           MANIKIN_OT_operation_remove, MANIKIN_OT_operation_move, MANIKIN_OT_operations_generate,
           MANIKIN_OT_operations_cancel)  # fmt: skip


def unregister() -> None:
    """Add-on disabled: stop a running generation and stop watching it."""
    control.stop_job()
