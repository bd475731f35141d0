"""The sidebar's "Population Study" panel: a study of the active manikin's targets for a manikin family, run in the
background (``study_operators``), its progress and its results table.

The settings and the rows of the last study live on the scene (``Scene.manikin_study``), so the table stays with
the .blend; the progress of a running study comes from the job itself. Imports only bpy and light solver modules.
"""

from __future__ import annotations

import bpy
from bpy.props import BoolProperty, CollectionProperty, EnumProperty, IntProperty, StringProperty

from ..scene.schema import rig_of
from . import study_operators
from .study_operators import FAMILIES, FOLDER

VARY = (
    ("NONE", "Nothing", "Every member on the targets as they are"),
    ("z", "Target height", "Add each value (m) to the height of the chosen targets"),
    ("x", "Target x", "Add each value (m) to the x of the chosen targets (armature space)"),
    ("y", "Target y", "Add each value (m) to the y of the chosen targets (armature space; the manikin faces -y)"),
)
HEADER = ("Manikin", "Role", "Values", "RULA", "REBA", "L4/L5 N", "Short mm")
SHOWN_ROWS = 6


def family_items() -> list[tuple[str, str, str]]:
    """The shipped families (presets/families/NAME with a family.toml), then "a folder of your own"."""
    names = sorted(p.name for p in FAMILIES.iterdir() if (p / "family.toml").is_file()) if FAMILIES.is_dir() else []
    shipped = [(n, n, f"The shipped family presets/families/{n}") for n in names]
    return shipped + [(FOLDER, "Folder...", "A family folder written by `python -m solver family`")]


class MANIKIN_PG_study_row(bpy.types.PropertyGroup):
    """One run of the last study, as the table shows it (``name``: the manikin, for the list's filter)."""

    run_id: StringProperty(name="Run id")
    role: StringProperty(name="Role")
    parameters: StringProperty(name="Parameters")
    status: StringProperty(name="Status")
    converged: BoolProperty(name="Converged")
    rula: StringProperty(name="RULA")
    reba: StringProperty(name="REBA")
    l4_l5: StringProperty(name="L4/L5 compression (N)")
    shortfall: StringProperty(name="Shortfall (mm)")


class MANIKIN_PG_study(bpy.types.PropertyGroup):
    """What to study, where, and the last study's rows."""

    family: EnumProperty(name="Family", items=family_items(), description="The manikins of the study")
    family_folder: StringProperty(name="Folder", subtype="DIR_PATH", description="A folder of `solver family`")
    vary: EnumProperty(name="Vary", items=VARY, default="NONE", description="One parameter the study varies")
    tcps: StringProperty(name="Targets", default="hand_r", description="TCP names of the targets moved (spaces)")
    values: StringProperty(name="Values", default="-0.1, 0, 0.1", description="Offsets in m, separated by commas")
    workers: IntProperty(name="Workers", default=0, min=0, max=256, description="Processes (0: all cores but one)")
    folder: StringProperty(
        name="Output", subtype="DIR_PATH",
        description="Where studies go (empty: manikin_studies beside the .blend, or in the temporary folder)",
    )  # fmt: skip
    status: StringProperty(name="Status", description="How the last study ended")
    study_file: StringProperty(name="Study file", description="The study the rows come from")
    source: StringProperty(name="Manikin", description="The armature whose targets the study ran on")
    rows: CollectionProperty(type=MANIKIN_PG_study_row)
    row_index: IntProperty(name="Row", default=0, min=0)


class MANIKIN_UL_study_rows(bpy.types.UIList):
    """The results table: a row per run."""

    def draw_item(self, context, layout, data, item, icon, active_data, active_propname, index=0) -> None:
        row = layout.row(align=True)
        row.label(text=item.name.rpartition("/")[2], icon="CHECKMARK" if item.converged else "X")
        for text in (item.role, item.parameters, item.rula, item.reba, item.l4_l5, item.shortfall):
            row.label(text=text)


class MANIKIN_PT_study(bpy.types.Panel):
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Manikin"
    bl_label = "Population Study"
    bl_parent_id = "MANIKIN_PT_main"
    bl_options = {"DEFAULT_CLOSED"}

    @classmethod
    def poll(cls, context: bpy.types.Context) -> bool:
        study = getattr(context.scene, "manikin_study", None)
        return study is not None and (rig_of(context.active_object) is not None or len(study.rows) > 0)

    def draw(self, context: bpy.types.Context) -> None:
        s = context.scene.manikin_study
        layout = self.layout
        col = layout.column()
        col.use_property_split = True
        col.prop(s, "family")
        if s.family == FOLDER:
            col.prop(s, "family_folder")
        col.prop(s, "vary")
        if s.vary != "NONE":
            col.prop(s, "tcps")
            col.prop(s, "values")
        col.prop(s, "workers")
        col.prop(s, "folder")
        job = study_operators.current_job()
        row = layout.row(align=True)
        row.scale_y = 1.3
        if job is not None and job.state in ("running", "cancelling"):
            row.operator("manikin.study_cancel", icon="CANCEL")
            layout.label(text=job.line(), icon="TIME")
            return
        row.operator("manikin.study_run", icon="COMMUNITY")
        if s.status:
            layout.label(text=s.status, icon="ERROR" if s.status.startswith("Study failed") else "INFO")
        if len(s.rows):
            head = layout.row(align=True)
            for text in HEADER:
                head.label(text=text)
            layout.template_list("MANIKIN_UL_study_rows", "", s, "rows", s, "row_index", rows=SHOWN_ROWS)
            layout.operator("manikin.study_load_row", icon="ARMATURE_DATA")


classes = (MANIKIN_PG_study_row, MANIKIN_PG_study, *study_operators.classes, MANIKIN_UL_study_rows, MANIKIN_PT_study)


def attach() -> None:
    """Give every scene the study settings (the classes registered first)."""
    bpy.types.Scene.manikin_study = bpy.props.PointerProperty(type=MANIKIN_PG_study)


def detach() -> None:
    """Stop a running study (its journal keeps the finished rows) and remove what :func:`attach` added."""
    study_operators.stop_job()
    del bpy.types.Scene.manikin_study
