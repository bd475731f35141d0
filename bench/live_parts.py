"""Where a live re-solve's trial evaluation and linearisation spend their time, part by part, without a profiler
(cProfile's per-call overhead inflates the many small NumPy calls, e.g. np.cross 3x).

At the poses of ``bench.live_drag``'s re-solves (the box lift, floor and self-collision on, the default comfort),
each pose and a point 1e-3 away (a trial's distance) are evaluated from a fresh ``State`` stage by stage, as a
solve does: forward kinematics, statics, every constraint's error, every comfort term's cost (a trial point), then
every constraint's Jacobian rows and every comfort term's derivatives (a linearisation at the same point, its
caches warm). Each stage is timed with ``perf_counter`` around it; the median over the points, best of the
repeats. One core, one BLAS thread.

    python -m bench.live_parts [DRAGS]      # default 20 drags: 40 points
"""

from __future__ import annotations

import sys
import time
from collections import defaultdict

import numpy as np

from . import one_core


def _stages(problem, v: np.ndarray) -> list[tuple[str, float]]:
    """(label, seconds) of each stage at ``v`` from a fresh state."""
    out = []
    t = time.perf_counter()

    def mark(label: str) -> None:
        nonlocal t
        now = time.perf_counter()
        out.append((label, now - t))
        t = now

    state = problem.state(v)
    state.kin  # noqa: B018 (computed here, cached on the state)
    mark("trial: forward kinematics")
    state.statics  # noqa: B018
    mark("trial: statics (totals)")
    for c in problem.constraints:
        c.error(state)
        mark(f"trial: error, {type(c).__name__}")
    for weight, term in problem.comfort.terms:
        if weight:
            term.cost(state)
            mark(f"trial: comfort cost, {term.name}")
    for c in problem.constraints:
        c.jacobian_rows(state)
        mark(f"linearisation: Jacobian rows, {type(c).__name__}")
    for weight, term in problem.comfort.terms:
        if weight:
            term.derivatives(state, weight)
            mark(f"linearisation: comfort derivatives, {term.name}")
    problem.live_jacobian(state)
    mark("linearisation: live_jacobian (again, with the rows above cached where they are)")
    return out


def run(drags: int = 20, repeats: int = 5) -> str:
    import solver

    from .live_drag import cases

    points = []
    for problem, start, options in cases(solver, drags)[0]:
        v = problem.to_variables(solver.solve(problem, start, options).x)
        points += [(problem, v), (problem, v + 1e-3 * np.sin(np.arange(len(v))))]
    best: dict[str, float] = {}
    for _ in range(repeats):
        got = defaultdict(list)
        for problem, v in points:
            for label, seconds in _stages(problem, v):
                got[label].append(seconds)
        for label, values in got.items():
            best[label] = min(best.get(label, np.inf), float(np.median(values)))
    lines = ["| stage | median us |", "|---|---:|"]
    lines += [f"| {label} | {seconds * 1e6:.1f} |" for label, seconds in best.items()]
    trial = sum(s for k, s in best.items() if k.startswith("trial"))
    lin = sum(s for k, s in best.items() if k.startswith("linearisation") and "again" not in k)
    lines.append(f"| a trial point, all stages | {trial * 1e6:.1f} |")
    lines.append(f"| a linearisation's rows and comfort derivatives | {lin * 1e6:.1f} |")
    return "\n".join(lines)


if __name__ == "__main__":
    one_core("bench.live_parts")
    print(run(*map(int, sys.argv[1:2])))
