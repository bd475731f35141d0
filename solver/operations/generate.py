"""A scenario with ``[[operations]]`` -> a timed plan -> every frame solved by the motion solver
(:func:`solver.motion.frames.solve_frames`: balance with contact forces, per-frame limits, the swept check).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..io.scenario.read import read_toml, scenario_from_dict
from ..iteration.result import Result
from ..motion.frames import solve_frames
from ..problem.scenario import Scenario
from .handlers import plan
from .objects import WorkObject
from .posing import Poser
from .schema import Operate, read_objects, read_operate, read_operations
from .stance import StanceFinder
from .timeline import Plan

OWN = ("objects", "operations", "operate")  # the tables this package reads; the rest is a scenario's
FEET = [{"tcp": "foot_r", "position": [-0.083, 0.0, 0.0], "lock": ["x", "y", "z", "rx", "ry"], "support": True},
        {"tcp": "foot_l", "position": [0.083, 0.0, 0.0], "lock": ["x", "y", "z", "rx", "ry"], "support": True}]


@dataclass
class Job:
    """A read operations scenario: the scenario (its first frame), the plan, the frames, and what was assumed."""

    scenario: Scenario
    plan: Plan
    operate: Operate
    frames: list[int]
    notes: list[str]
    objects: dict[str, WorkObject]

    def time_of(self, frame: int) -> float:
        return (frame - self.operate.start) / self.operate.fps


def load_operations(path: str | Path) -> Job:
    """Read the scenario ``path`` and plan its operations; a bad one is one ScenarioError line."""
    path = Path(path)
    root = read_toml(path)
    objects, notes = read_objects(root, path.parent)
    operations = read_operations(root)
    operate = read_operate(root)
    data = {k: v for k, v in root.data.items() if k not in OWN}
    if "targets" not in data:  # the feet where they stand in the zero pose, as a person expects
        data["targets"] = FEET
        notes.append("no [[targets]]: the feet stand at the zero pose's stance (supports)")
    scenario = scenario_from_dict(data, path)
    model = scenario.model
    kin = model.forward(scenario.start[: model.n])
    hands = {}
    for tcp in ("hand_r", "hand_l"):
        rotation, position = kin.tcp_frame(model.tcp(tcp))
        hands[tcp] = (np.asarray(position), np.asarray(rotation))
    feet = {t.tcp: np.asarray(t.position, dtype=float) for t in scenario.problem.all_targets if t.support}
    obstacles = list(scenario.problem.spec.obstacles)
    timed = plan(operations, objects, hands, feet, obstacles, StanceFinder(scenario.problem))
    notes.extend(timed.notes)
    count = int(round(timed.duration * operate.fps)) + 1
    frames = list(range(operate.start, operate.start + count))
    return Job(scenario, timed, operate, frames, notes, objects)


def solve_operations(job: Job) -> Iterator[tuple[int, Result]]:
    """Every frame of ``job`` solved in order, as :func:`solver.motion.frames.solve_frames` yields them."""
    poser = Poser(job.scenario.problem, job.plan)
    s = job.scenario
    return solve_frames(lambda f: poser.problem_at(job.time_of(f)), job.frames, s.start, s.options,
                        s.limits)  # fmt: skip


def summary(job: Job, converged: dict[int, bool], took: float) -> list[str]:
    """Lines: per operation its start and end (s, frames) and converged frames; the cycle time."""
    lines = [f"{len(job.plan.spans)} operations, {len(job.frames)} frames at {job.operate.fps:g} fps"]
    lines.extend(f"note: {note}" for note in job.notes)
    for label, t0, t1 in job.plan.spans:
        first = job.operate.start + int(round(t0 * job.operate.fps))
        last = job.operate.start + int(round(t1 * job.operate.fps))
        mine = [f for f in range(first, last + 1) if f in converged]
        good = sum(converged[f] for f in mine)
        lines.append(f"{label}: {t0:.2f}-{t1:.2f} s (frames {first}-{last}), {good}/{len(mine)} converged")
    total = sum(converged.values())
    lines.append(f"cycle time {job.plan.duration:.2f} s (MTM-1 times); {total}/{len(converged)} frames converged; "
                 f"solved in {took:.1f} s")  # fmt: skip
    return lines
