"""Import Reach Envelope (File > Import and the sidebar): ``python -m solver envelope``'s ``.obj`` or ``.glb`` as
objects beside the manikin; and the "Reach Envelope" panel's Compute Envelope and Cancel Envelope, which run that
command in the background for the active manikin and import its result. The work is :mod:`.objects`' and
:mod:`.control`'s, loaded inside ``execute``; errors reach the user via report()."""

from __future__ import annotations

from pathlib import Path

import bpy
from bpy.props import StringProperty
from bpy_extras.io_utils import ImportHelper

from ...solver.errors import ManikinError
from ..scene.schema import rig_of
from ..scene.watch import CancelJob
from . import control


class MANIKIN_OT_import_envelope(bpy.types.Operator, ImportHelper):
    """Load a reach envelope (.obj or .glb from python -m solver envelope) as objects centred on the shoulder,
    parented to the active manikin (or in the world when none is active)"""

    bl_idname = "manikin.import_envelope"
    bl_label = "Import Reach Envelope"
    bl_options = {"REGISTER", "UNDO"}

    filter_glob: StringProperty(default="*.obj;*.glb", options={"HIDDEN"})

    @classmethod
    def poll(cls, context: bpy.types.Context) -> bool:
        return context.mode == "OBJECT"

    def execute(self, context: bpy.types.Context) -> set[str]:
        from .objects import import_envelope

        arm = rig_of(context.active_object)
        try:
            made, warning = import_envelope(context, self.filepath, arm)
        except ManikinError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        if warning:
            self.report({"WARNING"}, warning)
        where = f"on {arm.name}" if arm is not None else "in the world (no manikin active)"
        names = ", ".join(ob.name for ob in made)
        self.report({"INFO"}, f"Imported {Path(self.filepath).name} {where}: {names}")
        return {"FINISHED"}


def draw_import_menu(self: bpy.types.Menu, context: bpy.types.Context) -> None:
    self.layout.operator("manikin.import_envelope", text="Manikin Reach Envelope (.obj, .glb)")


MENUS = (("TOPBAR_MT_file_import", draw_import_menu),)


class MANIKIN_OT_envelope_compute(bpy.types.Operator):
    """Compute the active manikin's reach envelope with these settings in the background, then import it onto the
    manikin (the same body and settings again import the envelope computed before)"""

    bl_idname = "manikin.envelope_compute"
    bl_label = "Compute Envelope"

    @classmethod
    def poll(cls, context: bpy.types.Context) -> bool:
        if control.is_running():
            cls.poll_message_set("An envelope is being computed")
            return False
        return context.mode == "OBJECT" and rig_of(context.active_object) is not None

    def execute(self, context: bpy.types.Context) -> set[str]:
        arm = rig_of(context.active_object)
        try:
            job, folder = control.start_envelope(context.scene, arm)
        except (ManikinError, OSError) as exc:
            self.report({"ERROR"}, " ".join(str(exc).split()))
            return {"CANCELLED"}
        if job is None:
            self.report({"INFO"}, context.scene.manikin_envelope.status)
        else:
            self.report({"INFO"}, f"Envelope of {arm.name} started: {job.total} directions, into {folder}")
        return {"FINISHED"}


class MANIKIN_OT_envelope_cancel(CancelJob, bpy.types.Operator):
    """Stop computing the envelope (nothing is imported)"""

    bl_idname = "manikin.envelope_cancel"
    bl_label = "Cancel Envelope"
    watch = control.WATCH
    stopping = "Stopping the envelope: {job.done} of {job.total} directions done"


classes = (MANIKIN_OT_import_envelope, MANIKIN_OT_envelope_compute, MANIKIN_OT_envelope_cancel)


def unregister() -> None:
    """Add-on disabled: stop a running envelope and stop watching it."""
    control.stop_job()
