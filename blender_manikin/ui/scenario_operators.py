"""Scenario files: the scene's targets, loops, loads, obstacles and settings to and from the solver's scenario TOML.

Import reads with :func:`solver.load_scenario` (all validation lives there) and builds the empties and the
obstacles (``scene.obstacle_objects``); export reads the scene into a Problem exactly as Solve does and writes it
with ``write_scenario_files``: mesh obstacles as OBJ files beside the TOML, boxes, spheres, capsules and planes in
it. Keyed targets become keyed empties and back (``scene.motion_keys``); general operator rows and custom soles
have no UI and are reported.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import bpy
import numpy as np
from bpy.props import BoolProperty, StringProperty
from bpy_extras.io_utils import ExportHelper, ImportHelper
from mathutils import Matrix

from ...solver.errors import ManikinError
from ...solver.presets import MANIKINS_DIR
from ..scene.schema import FILE_KEY, PRESET_KEY, members, rig_of

if TYPE_CHECKING:
    from ...solver.body.model import Model
    from ...solver.problem.scenario import Scenario


def body_source(model: Model) -> dict:
    """{"preset": name} for a shipped preset, else {"file": path} of the body TOML."""
    file = Path(model.info.get("file", ""))
    if file.parent == MANIKINS_DIR and file.suffix == ".toml":
        return {"preset": file.stem}
    return {"file": str(file)}


def rig_source(arm: bpy.types.Object) -> dict:
    """The armature's body as a scenario's [manikin] table: {"preset": name} or {"file": absolute path}."""
    preset = arm.get(PRESET_KEY, "")
    return {"preset": preset} if preset else {"file": bpy.path.abspath(arm.get(FILE_KEY, ""))}


def _world(arm: bpy.types.Object, rot: np.ndarray, pos: np.ndarray) -> Matrix:
    local = np.eye(4)
    local[:3, :3], local[:3, 3] = rot, pos
    return arm.matrix_world @ Matrix(local.tolist())


class MANIKIN_OT_import_scenario(bpy.types.Operator, ImportHelper):
    """Load a scenario TOML: targets, loops, loads, obstacles, settings and start pose (onto the active manikin if it
    has the same body, else onto a new one)"""

    bl_idname = "manikin.import_scenario"
    bl_label = "Import Scenario"
    bl_options = {"REGISTER", "UNDO"}

    filename_ext = ".toml"
    filter_glob: StringProperty(default="*.toml", options={"HIDDEN"})

    @classmethod
    def poll(cls, context: bpy.types.Context) -> bool:
        return context.mode == "OBJECT"

    def execute(self, context: bpy.types.Context) -> set[str]:
        from ... import solver
        from ..scene import armature, carried_object, obstacle_objects

        try:
            sc = solver.load_scenario(self.filepath)
            source = body_source(sc.model)
            arm = rig_of(context.active_object)
            if arm is None or rig_source(arm) != source:
                model = armature.load_model(source.get("preset", ""), source.get("file", ""))
                preset, file = source.get("preset", ""), source.get("file", "")
                arm = armature.create_manikin(context, model, preset, file, at_cursor=False)  # scenario = world
            keyed = self._apply(context.scene, arm, sc)
            obstacles = sc.problem.obstacles
            name = Path(self.filepath).name
            for warning in obstacle_objects.add_obstacles(context.scene, arm, obstacles, name):
                self.report({"WARNING"}, warning)
            if sc.carried is not None:
                carried_object.add_carried(arm, sc.carried)
        except ManikinError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        for ob in context.view_layer.objects.selected:
            if ob is not None:  # an object removed by a script since the view layer's last update
                ob.select_set(False)
        arm.select_set(True)
        context.view_layer.objects.active = arm
        motion = f"; {keyed} keyed targets, frames {sc.frames[0]}-{sc.frames[-1]}" if keyed else ""
        motion += f"; {len(obstacles)} obstacles" if obstacles else ""
        self.report({"INFO"}, f"Imported {name} onto {arm.name}{motion}")
        return {"FINISHED"}

    def _apply(self, scene: bpy.types.Scene, arm: bpy.types.Object, sc: Scenario) -> int:
        from ..scene import armature, motion_keys, targets

        for ob in members(arm):
            bpy.data.objects.remove(ob, do_unlink=True)
        problem, settings = sc.problem, arm.manikin
        settings.balance = problem.balance
        settings.floor = problem.floor
        settings.self_collision = problem.self_collision
        settings.reduction = bool(problem.reduction_groups)
        settings.comfort = sc.options.optimize_comfort
        settings.max_iterations = sc.options.max_iterations
        settings.restarts = sc.options.restarts
        w = problem.comfort.weights
        settings.comfort_range, settings.comfort_load, settings.comfort_contact = w.range, w.load, w.contact
        armature.write_pose(arm, sc.model.zero_pose())
        zero = sc.model.forward(sc.model.zero_pose())
        empties = []
        for t in problem.all_targets:
            ob = targets.add_target(arm, t.tcp, t.lock, t.support, t.friction)
            empties.append(ob)
            rot = t.rotation if t.rotation is not None else zero.tcp_frame(sc.model.tcp(t.tcp))[0]
            ob.matrix_world = _world(arm, rot, t.position)
            ob.manikin_target.weight, ob.manikin_target.enabled = t.weight, t.enabled
            ob.manikin_target.priority = "AUTO" if t.priority is None else str(t.priority)
            self._warn_unsupported(f"target {t.tcp}", t.operator, t.sole)
        for lp in problem.loops:
            ob = targets.add_loop(arm, lp.tcp, lp.other, lp.lock)
            rot = np.eye(3) if lp.offset_rotation is None else lp.offset_rotation
            local = np.eye(4)
            local[:3, :3], local[:3, 3] = rot, lp.offset_position
            if ob.parent is not None:
                ob.matrix_basis = Matrix(local.tolist())
            ob.manikin_target.weight = lp.weight
            self._warn_unsupported(f"loop {lp.tcp}-{lp.other}", lp.operator, None)
        arm_rot = np.array(arm.matrix_world.to_3x3())
        for ld in problem.load_specs:
            ob = targets.add_load(arm, ld.tcp, 0.0)
            ob.manikin_target.force = tuple(float(v) for v in arm_rot @ np.asarray(ld.force))
        armature.write_pose(arm, sc.start)
        return motion_keys.import_motion(scene, arm, sc, empties)

    def _warn_unsupported(self, what: str, operator, sole) -> None:
        if operator is not None:
            self.report({"WARNING"}, f"{what}: operator rows have no Blender UI; all axes locked instead")
        if sole is not None:
            self.report({"WARNING"}, f"{what}: custom sole ignored (the TCP's own sole is used)")


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
        from ...solver import scenario_to_dict
        from ...solver.io.scenario.write import write_scenario_files
        from ..scene import carried_object, motion_keys, problem_io

        arm = rig_of(context.active_object)
        context.evaluated_depsgraph_get()
        try:
            sp = problem_io.read_problem(arm)
            start = sp.x0 if self.include_pose else None
            data = scenario_to_dict(sp.problem, rig_source(arm), sp.options, start, arm.name)
            motion_keys.export_motion(data, context.scene, arm)
            if (carried := carried_object.carried_table(arm)) is not None:
                data["carried"] = carried
            written = write_scenario_files(self.filepath, data)
        except (ManikinError, OSError) as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        count = len(written) - 1
        meshes = f" and {count} mesh file{'s' if count > 1 else ''} beside it" if count else ""
        self.report({"INFO"}, f"Wrote {self.filepath}{meshes}")
        return {"FINISHED"}


classes = (MANIKIN_OT_import_scenario, MANIKIN_OT_export_scenario)
