"""Motions: targets keyed over frames, solved frame by frame, each warm-started from the previous one.

A keyed target holds its first key before it and its last key after it; in between, positions are
interpolated linearly and rotations by slerp. Between frames every joint may change by at most
``max_joint_change`` rad (``max_root_shift`` m for the root translation), so the motion cannot jump; a
frame that needs more does not converge and says that its target moved too far. On the way from one frame to the
next (joint values interpolated linearly, as Blender plays the baked keys) no body part may pass through the floor
or an obstacle: :mod:`solver.motion_sweep` checks it, re-solves a frame that would, and reports what remains.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

from .iteration import solve
from .motion_sweep import MotionSweep
from .options import DEFAULT_LIMITS, DEFAULT_OPTIONS, MotionLimits, SolverOptions
from .problem import Problem, Target
from .result import Result
from .spatial import matrix_to_quat, quat_to_matrix, slerp

if TYPE_CHECKING:
    from .scenario import Scenario


@dataclass(frozen=True)
class Key:
    """A target pose at one frame: position (m) and optional rotation (3x3)."""

    frame: int
    position: np.ndarray
    rotation: np.ndarray | None = None


@dataclass(frozen=True)
class Track:
    """The keys of the target at index ``target`` in the scenario's target list, sorted by frame."""

    target: int
    keys: tuple[Key, ...]

    def pose_at(self, frame: float) -> tuple[np.ndarray, np.ndarray | None]:
        """Interpolated (position, rotation) at ``frame``."""
        keys = self.keys
        if frame <= keys[0].frame:
            return keys[0].position, keys[0].rotation
        if frame >= keys[-1].frame:
            return keys[-1].position, keys[-1].rotation
        i = int(np.searchsorted([k.frame for k in keys], frame, side="right")) - 1
        a, b = keys[i], keys[i + 1]
        t = (frame - a.frame) / (b.frame - a.frame)
        position = (1.0 - t) * a.position + t * b.position
        if a.rotation is None or b.rotation is None:
            return position, a.rotation if b.rotation is None else b.rotation
        q = slerp(matrix_to_quat(a.rotation), matrix_to_quat(b.rotation), t)
        return position, quat_to_matrix(q)


def targets_at(targets: list[Target], tracks: list[Track], frame: float) -> list[Target]:
    """The target list with every keyed target moved to its pose at ``frame``."""
    out = list(targets)
    for track in tracks:
        position, rotation = track.pose_at(frame)
        out[track.target] = replace(out[track.target], position=position, rotation=rotation)
    return out


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


def bounded(problem: Problem, previous_x: np.ndarray, limits: MotionLimits) -> Problem:
    """A shallow copy of ``problem`` whose variable bounds also keep each joint near ``previous_x``."""
    step = variable_steps(problem, limits)
    return problem.with_bounds(problem.bounds.around(problem.to_variables(previous_x), step))


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
    way from it is checked for crossings of the floor and obstacles (:mod:`solver.motion_sweep`; pass ``sweep`` to
    read its counts). Yields (frame, result) so that callers can report progress or stop early.
    """
    sweep = MotionSweep() if sweep is None else sweep
    x = start
    previous: tuple[int, Problem, np.ndarray] | None = None  # the previous frame, its problem and solution
    for frame in frames:
        full = problem_at(frame)
        problem = full if (limits is None or previous is None) else bounded(full, previous[2], limits)
        result = solve(problem, x, options)
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
            steps = lambda: variable_steps(problem, step)  # noqa: E731, B023 (called at once, if at all)
            problems = previous[1], full, problem
            result = sweep.guard((previous[0], frame), problems, previous[2], result, options, steps)
        x = result.x
        previous = (frame, full, result.x)
        yield frame, result


def solve_motion(scenario: Scenario) -> Iterator[tuple[int, Result]]:
    """Solve every frame of ``scenario`` (one frame for a single pose) with its options and per-frame limits;
    yields (frame, result) as :func:`solve_frames` does."""
    return solve_frames(scenario.problem_at, scenario.frames, scenario.start, scenario.options, scenario.limits)
