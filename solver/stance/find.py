"""The stance for a set of hand targets: solve with stepping feet from the current stance and return the problem
with its feet planted where they stepped (:func:`find_stance`). Units: m, deg."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from ..iteration import solve
from ..iteration.result import Result
from ..options import DEFAULT_OPTIONS, SolverOptions
from ..problem.problem import Problem
from .report import Step, annotate, steps_of
from .step_problem import foot_targets, stepping


@dataclass
class StanceResult:
    """A found stance: ``problem`` with its foot targets moved onto it (planted there, their own locks), the
    ``steps`` taken to get there, whether the stepping solve ``converged`` (every target met, in balance), a
    one-line ``message`` and the stepping solve's ``result`` (its pose: a warm start at the new stance)."""

    problem: Problem
    steps: list[Step]
    converged: bool
    message: str
    result: Result = field(repr=False)


def find_stance(problem: Problem, start: np.ndarray | None = None,
                options: SolverOptions = DEFAULT_OPTIONS) -> StanceResult:  # fmt: skip
    """Where to stand for ``problem``'s targets: ``problem`` (feet planted on their support targets; or stepping
    already) solved with the feet free to step within the stance rows (each foot within a step of its target, not
    crossed, turned at most 45 deg), in balance and clear of the obstacles, from ``start`` (joint values, or joints +
    forces; None: the zero pose). Returns the problem with the feet planted where they ended."""
    free = stepping(problem)
    result = annotate(solve(free, start, options))
    steps = steps_of(free, result.state)
    planted = plant(problem, free, result)
    if result.converged:
        message = "; ".join(s.text() for s in steps) or "no step needed: the targets are met from where the feet stand"
    else:
        message = "no stance within a step meets every target: " + result.verdict()
    return StanceResult(planted, steps, result.converged, message, result)


def plant(problem: Problem, free: Problem, result: Result) -> Problem:
    """``problem`` with each foot target moved to where ``result`` (a solve of its stepping form ``free``) put the
    foot: position and orientation, its locks as they were (a stepping ``problem`` keeps its stance rows and step
    cost from its first stance)."""
    kin = result.state.kin
    feet = foot_targets(problem)
    moved = []
    for t in problem.all_targets:
        if t.tcp in feet and t is feet[t.tcp]:
            rot, pos = kin.tcp_frame(problem.model.tcp(t.tcp))
            t = dataclasses.replace(t, position=pos.copy(), rotation=rot.copy())
        moved.append(t)
    return problem.with_targets(moved)
