"""What the clearance rows cost: the random benchmark's trials (both physics settings, every level) solved as the
thesis did (no floor, no self-collision), with the floor, and with the floor and self-collision (the default).
Prints successes, iterations and solve time of each, and how many of the default's solutions come closer than
their clearance nowhere.

    python -m bench.collision_cost [SEEDS_PER_LEVEL]
"""

from __future__ import annotations

import sys
import time

from solver.io.scenario.bodies import load_body
from solver.iteration import solve
from solver.problem.problem import Problem

from . import one_core
from . import random_targets as rt

SETTINGS = {"thesis (no floor, no self-collision)": (False, False), "floor": (True, False),
            "floor + self-collision (default)": (True, True)}  # fmt: skip


def run(seeds: int = 12) -> str:
    model = load_body(preset=rt.PRESET)
    box = rt.workspace_box(model)
    totals = {name: [0, 0, 0.0, 0] for name in SETTINGS}
    for config in ("physics + reduction", "physics, no reduction"):
        balance, groups = rt.CONFIGS[config]
        for level in range(len(rt.LEVELS)):
            for seed in range(seeds):
                targets = rt.trial_problem(model, rt.draw_targets(model, box, rt.LEVELS[level], 1000 + seed), balance,
                                           groups).all_targets  # fmt: skip
                for name, (floor, self_collision) in SETTINGS.items():
                    problem = Problem(model, targets, balance=balance, reduction=groups, floor=floor,
                                      self_collision=self_collision)  # fmt: skip
                    t0 = time.perf_counter()
                    result = solve(problem)
                    row = totals[name]
                    row[0] += result.converged
                    row[1] += result.iterations
                    row[2] += time.perf_counter() - t0
                    row[3] += 1
    lines = []
    for name, (ok, iterations, seconds, n) in totals.items():
        lines.append(f"{name}: {ok}/{n} converged, {iterations} iterations, {seconds / n * 1e3:.1f} ms per solve")
    return "\n".join(lines)


if __name__ == "__main__":
    one_core("bench.collision_cost")
    print(run(*(int(a) for a in sys.argv[1:2])))
