"""Import Reach Envelope (File > Import and the sidebar): ``python -m solver envelope``'s ``.obj`` or ``.glb`` as
objects beside the manikin. The work is :func:`.objects.import_envelope`, loaded inside ``execute``."""

from __future__ import annotations

from pathlib import Path

import bpy
from bpy.props import StringProperty
from bpy_extras.io_utils import ImportHelper

from ...solver.errors import ManikinError
from ..scene.schema import rig_of


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

classes = (MANIKIN_OT_import_envelope,)
