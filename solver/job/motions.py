"""Each task's motion: its result file read, or its scenario (or operations scenario) solved now and written beside
the report; with the task's hand forces (:class:`.tasks.Force`).

Where the motion is solved, a force is one more of the problem's external loads at that hand in the frames it acts
(as a scenario's ``[[loads]]``): the solver balances the body against it, so the contact forces at the feet, every
joint moment (shoulder, L5/S1, hip, knee, ankle) and so % capable include it. A result file was solved without it:
the force is added to each frame's loads at the hand's position. The moment about a joint sums what acts on the
links beyond it (:mod:`solver.ergonomics.loads`), so every joint between that hand and the trunk (wrist, elbow,
shoulder, spine, L5/S1) includes the force exactly; the feet's contact forces cannot be solved again from a result,
so the legs' moments (hip, knee, ankle: what % capable rates) do not, and the report says so.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..errors import UsageError
from ..io.result.read import ResultFile, read_result
from .tasks import Force, Task

if TYPE_CHECKING:  # the problem and the solver load only when a task is solved (Blender's job panel never does)
    from ..problem.problem import Problem

RESULT_NOTE = ("hand forces added to the result's frames at the hand: the joint moments from the hand to the trunk "
               "(elbow, shoulder, L5/S1) include them; the feet's contact forces were not solved again, so the legs' "
               "moments, and % capable (hip, knee, ankle), do not")  # fmt: skip


@dataclass
class TaskMotion:
    """A task's solved or read motion, its frames per second and what was assumed in getting it."""

    task: Task
    motion: ResultFile
    fps: float
    notes: list[str] = field(default_factory=list)


def with_forces(problem_at: Callable[[int], Problem], forces: tuple[Force, ...]) -> Callable[[int], Problem]:
    """``problem_at`` with the forces acting at each frame added to the problem's loads."""
    if not forces:
        return problem_at
    from ..problem.problem import Problem
    from ..problem.specs import ExternalLoad

    built: dict[tuple, tuple[Problem, Problem]] = {}  # (id of the base problem, active forces) -> (base, loaded)

    def at(frame: int) -> Problem:
        problem = problem_at(frame)
        active = tuple(i for i, f in enumerate(forces) if f.acts_at(frame))
        if not active:
            return problem
        key = (id(problem), active)
        if key not in built:  # the base kept alongside, so its id is not reused while cached
            extra = [ExternalLoad(forces[i].hand, np.asarray(forces[i].force, dtype=float)) for i in active]
            spec = problem.spec.replace(loads=[*problem.spec.loads, *extra], comfort=problem.comfort)
            built[key] = (problem, Problem(problem.model, spec))
        return built[key][1]

    return at


def add_forces(motion: ResultFile, forces: tuple[Force, ...]) -> None:
    """Add the forces to the frames of a read result (at the hand's position in each frame they act at)."""
    for frame in motion.frames:
        extra = [(f.hand, np.array(frame.tcp_position[f.hand]), np.asarray(f.force, dtype=float))
                 for f in forces if f.acts_at(frame.number) and f.hand in frame.tcp_position]  # fmt: skip
        if extra:
            frame.loads = [*frame.loads, *extra]


def _solve(task: Task, path: Path) -> tuple[ResultFile, float, list[str]]:
    """Solve a task's scenario or operations scenario (with its forces) into ``path``: (motion, fps, notes)."""
    from ..io.result.write import ResultWriter
    from ..motion.frames import solve_frames

    notes: list[str] = []
    solved: Iterator
    if task.kind == "operations":
        from ..operations.generate import load_operations
        from ..operations.posing import Poser

        ops = load_operations(task.source)
        poser, s = Poser(ops.scenario.problem, ops.plan), ops.scenario
        at = with_forces(lambda f: poser.problem_at(ops.time_of(f)), task.forces)
        solved, scenario_path, fps = solve_frames(at, ops.frames, s.start, s.options, s.limits), s.path, ops.operate.fps
        notes += ops.notes
    else:
        from ..io.scenario.read import load_scenario

        s = load_scenario(task.source)
        at = with_forces(s.problem_at, task.forces)
        solved, scenario_path, fps = solve_frames(at, s.frames, s.start, s.options, s.limits), s.path, task.fps
    writer = ResultWriter(path, Path(scenario_path).resolve(), None)  # the scenario found from anywhere
    for frame, result in solved:
        writer.add(frame, result)
    return read_result(writer.close()), fps, notes


def motions_of(tasks: tuple[Task, ...], out_dir: Path, job_path: Path | None = None) -> list[TaskMotion]:
    """Every task's motion: a result file read (its forces added), a scenario solved into ``out_dir`` (motion.json
    for one task, motion_<n>.json for task n of several). A force acting at none of its task's frames is one
    UsageError line naming ``job_path`` and the force's key."""
    out = []
    for i, task in enumerate(tasks):
        if task.kind == "result":
            motion = read_result(task.source)
            add_forces(motion, task.forces)
            out.append(TaskMotion(task, motion, task.fps or 24.0, [RESULT_NOTE] if task.forces else []))
        else:
            name = "motion.json" if len(tasks) == 1 else f"motion_{i + 1}.json"
            out.append(TaskMotion(task, *_solve(task, out_dir / name)))
        numbers = [f.number for f in out[-1].motion.frames]
        for j, force in enumerate(task.forces):
            if numbers and not any(force.acts_at(n) for n in numbers):
                raise UsageError(f"{job_path}: tasks[{i}].forces[{j}].frames: expected frames of the task's motion "
                                 f"({numbers[0]}-{numbers[-1]}), got {list(force.frames or ())}")  # fmt: skip
    return out
