"""The sidebar's "Population Study" panel: a study of the active manikin's targets for a manikin family, run in the
background (:mod:`.control`), its progress and its results table (the rows stored in ``Scene.manikin_study``, the
progress of a running study from the job itself). Imports only bpy and light solver modules."""

from __future__ import annotations

import bpy

from ..scene.help import draw_help
from ..scene.schema import rig_of
from . import control
from .properties import FOLDER
from .table import header, split

SHOWN_ROWS = 6


class MANIKIN_UL_study_rows(bpy.types.UIList):
    """The results table: a row per run."""

    def draw_item(self, context, layout, data, item, icon, active_data, active_propname, index=0) -> None:
        row = layout.row(align=True)
        row.label(text=item.name.rpartition("/")[2], icon="CHECKMARK" if item.converged else "X")
        for text in (item.role, item.parameters, *split(item.scores), item.l4_l5, item.shortfall):
            row.label(text=text)


class MANIKIN_PT_study(bpy.types.Panel):
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Manikin"
    bl_label = "Population Study"
    bl_parent_id = "MANIKIN_PT_main"
    bl_order = 7  # the places of the subpanels: pose/panels.py
    bl_options = {"DEFAULT_CLOSED"}
    draw_header_preset = draw_help  # the help button (scene/help.py)

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
        job = control.current_job()
        row = layout.row(align=True)
        row.scale_y = 1.3
        if control.is_running():
            row.operator("manikin.study_cancel", icon="CANCEL")
            layout.label(text=job.line(), icon="TIME")
            return
        row.operator("manikin.study_run", icon="COMMUNITY")
        if s.status:
            layout.label(text=s.status, icon="ERROR" if s.status.startswith("Study failed") else "INFO")
        if len(s.rows):
            head = layout.row(align=True)
            for text in header(s.score_titles):
                head.label(text=text)
            layout.template_list("MANIKIN_UL_study_rows", "", s, "rows", s, "row_index", rows=SHOWN_ROWS)
            layout.operator("manikin.study_load_row", icon="ARMATURE_DATA")


classes = (MANIKIN_UL_study_rows, MANIKIN_PT_study)
