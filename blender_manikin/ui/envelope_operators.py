"""Import a reach envelope (``python -m solver envelope``'s ``.obj`` or ``.glb``) as objects beside the manikin.

The file is read by :func:`solver.envelope.mesh_files.read_envelope` (numpy only, so it works in a Blender's own
Python) inside ``execute``; the objects are made by ``scene.envelope_objects``.
"""

from __future__ import annotations

from pathlib import Path

import bpy
from bpy.props import StringProperty
from bpy_extras.io_utils import ImportHelper

from ...solver.errors import ManikinError
from ..scene.schema import FILE_KEY, PRESET_KEY, rig_of


def _body_name(arm: bpy.types.Object) -> str:
    """The name a manikin's body has in an envelope file: its preset, or its body file's stem."""
    return arm.get(PRESET_KEY) or Path(arm.get(FILE_KEY, "")).stem


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
        from ...solver.envelope.mesh_files import read_envelope
        from ..scene.envelope_objects import add_envelope

        try:
            envelope = read_envelope(self.filepath)
        except ManikinError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        arm = rig_of(context.active_object)
        collection = arm.users_collection[0] if arm is not None else context.scene.collection
        made = add_envelope(collection, envelope, self.filepath, arm)
        manikin = envelope.info.get("manikin", "")
        if arm is not None and manikin and manikin != _body_name(arm):
            self.report({"WARNING"}, f"the envelope is {manikin}'s, placed on {arm.name} ({_body_name(arm)})")
        where = f"on {arm.name}" if arm is not None else "in the world (no manikin active)"
        names = ", ".join(ob.name for ob in made)
        self.report({"INFO"}, f"Imported {Path(self.filepath).name} {where}: {names}")
        return {"FINISHED"}


classes = (MANIKIN_OT_import_envelope,)
