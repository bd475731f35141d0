"""A/B of the compiled kernels against the NumPy path, in one process, interleaved: the random benchmark's trials
(thesis §6.1.2, physics + reduction), comfort on and off, and the live drag's re-solves.

    python -m bench.kernels_ab [TRIALS_PER_LEVEL]

Prints per setting the median solve time of each path, their ratio, how many solves reached the same x (1e-9)
and the iterations and successes of each (the same, unless a trial's iterates are chaotic to rounding).
"""

from __future__ import annotations

import sys
import time

import numpy as np

from solver import SolverOptions, kernels, solve
from solver.io.scenario.bodies import load_body

from . import one_core
from . import random_targets as rt


def random_problems(per_level: int) -> list:
    """The random benchmark's problems, seeds 7000.. at each Max Dev level."""
    model = load_body(preset=rt.PRESET)
    box = rt.workspace_box(model)
    balance, groups = rt.CONFIGS["physics + reduction"]
    return [
        rt.trial_problem(model, rt.draw_targets(model, box, level, 7000 + seed), balance, groups)
        for level in rt.LEVELS
        for seed in range(per_level)
    ]


def compare(problems: list, options: SolverOptions, repeats: int = 2) -> dict:
    """Median s of each path (False = NumPy, True = compiled), interleaved in alternating order, and the results."""
    times: dict[bool, list[float]] = {False: [], True: []}
    results = {}
    for flag in (False, True):  # compile / load the cache, warm both
        with kernels.using(flag):
            solve(problems[0], options=options)
    for rep in range(repeats):
        for i, problem in enumerate(problems):
            for flag in (False, True) if (i + rep) % 2 == 0 else (True, False):
                with kernels.using(flag):
                    start = time.perf_counter()
                    results[flag, i] = solve(problem, options=options)
                    times[flag].append(time.perf_counter() - start)
    n = len(problems)
    return {
        "numpy_ms": float(np.median(times[False])) * 1e3,
        "compiled_ms": float(np.median(times[True])) * 1e3,
        "same": sum(np.allclose(results[False, i].x, results[True, i].x, rtol=0, atol=1e-9) for i in range(n)),
        "max_dx": max(float(np.abs(results[False, i].x - results[True, i].x).max()) for i in range(n)),
        "iterations": [sum(results[f, i].iterations for i in range(n)) for f in (False, True)],
        "converged": [sum(bool(results[f, i].converged) for i in range(n)) for f in (False, True)],
        "count": n,
    }


def main(argv: list[str]) -> None:
    one_core("bench.kernels_ab")
    per_level = int(argv[0]) if argv else 6
    print(kernels.status())
    problems = random_problems(per_level)
    for label, options in (("comfort on", SolverOptions()), ("comfort off", SolverOptions(optimize_comfort=False))):
        r = compare(problems, options)
        print(
            f"random, {label}: NumPy {r['numpy_ms']:.2f} ms, compiled {r['compiled_ms']:.2f} ms, "
            f"ratio {r['compiled_ms'] / r['numpy_ms']:.3f}; same x {r['same']}/{r['count']} (max |dx| "
            f"{r['max_dx']:.1e}); iterations {r['iterations']}, converged {r['converged']}"
        )


if __name__ == "__main__":
    main(sys.argv[1:])
