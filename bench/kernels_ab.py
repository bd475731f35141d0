"""A/B of the compiled kernels against the NumPy path, in one process, interleaved: the random benchmark's trials
(thesis §6.1.2, physics + reduction), comfort on and off; Blender Live's re-solves after a 5 cm drag (box lift,
floor and self-collision); and every shipped single-pose scenario, cold from its start pose.

    python -m bench.kernels_ab [TRIALS_PER_LEVEL [DRAGS [REPEATS]]]      # default 6, 100, 5

Prints per case the median solve time of each path, their ratio, how many solves reached the same x (1e-9) and
the iterations and successes of each (the same, unless a trial's iterates are chaotic to rounding).
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

import solver
from solver import SolverOptions, kernels
from solver.io.scenario.bodies import load_body

from . import one_core
from . import random_targets as rt
from .cold_scenarios import single_pose_scenarios
from .live_drag import cases as live_cases

PRESETS = Path(__file__).resolve().parents[1] / "presets" / "scenarios"


def random_cases(per_level: int, options: SolverOptions) -> list[tuple]:
    """The random benchmark's (problem, start, options), seeds 7000.. at each Max Dev level."""
    model = load_body(preset=rt.PRESET)
    box = rt.workspace_box(model)
    balance, groups = rt.CONFIGS["physics + reduction"]
    return [
        (rt.trial_problem(model, rt.draw_targets(model, box, level, 7000 + seed), balance, groups), None, options)
        for level in rt.LEVELS
        for seed in range(per_level)
    ]


def compare(cases: list[tuple], repeats: int = 2) -> dict:
    """Solve times (s) of each path (False = NumPy, True = compiled) per case, interleaved in alternating order."""
    times: dict[bool, list[list[float]]] = {False: [[] for _ in cases], True: [[] for _ in cases]}
    results = {}
    for flag in (False, True):  # compile / load the cache, warm both
        with kernels.using(flag):
            solver.solve(*cases[0])
    for rep in range(repeats):
        for i, case in enumerate(cases):
            for flag in (False, True) if (i + rep) % 2 == 0 else (True, False):
                with kernels.using(flag):
                    start = time.perf_counter()
                    results[flag, i] = solver.solve(*case)
                    times[flag][i].append(time.perf_counter() - start)
    n = len(cases)
    return {
        "times": times,
        "numpy_ms": float(np.median(times[False])) * 1e3,
        "compiled_ms": float(np.median(times[True])) * 1e3,
        "same": sum(np.allclose(results[False, i].x, results[True, i].x, rtol=0, atol=1e-9) for i in range(n)),
        "max_dx": max(float(np.abs(results[False, i].x - results[True, i].x).max()) for i in range(n)),
        "iterations": [sum(results[f, i].iterations for i in range(n)) for f in (False, True)],
        "converged": [sum(bool(results[f, i].converged) for i in range(n)) for f in (False, True)],
        "count": n,
    }


def line(label: str, r: dict) -> str:
    return (
        f"{label}: NumPy {r['numpy_ms']:.2f} ms, compiled {r['compiled_ms']:.2f} ms (medians), ratio "
        f"{r['compiled_ms'] / r['numpy_ms']:.3f}; same x {r['same']}/{r['count']} (max |dx| {r['max_dx']:.1e}); "
        f"iterations {r['iterations']}, converged {r['converged']}"
    )


def main(argv: list[str]) -> None:
    one_core("bench.kernels_ab")
    defaults = [6, 100, 5]
    per_level, drags, repeats = [int(a) for a in argv[:3]] + defaults[len(argv[:3]) :]
    print(kernels.status())
    for label, options in (("comfort on", SolverOptions()), ("comfort off", SolverOptions(optimize_comfort=False))):
        print(line(f"random benchmark, {label}", compare(random_cases(per_level, options))))
    print(line(f"live drag, {drags} drags", compare(live_cases(solver, drags)[0], repeats=1)))
    names = single_pose_scenarios()
    loaded = [solver.load_scenario(PRESETS / f"{name}.toml") for name in names]
    r = compare([(sc.problem, sc.start, sc.options) for sc in loaded], repeats=repeats)
    print(line(f"cold single-pose scenarios ({len(names)}, {repeats} each)", r))
    for name, numpy_t, compiled_t in zip(names, r["times"][False], r["times"][True], strict=True):
        print(f"  {name}: NumPy {np.median(numpy_t) * 1e3:.1f} ms, compiled {np.median(compiled_t) * 1e3:.1f} ms")


if __name__ == "__main__":
    main(sys.argv[1:])
