"""Motions: targets keyed over frames (:mod:`solver.problem.tracks`), solved frame by frame, each warm-started from
the previous one.

Between frames every joint may change by at most
``max_joint_change`` rad (``max_root_shift`` m for the root translation), so the motion cannot jump; a
frame that needs more does not converge and says that its target moved too far. On the way from one frame to the
next (joint values interpolated linearly, as Blender plays the baked keys) no body part may pass through the floor
or an obstacle: :mod:`solver.motion.between_frames` checks it, re-solves a frame that would, and reports what remains.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import TYPE_CHECKING

import numpy as np

from ..iteration import solve
from ..iteration.result import Result
from ..options import DEFAULT_LIMITS, DEFAULT_OPTIONS, MotionLimits, SolverOptions
from ..problem.problem import Problem
from ..stance.report import annotate, frame_moves
from .between_frames import MotionSweep

if TYPE_CHECKING:
    from ..problem.scenario import Scenario


def variable_steps(problem: Problem, limits: MotionLimits) -> np.ndarray:
    """Largest per-frame change of each solver variable (inf for force variables)."""
    model = problem.model
    step = np.full(problem.n_x, np.inf)
    step[: model.n] = np.where(model.prismatic, limits.max_root_shift, limits.max_joint_change)
    if problem.reduction is None:
        return step
    weights = problem.reduction.slope  # |dx/dbeta|, its largest over the bounds for the shoulder rhythm
    with np.errstate(divide="ignore"):
        per_joint = np.where(weights > 0, step[:, None] / weights, np.inf)
    return per_joint.min(axis=0)


def as_x(problem: Problem, x: np.ndarray) -> np.ndarray:
    """``x`` as ``problem``'s full x: itself, or (another set of supports, e.g. a foot lifted for a step) its joints
    with the forces shared evenly again."""
    if len(x) == problem.n_x:
        return x
    return problem.to_x(problem.start(x[: problem.model.n]))


def kept_steps(problem: Problem, limits: MotionLimits) -> np.ndarray:
    """:func:`variable_steps`, read-only, kept for the next call with the same model, reduction, variable count and
    limits (a motion's next frame)."""
    model, last = problem.model, _last_steps[0]
    key = (model, problem.reduction, problem.n_x, limits)
    if last is not None and last[0] is model and last[1] is key[1] and last[2:4] == key[2:]:
        return last[4]
    steps = variable_steps(problem, limits)
    steps.flags.writeable = False
    _last_steps[0] = (*key, steps)
    return steps


_last_steps: list[tuple | None] = [None]  # (model, reduction, n_x, limits, steps) of the last kept_steps


def bounded(problem: Problem, previous_x: np.ndarray, limits: MotionLimits) -> Problem:
    """A shallow copy of ``problem`` whose variable bounds also keep each joint near ``previous_x``; the narrowed
    bounds of the last call kept for the same bounds, reduction, steps and ``previous_x`` (a motion's frame after one
    that did not move)."""
    step, bounds, reduction = kept_steps(problem, limits), problem.bounds, problem.reduction
    center, last = np.asarray(previous_x, dtype=float).tobytes(), _last_bounds[0]
    if last is not None and last[0] is bounds and last[1] is reduction and last[2] is step and last[3] == center:
        return problem.with_bounds(last[4])
    narrowed = bounds.around(problem.to_variables(previous_x), step)
    _last_bounds[0] = (bounds, reduction, step, center, narrowed)
    return problem.with_bounds(narrowed)


_last_bounds: list[tuple | None] = [None]  # (bounds, reduction, steps, previous_x's bytes, narrowed) of the last


def solve_frames(
    problem_at: Callable[[int], Problem],
    frames: list[int],
    start: np.ndarray,
    options: SolverOptions = DEFAULT_OPTIONS,
    limits: MotionLimits | None = DEFAULT_LIMITS,
    sweep: MotionSweep | None = None,
) -> Iterator[tuple[int, Result]]:
    """Solve ``frames`` in order, each warm-started from the previous frame's solution.

    The first frame starts from ``start``; later frames are held within ``limits`` of their predecessor, and the
    way from it is checked for crossings of the floor and obstacles (:mod:`solver.motion.between_frames`; pass
    ``sweep`` to
    read its counts). Yields (frame, result) so that callers can report progress or stop early.
    """
    sweep = MotionSweep() if sweep is None else sweep
    x = start
    previous: tuple[int, Problem, np.ndarray] | None = None  # the previous frame, its problem and solution
    warm = None  # the previous frame's end state: where this frame starts, what it computed there is shared
    for frame in frames:
        full = problem_at(frame)
        x = as_x(full, x)
        if previous is not None and len(previous[2]) != full.n_x:  # the supports changed: forces shared again
            previous = (previous[0], previous[1], as_x(full, previous[2]))
        problem = full if (limits is None or previous is None) else bounded(full, previous[2], limits)
        result = solve(problem, x, options, warm=warm)
        if not result.converged and problem is not full:
            v = problem.to_variables(result.x)
            held = problem.bounds.held(v, full.bounds)
            if held.any():
                names = full.variable_names()
                shown = ", ".join(names[i] for i in np.nonzero(held)[0][:3])
                result.notes.append(
                    f"frame {frame}: a target moved too far since the previous frame; joints held at the "
                    f"per-frame change bound: {shown}"
                )
        if previous is not None:
            step = limits or DEFAULT_LIMITS
            steps = lambda: kept_steps(problem, step)  # noqa: E731, B023 (called at once, if at all)
            problems = previous[1], full, problem
            result = sweep.guard((previous[0], frame), problems, previous[2], result, options, steps)
        annotate(result)  # the steps taken, or that planted feet kept a target out of reach
        if previous is not None:  # a stepping foot that moved since the last frame slid there: say so
            result.notes.extend(frame_moves(full, previous[1].state_of_x(previous[2]), result.state))
        x, warm = result.x, result.state
        previous = (frame, full, result.x)
        yield frame, result


def solve_motion(scenario: Scenario) -> Iterator[tuple[int, Result]]:
    """Solve every frame of ``scenario`` (one frame for a single pose) with its options and per-frame limits;
    yields (frame, result) as :func:`solve_frames` does."""
    return solve_frames(scenario.problem_at, scenario.frames, scenario.start, scenario.options, scenario.limits)
