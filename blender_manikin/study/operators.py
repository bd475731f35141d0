"""Operators of the "Population Study" panel: run a study of the active manikin's targets for a family in the
background, cancel it, and load one row's manikin and pose into the scene. The work is :mod:`.control`'s; errors
reach the user via report().
"""

from __future__ import annotations

import bpy

from ...solver.errors import ManikinError
from ..scene.schema import rig_of
from ..scene.watch import CancelJob
from . import control


class MANIKIN_OT_study_run(bpy.types.Operator):
    """Run a study of this manikin's targets for every member of the family (and each value of the parameter) in
    the background; the table fills when it ends"""

    bl_idname = "manikin.study_run"
    bl_label = "Run Study"

    @classmethod
    def poll(cls, context: bpy.types.Context) -> bool:
        if control.is_running():
            cls.poll_message_set("A study is running")
            return False
        return rig_of(context.active_object) is not None

    def execute(self, context: bpy.types.Context) -> set[str]:
        try:
            job, folder = control.start_study(context.scene, rig_of(context.active_object))
        except (ManikinError, OSError) as exc:
            self.report({"ERROR"}, " ".join(str(exc).split()))
            return {"CANCELLED"}
        kept = f", {job.kept} done before" if job.kept else ""
        self.report({"INFO"}, f"Study started: {job.total} runs{kept} in {folder}")
        return {"FINISHED"}


class MANIKIN_OT_study_cancel(CancelJob, bpy.types.Operator):
    """Stop the running study; the finished runs are kept, and Run Study goes on from them"""

    bl_idname = "manikin.study_cancel"
    bl_label = "Cancel Study"
    watch = control.WATCH
    stopping = "Stopping the study: {job.done} of {job.total} runs done"


class MANIKIN_OT_study_load_row(bpy.types.Operator):
    """Put the selected row's manikin into the scene where the study's manikin stands, in the row's pose"""

    bl_idname = "manikin.study_load_row"
    bl_label = "Load Row"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context: bpy.types.Context) -> bool:
        settings = getattr(context.scene, "manikin_study", None)
        return context.mode == "OBJECT" and settings is not None and 0 <= settings.row_index < len(settings.rows)

    def execute(self, context: bpy.types.Context) -> set[str]:
        settings = context.scene.manikin_study
        item = settings.rows[settings.row_index]
        try:
            _, result = control.load_row(context, settings, item.run_id)
        except (ManikinError, OSError) as exc:
            self.report({"ERROR"}, " ".join(str(exc).split()))
            return {"CANCELLED"}
        state = "converged" if result.converged else "NOT converged: " + result.verdict()
        self.report({"INFO"} if result.converged else {"WARNING"}, f"{item.name} {item.parameters}: {state}")
        return {"FINISHED"}


classes = (MANIKIN_OT_study_run, MANIKIN_OT_study_cancel, MANIKIN_OT_study_load_row)


def unregister() -> None:
    """Add-on disabled: stop a running study (its journal keeps the finished rows) and stop watching it."""
    control.stop_job()
