"""A scenario file into the scene (bpy): what Import Scenario does, as functions that the operator and the headless
job (``motion/job.py``) call alike.

The file is read by :func:`solver.load_scenario` (all validation lives there) before the scene changes; then its
targets, loops and loads become empties (keyed targets keyed, :mod:`.keys`), its settings the manikin's, its start
the pose, its obstacles objects (``scene.obstacle_objects``) and its carried box an object between the hands
(``scene.carried_object``). General operator rows and custom soles have no UI: they come back as warnings.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import bpy
import numpy as np
from mathutils import Matrix

from ... import solver
from ...solver.presets import MANIKINS_DIR
from ...solver.problem.scenario import Scenario
from ..scene import armature, carried_object, obstacle_objects, targets
from ..scene.registries import set_comfort_weights
from ..scene.schema import FILE_KEY, PRESET_KEY, members
from . import keys


@dataclass
class Imported:
    """What an import made: the manikin it went onto, the scenario read, how many targets are keyed, how many
    obstacles it has, and the warnings (lines for the user)."""

    arm: bpy.types.Object
    scenario: Scenario
    keyed: int
    obstacles: int
    warnings: list[str] = field(default_factory=list)


def body_source(model: solver.Model) -> dict:
    """{"preset": name} for a shipped preset, else {"file": path} of the body TOML."""
    file = Path(model.info.get("file", ""))
    if file.parent == MANIKINS_DIR and file.suffix == ".toml":
        return {"preset": file.stem}
    return {"file": str(file)}


def rig_source(arm: bpy.types.Object, resolved: bool = False) -> dict:
    """The armature's body as a scenario's [manikin] table: {"preset": name} or {"file": absolute path} (with
    ``resolved``, symbolic links and ``..`` resolved, to compare with :func:`body_source`)."""
    preset = arm.get(PRESET_KEY, "")
    if preset:
        return {"preset": preset}
    path = bpy.path.abspath(arm.get(FILE_KEY, ""))
    return {"file": str(Path(path).resolve()) if resolved else path}


def import_scenario(context: bpy.types.Context, path: str | Path, onto: bpy.types.Object | None = None,
                    replace: bool = False) -> Imported:  # fmt: skip
    """Read the scenario file ``path`` into the scene: onto the manikin ``onto`` if it has the scenario's body
    (its empties replaced), else onto a new manikin at the world origin. With ``replace``, the obstacles earlier
    imports brought into the scene and the manikin's carried box go first. The manikin ends selected and active.
    ManikinError (one line) for a bad file, before anything changes."""
    return apply_scenario(context, solver.load_scenario(path), Path(path).name, onto, replace)


def apply_scenario(context: bpy.types.Context, sc: Scenario, name: str, onto: bpy.types.Object | None = None,
                   replace: bool = False) -> Imported:  # fmt: skip
    """:func:`import_scenario` of a scenario already read (``name``: its file's name, which the obstacle objects
    it makes remember)."""
    obstacle_objects.check_shapes(sc.problem.obstacles)  # before anything changes
    source = body_source(sc.model)
    arm = onto if onto is not None and context.scene.objects.get(onto.name) == onto else None  # this scene's only
    if arm is None or rig_source(arm) != source:
        preset, file = source.get("preset", ""), source.get("file", "")
        model = armature.load_model(preset, file)
        arm = armature.create_manikin(context, model, preset, file, at_cursor=False)  # scenario = world
    warnings: list[str] = []
    if replace:  # the previous scenario's obstacles (this scene's only) and box
        obstacle_objects.remove_imported(context.scene)
        carried_object.remove_carried(arm)
    keyed = _apply(context.scene, arm, sc, warnings)
    obstacles = sc.problem.obstacles
    warnings += obstacle_objects.add_obstacles(context.scene, arm, obstacles, name)
    if sc.carried is not None:
        carried_object.add_carried(arm, sc.carried)
    for ob in context.view_layer.objects.selected:
        if ob is not None:  # an object removed by a script since the view layer's last update
            ob.select_set(False)
    arm.select_set(True)
    context.view_layer.objects.active = arm
    return Imported(arm, sc, keyed, len(obstacles), warnings)


def _world(arm: bpy.types.Object, rot: np.ndarray, pos: np.ndarray) -> Matrix:
    local = np.eye(4)
    local[:3, :3], local[:3, 3] = rot, pos
    return arm.matrix_world @ Matrix(local.tolist())


def _settings(arm: bpy.types.Object, sc: Scenario) -> None:
    """The manikin's solver settings from the scenario's."""
    problem, settings = sc.problem, arm.manikin
    settings.balance = problem.balance
    settings.floor = problem.floor
    settings.self_collision = problem.self_collision
    settings.reduction = bool(problem.reduction_groups)
    settings.comfort = sc.options.optimize_comfort
    settings.max_iterations = sc.options.max_iterations
    settings.restarts = sc.options.restarts
    if problem.comfort.weights is not None:  # a scenario's comfort is the standard terms with its weights
        set_comfort_weights(settings, problem.comfort.weights)


def _apply(scene: bpy.types.Scene, arm: bpy.types.Object, sc: Scenario, warnings: list[str]) -> int:
    """The scenario's settings, empties and start pose on ``arm`` (its old empties removed); the number of keyed
    targets."""
    for ob in members(arm):
        bpy.data.objects.remove(ob, do_unlink=True)
    _settings(arm, sc)
    problem = sc.problem
    armature.write_pose(arm, sc.model.zero_pose())
    zero = sc.model.forward(sc.model.zero_pose())
    empties = []
    for t in problem.all_targets:
        ob = targets.add_target(arm, t.tcp, t.lock, t.support, t.friction, follow=True)  # moves with the manikin
        empties.append(ob)
        rot = t.rotation if t.rotation is not None else zero.tcp_frame(sc.model.tcp(t.tcp))[0]
        ob.matrix_world = _world(arm, rot, t.position)
        ob.manikin_target.weight, ob.manikin_target.enabled = t.weight, t.enabled
        ob.manikin_target.priority = "AUTO" if t.priority is None else str(t.priority)
        warnings += _unsupported(f"target {t.tcp}", t.operator, t.sole)
    for lp in problem.loops:
        ob = targets.add_loop(arm, lp.tcp, lp.other, lp.lock)
        rot = np.eye(3) if lp.offset_rotation is None else lp.offset_rotation
        local = np.eye(4)
        local[:3, :3], local[:3, 3] = rot, lp.offset_position
        if ob.parent is not None:
            ob.matrix_basis = Matrix(local.tolist())
        ob.manikin_target.weight = lp.weight
        warnings += _unsupported(f"loop {lp.tcp}-{lp.other}", lp.operator, None)
    arm_rot = np.array(arm.matrix_world.to_3x3())
    for ld in problem.load_specs:
        ob = targets.add_load(arm, ld.tcp, 0.0)
        ob.manikin_target.force = tuple(float(v) for v in arm_rot @ np.asarray(ld.force))
    armature.write_pose(arm, sc.start)
    return keys.import_motion(scene, arm, sc, empties)


def _unsupported(what: str, operator: object, sole: object) -> list[str]:
    """Warnings for what a scenario may hold but the scene cannot show."""
    out = []
    if operator is not None:
        out.append(f"{what}: operator rows have no Blender UI; all axes locked instead")
    if sole is not None:
        out.append(f"{what}: custom sole ignored (the TCP's own sole is used)")
    return out
