"""The Job panel (under Motion in the Manikin sidebar tab): the job around the baked motion and its verdicts.

The user sets what the job adds to one cycle's motion (cycle time, cycles per shift, shift length, lifts per cycle,
the load and the hands holding it: by default the loads the hands held when baked). Assess Job rates the last bake
with every method of :mod:`solver.job.registry` exactly as ``manikin job`` does (:mod:`.job_assess`); the panel shows
one row per method (its verdict line, coloured by its severity) with a button per frame that drives it (Go to Frame).
Write Report writes the job command's one-file HTML through a file browser, put in place as every output of ours
(temporary file, checked, renamed); Blender's Python has no matplotlib, so it has no plots there and says so.
The verdicts are stored on the armature (``JOB_KEY``) with the bake they rate: a later bake marks them out of date.
"""

from __future__ import annotations

import json
import textwrap
import zlib

import bpy
from bpy.props import EnumProperty, FloatProperty, IntProperty, PointerProperty, StringProperty

from ...solver.errors import ManikinError
from ..pose.panels import draw_verdict
from ..scene.help import draw_help
from ..scene.schema import FRAMES_KEY, JOB_KEY, baked_frame, rig_of

HANDS_ITEMS = (
    ("both", "Both", "The load is held in both hands"),
    ("right", "Right", "The load is held in the right hand"),
    ("left", "Left", "The load is held in the left hand"),
)
LOAD_ITEMS = (
    ("SCENE", "From Bake", "The loads the hands held in the baked motion (Add Load, or a scenario's loads)"),
    ("SET", "Set", "The load mass and hands set here"),
)
WRAP = 56  # characters of a verdict line per label: the sidebar cuts longer labels


class MANIKIN_PG_job(bpy.types.PropertyGroup):
    """The job around a manikin's baked motion (one work cycle), as the job file's [work] and [load] tables."""

    cycle_time: FloatProperty(name="Cycle Time (s)", default=30.0, min=0.0, soft_max=3600.0,
                              description="s, one work cycle: the motion and the time around it")  # fmt: skip
    repetitions: IntProperty(name="Cycles per Shift", default=800, min=0, soft_max=10000,
                             description="Work cycles in one shift (0 allowed)")  # fmt: skip
    shift: FloatProperty(name="Shift (h)", default=8.0, min=0.0, max=24.0, description="Shift length, h")
    lifts_per_cycle: IntProperty(name="Lifts per Cycle", default=1, min=0, max=1000,
                                 description="Lifts of the load in one cycle")  # fmt: skip
    load_source: EnumProperty(name="Load", items=LOAD_ITEMS, default="SCENE",
                              description="Where the load lifted comes from")  # fmt: skip
    load_mass: FloatProperty(name="Load (kg)", default=10.0, min=0.0, soft_max=50.0, description="The load lifted, kg")
    hands: EnumProperty(name="Hands", items=HANDS_ITEMS, default="both", description="The hands holding the load")


def bake_stamp(arm: bpy.types.Object) -> int | None:
    """The checksum of the last bake's stored head (None: no bake stored): what the stored verdicts rated."""
    group = arm.get(FRAMES_KEY)
    head = group.get("head") if hasattr(group, "get") else None
    return zlib.crc32(head.encode()) if isinstance(head, str) else None


def baked_entries(arm: bpy.types.Object) -> list[dict]:
    """Every baked frame's stored entry (the poses the job is rated from), in frame order."""
    group = arm.get(FRAMES_KEY)
    keys = [k for k in group.keys() if k != "head"] if hasattr(group, "keys") else []
    return [e for k in sorted(keys, key=int) if (e := baked_frame(arm, k)) is not None]


def work_of(arm: bpy.types.Object, entries: list[dict]):
    """The panel's inputs as a :class:`.job_assess.Work` (the load from the bake when so chosen)."""
    from .job_assess import Work, scene_load, stored_poses

    s = arm.manikin_job
    mass, hands = s.load_mass, s.hands
    if s.load_source == "SCENE":
        mass, hands = scene_load(stored_poses(entries)) or (0.0, "both")
    return Work(s.cycle_time, s.repetitions, s.shift, s.lifts_per_cycle, mass, hands)


def assess(context: bpy.types.Context, arm: bpy.types.Object) -> tuple[dict, list]:
    """Rate the last bake of ``arm`` (one ManikinError line on bad input) and store the verdicts on it."""
    from ..scene.armature import model_of
    from .job_assess import assess as rate
    from .job_assess import verdict_rows

    entries = baked_entries(arm)
    if not entries:
        raise ManikinError(f"{arm.name} has no baked motion: bake the motion first (Motion > Bake Motion)")
    render = context.scene.render
    blend = bpy.path.basename(bpy.data.filepath) or "an unsaved .blend"
    where = f"{arm.name}, baked frames {entries[0]['frame']}-{entries[-1]['frame']} in {blend}"
    work = work_of(arm, entries)
    report, frames = rate(entries, model_of(arm), work, arm.name, render.fps / render.fps_base, where)
    arm[JOB_KEY] = json.dumps(dict(rows=verdict_rows(report), bake=bake_stamp(arm), load_kg=work.load_mass,
                                   hands=work.hands, motion_s=report["motion_time_s"]))  # fmt: skip
    return report, frames


class MANIKIN_OT_assess_job(bpy.types.Operator):
    """Rate the baked motion as a job (cycle time, cycles per shift, load) with every job method: LiFFT, The
    Shoulder Tool, time at each RULA/REBA/OWAS level, ..."""

    bl_idname = "manikin.assess_job"
    bl_label = "Assess Job"
    bl_options = {"REGISTER"}

    @classmethod
    def poll(cls, context: bpy.types.Context) -> bool:
        if rig_of(context.active_object) is None:
            cls.poll_message_set("Select a manikin, or one of its targets")
            return False
        return True

    def execute(self, context: bpy.types.Context) -> set[str]:
        arm = rig_of(context.active_object)
        try:
            report, _ = assess(context, arm)
        except ManikinError as exc:
            self.report({"ERROR"}, f"Assess Job: {exc}")
            return {"CANCELLED"}
        worst = max((v["severity"] for v in report["verdicts"].values() if v["severity"] is not None), default=None)
        word = {0: "green", 1: "yellow", 2: "red"}.get(worst, "not rated")
        self.report({"INFO"}, f"Assessed {arm.name}'s job: {len(report['verdicts'])} methods, worst {word}")
        return {"FINISHED"}


class MANIKIN_OT_write_job_report(bpy.types.Operator):
    """Assess the job and write its one-file HTML report (verdicts, tables, sources; readable offline)"""

    bl_idname = "manikin.write_job_report"
    bl_label = "Write Report"
    bl_options = {"REGISTER"}

    filepath: StringProperty(name="File", subtype="FILE_PATH", description="The HTML file to write",
                             options={"SKIP_SAVE"})  # fmt: skip
    filter_glob: StringProperty(default="*.html;*.htm", options={"HIDDEN"})
    check_existing: bpy.props.BoolProperty(default=True, options={"HIDDEN"})

    poll = MANIKIN_OT_assess_job.poll

    def invoke(self, context: bpy.types.Context, event: bpy.types.Event) -> set[str]:
        if not self.filepath:
            self.filepath = f"//{bpy.path.clean_name(rig_of(context.active_object).name)}_job.html"
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}

    def execute(self, context: bpy.types.Context) -> set[str]:
        from .job_assess import has_matplotlib, html_of
        from .written import written_by_path

        arm = rig_of(context.active_object)
        if not self.filepath:
            self.report({"ERROR"}, "Write Report: no file chosen")
            return {"CANCELLED"}
        path = bpy.path.abspath(self.filepath)
        path = path if path.lower().endswith((".html", ".htm")) else path + ".html"
        try:
            report, frames = assess(context, arm)
            text = html_of(report, frames)
            with written_by_path(path) as work, open(work, "w", encoding="utf-8") as out:
                out.write(text)
        except ManikinError as exc:
            self.report({"ERROR"}, f"Write Report: {exc}")
            return {"CANCELLED"}
        plots = "" if has_matplotlib() else " (no plots: Blender's Python has no matplotlib)"
        self.report({"INFO"}, f"Wrote the job report of {arm.name} to {path}{plots}")
        return {"FINISHED"}


class MANIKIN_PT_job(bpy.types.Panel):
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Manikin"
    draw_header_preset = draw_help  # the help button (scene/help.py)
    bl_label = "Job"
    bl_parent_id = "MANIKIN_PT_motion"

    @classmethod
    def poll(cls, context: bpy.types.Context) -> bool:
        return rig_of(context.active_object) is not None

    def draw(self, context: bpy.types.Context) -> None:
        arm = rig_of(context.active_object)
        s, layout = arm.manikin_job, self.layout
        col = layout.column(align=True)
        for name in ("cycle_time", "repetitions", "shift", "lifts_per_cycle"):
            col.prop(s, name)
        layout.prop(s, "load_source", expand=True)
        if s.load_source == "SET":
            layout.prop(s, "load_mass")
            layout.prop(s, "hands", expand=True)
        else:
            layout.label(text=_bake_load(arm), icon="INFO")
        layout.operator(MANIKIN_OT_assess_job.bl_idname, icon="CHECKMARK")
        draw_verdicts(layout, arm)
        layout.operator(MANIKIN_OT_write_job_report.bl_idname, icon="FILE_TEXT")


def _bake_load(arm: bpy.types.Object) -> str:
    """What "From Bake" uses: the load the hands held in the first baked frame."""
    from .job_assess import POSE_KEY, scene_load

    head = baked_frame(arm, "head")
    first = baked_frame(arm, head["frame_start"]) if head else None
    if first is None or POSE_KEY not in first:
        return "Load from the bake (bake the motion first)"
    found = scene_load([first])
    return f"Load from the bake: {found[0]:.1f} kg, {found[1]} hands" if found else "No load in the baked hands: 0 kg"


def draw_verdicts(layout: bpy.types.UILayout, arm: bpy.types.Object) -> None:
    """The stored verdicts: per method its title, its verdict line (wrapped, coloured by severity) and a Go to
    Frame button per frame driving it."""
    try:
        stored = json.loads(arm.get(JOB_KEY, ""))
    except ValueError:
        return
    box = layout.box()
    if stored.get("bake") != bake_stamp(arm):
        box.label(text="Out of date: the motion was baked again; Assess Job again", icon="ERROR")
    box.label(text=f"Rated with {stored['load_kg']:.1f} kg in {stored['hands']} hands, {stored['motion_s']:.2f} s "
                   "of motion")  # fmt: skip
    for row in stored["rows"]:
        draw_verdict(box, row["title"], row["severity"])
        for line in textwrap.wrap(row["text"], WRAP):
            sub = box.row()
            sub.alert = row["severity"] == 2
            sub.label(text="    " + line)
        for frame in row["frames"]:
            op = box.row().operator("manikin.go_to_frame", text=f"Go to frame {frame}", icon="TIME")
            op.frame = frame


def attach() -> None:
    """Give every object the job settings (used on manikins)."""
    bpy.types.Object.manikin_job = PointerProperty(type=MANIKIN_PG_job)


def detach() -> None:
    del bpy.types.Object.manikin_job


classes = (MANIKIN_PG_job, MANIKIN_OT_assess_job, MANIKIN_OT_write_job_report, MANIKIN_PT_job)
