"""Import Scenario and Export Scenario (File > Import / Export and the sidebar): a scenario TOML onto a manikin and
back. The work is :mod:`.read` and :mod:`.write`, loaded inside ``execute``; errors reach the user via report().
"""

from __future__ import annotations

from pathlib import Path

import bpy
from bpy.props import BoolProperty, StringProperty
from bpy_extras.io_utils import ExportHelper, ImportHelper

from ...solver.errors import ManikinError
from ..scene.schema import rig_of


class MANIKIN_OT_import_scenario(bpy.types.Operator, ImportHelper):
    """Load a scenario TOML: targets, loops, loads, obstacles, settings and start pose (onto the active manikin if it
    has the same body, else onto a new one)"""

    bl_idname = "manikin.import_scenario"
    bl_label = "Import Scenario"
    bl_options = {"REGISTER", "UNDO"}

    filename_ext = ".toml"
    filter_glob: StringProperty(default="*.toml", options={"HIDDEN"})
    replace: BoolProperty(
        name="Replace the previous scenario's obstacles and box", default=True,
        description="Remove the obstacles earlier scenario imports made in this scene, and the manikin's carried box, "
        "before importing (off: they stay, and obstacles of the same name are replaced)",
    )  # fmt: skip

    @classmethod
    def poll(cls, context: bpy.types.Context) -> bool:
        return context.mode == "OBJECT"

    def execute(self, context: bpy.types.Context) -> set[str]:
        from .read import import_scenario

        try:
            done = import_scenario(context, self.filepath, onto=rig_of(context.active_object), replace=self.replace)
        except ManikinError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        for warning in done.warnings:
            self.report({"WARNING"}, warning)
        frames = done.scenario.frames
        motion = f"; {done.keyed} keyed targets, frames {frames[0]}-{frames[-1]}" if done.keyed else ""
        motion += f"; {done.obstacles} obstacles" if done.obstacles else ""
        self.report({"INFO"}, f"Imported {Path(self.filepath).name} onto {done.arm.name}{motion}")
        return {"FINISHED"}


class MANIKIN_OT_export_scenario(bpy.types.Operator, ExportHelper):
    """Write the active manikin's targets, loops, loads, obstacles, settings (and pose) as a scenario TOML for the
    CLI; mesh obstacles go to OBJ files beside it"""

    bl_idname = "manikin.export_scenario"
    bl_label = "Export Scenario"

    filename_ext = ".toml"
    filter_glob: StringProperty(default="*.toml", options={"HIDDEN"})
    include_pose: BoolProperty(name="Include pose", default=True, description="Write the current pose as [start]")

    @classmethod
    def poll(cls, context: bpy.types.Context) -> bool:
        return rig_of(context.active_object) is not None

    def execute(self, context: bpy.types.Context) -> set[str]:
        from .write import export_scenario

        try:
            written = export_scenario(rig_of(context.active_object), self.filepath, pose=self.include_pose)
        except (ManikinError, OSError) as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        count = len(written) - 1
        meshes = f" and {count} mesh file{'s' if count > 1 else ''} beside it" if count else ""
        self.report({"INFO"}, f"Wrote {self.filepath}{meshes}")
        return {"FINISHED"}


def draw_import_menu(self: bpy.types.Menu, context: bpy.types.Context) -> None:
    self.layout.operator("manikin.import_scenario", text="Manikin Scenario (.toml)")


def draw_export_menu(self: bpy.types.Menu, context: bpy.types.Context) -> None:
    self.layout.operator("manikin.export_scenario", text="Manikin Scenario (.toml)")


MENUS = (("TOPBAR_MT_file_import", draw_import_menu), ("TOPBAR_MT_file_export", draw_export_menu))

classes = (MANIKIN_OT_import_scenario, MANIKIN_OT_export_scenario)
