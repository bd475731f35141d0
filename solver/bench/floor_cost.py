"""What the floor costs: the random benchmark's trials (both physics settings, every level) solved without and with
the floor's clearance rows. Prints successes, iterations and solve time of each.

    python -m solver.bench.floor_cost [SEEDS_PER_LEVEL]
"""

from __future__ import annotations

import sys
import time

from ..bodies import load_body
from ..iteration import solve
from ..problem import Problem
from . import random_targets as rt


def run(seeds: int = 12) -> str:
    model = load_body(preset=rt.PRESET)
    box = rt.workspace_box(model)
    totals = {False: [0, 0, 0.0, 0], True: [0, 0, 0.0, 0]}
    for config in ("physics + reduction", "physics, no reduction"):
        balance, groups = rt.CONFIGS[config]
        for level in range(len(rt.LEVELS)):
            for seed in range(seeds):
                plain = rt.trial_problem(model, rt.draw_targets(model, box, rt.LEVELS[level], 1000 + seed), balance,
                                         groups)  # fmt: skip
                floored = Problem(model, plain.all_targets, balance=balance, reduction=groups)
                assert floored.floor_constraint is not None and plain.floor_constraint is None
                for with_floor, problem in ((False, plain), (True, floored)):
                    t0 = time.perf_counter()
                    result = solve(problem)
                    row = totals[with_floor]
                    row[0] += result.converged
                    row[1] += result.iterations
                    row[2] += time.perf_counter() - t0
                    row[3] += 1
    lines = []
    for with_floor, (ok, iterations, seconds, n) in totals.items():
        lines.append(f"{'with' if with_floor else 'without'} the floor: {ok}/{n} converged, {iterations} iterations, "
                     f"{seconds / n * 1e3:.1f} ms per solve")  # fmt: skip
    return "\n".join(lines)


if __name__ == "__main__":
    print(run(*(int(a) for a in sys.argv[1:2])))
