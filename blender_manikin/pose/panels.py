"""The "Manikin" tab of the 3D view's sidebar (its main panel and the pose's subpanels: target, obstacle, result,
solver settings), and the Add > Manikin menu entry.

Every subpanel of the tab, whichever feature's folder it is in, has its place under the main panel in
``bl_order``: target 1, obstacle 2, result 3, motion 4, solver settings 5, retarget 6, population study 7.
"""

import math

import bpy

from ...solver.options import AXES
from ..scene import kernel_warmup
from ..scene.help import draw_help
from ..scene.registries import comfort_settings
from ..scene.schema import (
    ERROR_KEY,
    FILE_KEY,
    PRESET_KEY,
    frame_result,
    is_obstacle,
    last_result,
    members,
    orphan_hint,
    rig_of,
)

_UNITS = {
    ".position": ("mm", 1e3),
    ".rotation": ("deg", 180.0 / math.pi),
    ".force": ("N", 1.0),
    ".moment": ("N m", 1.0),
    ".shortfall": ("mm", 1e3),  # floor, obstacles, self-collision: how far inside the clearance (m)
}
_ROLE_ICONS = {"TARGET": "EMPTY_ARROWS", "LOOP": "LINKED", "LOAD": "CUBE"}


def _shown(name: str, value: float) -> str:
    """A residual with its unit: mm, deg, N, N m; a target held by a combination of axes (no own unit) says so."""
    for suffix, (unit, scale) in _UNITS.items():
        if name.endswith(suffix):
            return f"{value * scale:.2f} {unit}"
    return f"{value:.3g} (m and rad combined)"


def _loose_supports(arm: bpy.types.Object) -> list[str]:
    """TCPs of ``arm``'s supports with x, y or rz unlocked: they slide even when the feet are planted."""
    found = []
    for ob in members(arm):
        s = ob.manikin_target
        if s.role == "TARGET" and s.support and s.enabled and not (s.lock[0] and s.lock[1] and s.lock[5]):
            found.append(s.tcp)
    return found


def listed(arm: bpy.types.Object | None, objects) -> list[bool]:
    """Per object of ``objects`` (bpy.data.objects): is it a target, loop or load of ``arm`` in some scene."""
    return [arm is not None and ob.manikin_target.role != "NONE" and ob.manikin_target.rig == arm
            and bool(ob.users_scene) for ob in objects]  # fmt: skip


class MANIKIN_UL_targets(bpy.types.UIList):
    """The manikin's targets, loops and loads, one row each: enabled, name (and TCP), priority, locks, support,
    weight; clicking a row selects that empty (its Target panel then shows the rest)."""

    def filter_items(self, context: bpy.types.Context, data, propname: str) -> tuple[list[int], list[int]]:
        objects = getattr(data, propname)
        flags = [self.bitflag_filter_item if ok else 0 for ok in listed(rig_of(context.active_object), objects)]
        return flags, []  # no new order: bpy.data.objects is kept sorted by name

    def draw_item(self, context, layout, data, item, icon, active_data, active_prop, index=0, flt_flag=0) -> None:
        s = item.manikin_target
        row = layout.row(align=True)
        row.prop(s, "enabled", text="")
        row.label(text=item.name + (f" > {s.other}" if s.role == "LOOP" else ""), icon=_ROLE_ICONS.get(s.role, "DOT"))
        if s.role == "LOAD":
            row.label(text=f"{-s.force[2] / 9.81:.1f} kg")
            return
        if s.role == "TARGET":
            row.prop(s, "priority", text="")
        locks = row.row(align=True)
        for i, axis in enumerate(AXES):
            locks.prop(s, "lock", index=i, text=axis, toggle=True)
        if s.role == "TARGET":
            row.prop(s, "support", text="", icon="SNAP_FACE")
        row.prop(s, "weight", text="")


def draw_add_menu(self: bpy.types.Menu, context: bpy.types.Context) -> None:
    self.layout.operator_menu_enum("manikin.add_manikin", "preset", text="Manikin", icon="ARMATURE_DATA")


MENUS = (("VIEW3D_MT_add", draw_add_menu),)


class _SidebarPanel(bpy.types.Panel):
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Manikin"
    draw_header_preset = draw_help  # the help button (scene/help.py)


def _draw_warmup(layout: bpy.types.UILayout) -> None:
    """A line while the kernels compile in the background after installing (a solve meanwhile may wait for them)."""
    line = kernel_warmup.status_line()
    if line:
        layout.label(text=line, icon="SORTTIME")


class MANIKIN_PT_main(_SidebarPanel):
    bl_idname = "MANIKIN_PT_main"
    bl_label = "Manikin"

    def draw(self, context: bpy.types.Context) -> None:
        layout = self.layout
        arm = rig_of(context.active_object)
        layout.operator_menu_enum("manikin.add_manikin", "preset", text="Add Manikin", icon="ARMATURE_DATA")
        if arm is None:
            orphan = orphan_hint(context.active_object)  # a target or body whose manikin was deleted with X
            layout.label(text=orphan or "Select a manikin or one of its targets", icon="ERROR" if orphan else "INFO")
            if orphan:
                layout.operator("manikin.delete_manikin", icon="TRASH")
            return
        layout.label(text=f"{arm.name} ({arm.get(PRESET_KEY) or arm.get(FILE_KEY)})")
        layout.row(align=True).prop(arm.manikin, "display", expand=True)
        layout.row(align=True).prop(arm.manikin, "feet", expand=True)
        if arm.manikin.feet == "PLANTED":  # a support's own unlocked axes still let it slide: say which
            loose = _loose_supports(arm)
            if loose:
                layout.label(text=f"May still slide (x, y or rz unlocked): {', '.join(loose)}", icon="INFO")
        row = layout.row(align=True)
        row.scale_y = 1.4
        row.operator("manikin.solve_pose", icon="PLAY")
        row.prop(arm.manikin, "live", toggle=True, icon="REC")
        _draw_warmup(layout)
        row = layout.row(align=True)
        row.operator("manikin.reset_pose", icon="LOOP_BACK")
        row.prop(arm.manikin, "show_overlay", toggle=True, icon="OVERLAY")
        row.prop(arm.manikin, "show_capsules", toggle=True, icon="MESH_CAPSULE")
        col = layout.column(align=True)
        col.operator("manikin.add_target", icon="EMPTY_ARROWS")
        col.operator("manikin.add_loop", icon="LINKED")
        col.operator("manikin.add_load", icon="CUBE")
        layout.label(text="Targets, loops and loads")
        layout.template_list("MANIKIN_UL_targets", "", bpy.data, "objects", arm.manikin, "target_index", rows=3)
        row = layout.row(align=True)
        row.operator("manikin.import_scenario", icon="IMPORT")
        row.operator("manikin.export_scenario", icon="EXPORT")
        layout.operator("manikin.import_envelope", icon="MESH_UVSPHERE")
        row = layout.row(align=True)
        row.operator("manikin.duplicate_manikin", icon="DUPLICATE")
        row.operator("manikin.delete_manikin", icon="TRASH")
        if arm.get(ERROR_KEY):  # from live mode, which has no report()
            layout.label(text=arm[ERROR_KEY], icon="ERROR")


class MANIKIN_PT_target(_SidebarPanel):
    bl_label = "Target"
    bl_parent_id = "MANIKIN_PT_main"
    bl_order = 1

    @classmethod
    def poll(cls, context: bpy.types.Context) -> bool:
        ob = context.active_object
        return ob is not None and ob.manikin_target.role != "NONE"

    def draw(self, context: bpy.types.Context) -> None:
        s = context.active_object.manikin_target
        layout = self.layout
        layout.use_property_split = True
        layout.prop(s, "role")
        layout.prop(s, "rig")
        layout.prop(s, "tcp")
        if s.role == "LOOP":
            layout.prop(s, "other")
        if s.role == "LOAD":
            layout.prop(s, "force")
            layout.label(text=f"= {-s.force[2] / 9.81:.2f} kg carried")
        else:
            row = layout.row(align=True, heading="Lock")
            for i, axis in enumerate(AXES):
                row.prop(s, "lock", index=i, text=axis, toggle=True)
            layout.prop(s, "weight")
        if s.role == "TARGET":
            layout.prop(s, "support")
            sub = layout.row()
            sub.active = s.support
            sub.prop(s, "friction")
            layout.prop(s, "priority")
        layout.prop(s, "enabled")


class MANIKIN_PT_obstacle(_SidebarPanel):
    bl_label = "Obstacle"
    bl_parent_id = "MANIKIN_PT_main"
    bl_order = 2

    @classmethod
    def poll(cls, context: bpy.types.Context) -> bool:
        ob = context.active_object
        return ob is not None and ob.type == "MESH" and ob.manikin_target.role == "NONE"

    def draw(self, context: bpy.types.Context) -> None:
        s = context.active_object.manikin_obstacle
        layout = self.layout
        layout.use_property_split = True
        layout.prop(s, "enabled")
        col = layout.column()
        col.active = is_obstacle(context.active_object)  # ticked, or in a scene's obstacle collection
        col.prop(s, "clearance")
        col.prop(s, "shape")
        layout.label(text='(or put it in a collection named "Obstacles")')


SEVERITY_ICONS = {0: "CHECKMARK", 1: "ERROR", 2: "ERROR"}  # a score's severity (2 also drawn red: alert)


def draw_verdict(layout: bpy.types.UILayout, text: str, severity: int | None) -> None:
    """One line of a score's words with its severity's icon, red when it says change it."""
    row = layout.row()
    row.alert = severity == 2
    row.label(text=text, icon=SEVERITY_ICONS.get(severity, "NONE"))


class MANIKIN_PT_result(_SidebarPanel):
    """The last solve's result or, after a bake, the current frame's (stored by the bake: motion/frame_store.py)."""

    bl_label = "Result"
    bl_parent_id = "MANIKIN_PT_main"
    bl_order = 3

    @classmethod
    def poll(cls, context: bpy.types.Context) -> bool:
        arm = rig_of(context.active_object)
        return arm is not None and (last_result(arm) or frame_result(arm, context.scene.frame_current)) is not None

    def draw(self, context: bpy.types.Context) -> None:
        arm, frame = rig_of(context.active_object), context.scene.frame_current
        data = frame_result(arm, frame)
        layout = self.layout
        if data is not None:  # the panel follows the timeline through the baked frames
            layout.label(text=f"Baked frame {frame}", icon="TIME")
        else:
            data = last_result(arm)
        ok = data["converged"]
        layout.label(
            text=f"{'Converged' if ok else 'NOT converged'}: {data['iterations']} it, {data['time_ms']:.0f} ms",
            icon="CHECKMARK" if ok else "ERROR",
        )
        from ..scene.supports import moved_text  # light (NumPy), but kept out of enabling like the scene code

        for line in data.get("step_lines", []) + moved_text(data.get("moved", {})):
            layout.label(text=line, icon="TRACKING_FORWARDS")
        for line in data.get("notes", []):
            layout.label(text=line, icon="ERROR")
        for name in data["unmet"]:
            if name in data.get("shortfall", {}):
                layout.label(text=f"{name}: short by {data['shortfall'][name]}", icon="X")
            elif name in data.get("broken", ()):
                layout.label(text=f"{name}: NOT held (priority 1)", icon="ERROR")
            else:
                layout.label(text=f"unmet: {name}", icon="X")
        box = layout.box()
        box.label(text="Residuals")
        for name, value in data["residuals"].items():
            row = box.row()
            row.label(text=name)
            row.label(text=_shown(name, value))
        parts = ", ".join(f"{k} {v:.3f}" for k, v in data["comfort_parts"].items())
        # the solver maximises comfort = -(the weighted sum of the parts) <= 0: shown as discomfort >= 0, 0 the best
        layout.label(text=f"Discomfort {-data['comfort']:.3f} (0 = best; parts before weights: {parts})")
        words = data.get("scores")
        if data.get("pending"):  # a live drag's result: the scores are added when the drag ends (pose/live.py)
            layout.label(text="Ergonomics: when the drag ends", icon="TIME")
        if isinstance(words, list) and words:  # the scores' words (an older version stored a dict)
            box = layout.box()
            box.label(text="Ergonomics (this pose)")
            rated = {v["text"]: v for v in data.get("verdicts", ()) if isinstance(v, dict)}
            for text in words:
                draw_verdict(box, text, rated.get(text, {}).get("severity"))
            for verdict in rated.values():  # what each level means: OWAS's action category, the worksheet's worst item
                if verdict.get("level"):
                    box.label(text=f"{verdict['title']}: {verdict['level']}")
        box = layout.box()
        box.label(text="Most loaded joints (% of strength)")
        for name, tau, percent in data["joint_loads"]:
            row = box.row()
            row.label(text=name)
            row.label(text=f"{abs(tau):.1f} N m, {percent:.0f}%")
        for c in data["contacts"]:
            layout.label(text=f"{c['tcp']}: {c['force'][2]:.0f} N up")
        if data.get("kernels"):  # a solve's (not a baked frame's, nor an older version's): which kernels solved it
            layout.label(text=f"Solver kernels: {data['kernels']}")
            _draw_warmup(layout)


class MANIKIN_PT_settings(_SidebarPanel):
    bl_label = "Solver Settings"
    bl_parent_id = "MANIKIN_PT_main"
    bl_order = 5
    bl_options = {"DEFAULT_CLOSED"}

    @classmethod
    def poll(cls, context: bpy.types.Context) -> bool:
        return rig_of(context.active_object) is not None

    def draw(self, context: bpy.types.Context) -> None:
        settings = rig_of(context.active_object).manikin
        layout = self.layout
        layout.use_property_split = True
        names = ("balance", "floor", "self_collision", "comfort", "reduction", "max_iterations", "restarts",
                 "live_iterations")  # fmt: skip
        for name in names:
            layout.prop(settings, name)
        col = layout.column(heading="Comfort weights", align=True)
        for setting in comfort_settings():  # one per registered standard comfort term
            if hasattr(settings, setting.prop):  # a term registered after the add-on has none until it registers again
                col.prop(settings, setting.prop)


classes = (
    MANIKIN_UL_targets,
    MANIKIN_PT_main,
    MANIKIN_PT_target,
    MANIKIN_PT_obstacle,
    MANIKIN_PT_result,
    MANIKIN_PT_settings,
)
