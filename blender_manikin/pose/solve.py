"""Solving and resetting a manikin's pose (bpy): what Solve Pose and Reset Pose do, as plain functions that the
operators and headless scripts (``dev/snapshot.py``) call alike; live mode (``live``) re-solves with its own limits.

Imports the solver at module level: the operators import this module inside ``execute`` only.
"""

from __future__ import annotations

import bpy

from ...solver import Result, kernels, solve
from ..scene import armature, problem_io
from ..scene.schema import RESULT_KEY


def solve_pose(arm: bpy.types.Object) -> Result:
    """Solve ``arm``'s pose for its targets, loops and loads from its current pose and pose it with the result
    (its summary kept for the sidebar and the overlay); ManikinError names the empty or setting at fault."""
    bpy.context.evaluated_depsgraph_get()  # brings the empties' world matrices up to date
    sp = problem_io.read_problem(arm)
    result = solve(sp.problem, sp.x0, sp.options)
    problem_io.write_result(arm, result)
    return result


_kernels_said: list[float] = []  # the kernels' compile seconds already said (and NumPy's note, once a process)
SLOW_COMPILE = 1.0  # s: compiling kernels longer than this since the last report is said


def kernels_note() -> str:
    """The line "Solver kernels: <status>" the first time a solve runs on the NumPy kernels in this process (Numba
    did not import, or MANIKIN_KERNELS=numpy); with compiled kernels, how long compiling them took when a solve
    waited more than a second for it (the first after installing); else "". The Result panel names them always."""
    if not kernels.active():
        if _kernels_said:
            return ""
        _kernels_said.append(0.0)
        return f"Solver kernels: {kernels.status()}"
    spent = kernels.compile_seconds() - sum(_kernels_said)
    if spent <= SLOW_COMPILE:
        return ""
    _kernels_said.append(spent)
    return f"the solver's kernels were compiled for this machine first ({spent:.1f} s, once: later solves load them)"


def reset_pose(arm: bpy.types.Object) -> None:
    """Stand ``arm`` in its zero pose (upright, arms hanging) and forget its last result."""
    armature.write_pose(arm, armature.model_of(arm).zero_pose())
    arm.pop(RESULT_KEY, None)
