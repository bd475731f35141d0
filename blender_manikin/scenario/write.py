"""The scene as a scenario file (bpy): what Export Scenario does, and the scenario a population study runs on.

The scene is read into a Problem exactly as Solve Pose reads it (``scene.problem_io``) and turned into the
scenario's tables by :func:`solver.scenario_to_dict`; keyed target empties become keyed targets and ``[motion]``
(:mod:`.keys`), the carried box its table; ``write_scenario_files`` writes mesh obstacles as OBJ files beside the
TOML and boxes, spheres, capsules and planes in it.
"""

from __future__ import annotations

from pathlib import Path

import bpy

from ...solver import scenario_to_dict
from ...solver.io.scenario.write import write_scenario_files
from ..scene import carried_object, problem_io
from . import keys
from .read import rig_source


def scene_scenario(arm: bpy.types.Object, pose: bool = False, motion: bool = False) -> dict:
    """``arm``'s targets, loops, loads, obstacles, carried box and settings as a scenario's tables; with ``pose``
    its current pose as ``[start]``, with ``motion`` its keyed targets' keys and ``[motion]``."""
    bpy.context.evaluated_depsgraph_get()  # brings the empties' world matrices up to date
    sp = problem_io.read_problem(arm, start=pose)
    data = scenario_to_dict(sp.problem, rig_source(arm), sp.options, sp.x0 if pose else None, arm.name)
    if motion:
        keys.export_motion(data, bpy.context.scene, arm)
    if (carried := carried_object.carried_table(arm)) is not None:
        data["carried"] = carried
    return data


def export_scenario(arm: bpy.types.Object, path: str | Path, pose: bool = True) -> list[Path]:
    """Write ``arm``'s scenario (with its keys and, with ``pose``, its current pose) to ``path``, its mesh
    obstacles beside it; the files written (the mesh files, then the scenario). ManikinError or OSError."""
    return write_scenario_files(path, scene_scenario(arm, pose=pose, motion=True))
