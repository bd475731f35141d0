"""A problem whose feet may step: each foot support freed in x, y and rz (flat on the floor, its z, roll and pitch
locks kept), bounded by the stance rows (:mod:`.limits`) and costed by the step cost (:mod:`.cost`). Units: m, rad.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..comfort import Comfort
from ..errors import ManikinError, UsageError
from ..problem.problem import Problem
from ..problem.specs import Target
from .cost import COMFORT_FRACTION, WEIGHT, StepCost
from .limits import FEET, StanceBounds, stance_limits, stature_of

PLANTED, STEP = "planted", "step"
FEET_MODES = (PLANTED, STEP)
FREED = ("x", "y", "rz")  # what a stepping foot's target no longer holds: along and about the floor


def check_feet(value: object, what: str = "--feet") -> str:
    """``value`` as a feet mode ("planted" or "step"); anything else one UsageError line naming ``what``."""
    if value not in FEET_MODES:
        raise UsageError(f"{what}: expected {' or '.join(FEET_MODES)}, got {value!r}")
    return str(value)


def foot_targets(problem: Problem) -> dict[str, Target]:
    """The enabled support targets on the feet, by TCP."""
    return {t.tcp: t for t in problem.all_targets if t.support and t.enabled and t.tcp in FEET}


def bounds_of(problem: Problem) -> StanceBounds | None:
    """The stance rows of a stepping problem (None: its feet are planted)."""
    return next((c for c in problem.extra_constraints if isinstance(c, StanceBounds)), None)


def stepping(problem: Problem) -> Problem:
    """``problem`` with its feet free to step from where their targets stand (the same problem if it steps already).
    A body without both feet as enabled supports is one ManikinError line."""
    if bounds_of(problem) is not None:
        return problem
    feet = foot_targets(problem)
    if set(feet) != set(FEET):
        missing = ", ".join(f for f in FEET if f not in feet)
        raise ManikinError(f"feet = step: needs both feet as enabled support targets (missing: {missing})")
    model = problem.model
    zero = model.forward(model.zero_pose())
    starts = {f: (_rotation(problem, feet[f], zero), np.asarray(feet[f].position, dtype=float)) for f in FEET}
    freed = [dataclasses.replace(t, lock=tuple(a for a in t.lock if a not in FREED), operator=None)
             if t.tcp in feet and t is feet[t.tcp] else t for t in problem.all_targets]  # fmt: skip
    stature = stature_of(model)
    cost = StepCost(model, starts, COMFORT_FRACTION * stature)
    comfort = Comfort([*problem.comfort.terms, (WEIGHT, cost)], problem.comfort.weights)
    bounds = StanceBounds(model, stance_limits(model), starts)
    spec = problem.spec.replace(targets=freed, comfort=comfort,
                                extra_constraints=(*problem.spec.extra_constraints, bounds))  # fmt: skip
    return Problem(model, spec)


def _rotation(problem: Problem, target: Target, zero) -> np.ndarray:
    """A foot target's rotation (3x3, world): its own, else the TCP's zero-pose orientation (as the problem has it)."""
    if target.rotation is not None:
        return np.asarray(target.rotation, dtype=float)
    return zero.tcp_frame(problem.model.tcp(target.tcp))[0]
