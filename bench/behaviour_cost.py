"""What the behaviour model costs on the random benchmark's trials: each trial solved with it off and on in turn.

``python -m bench.behaviour_cost [SEEDS] [--span S] [--wall] [--no-rest]``: seeds 7000.. (each at every Max Dev
level, physics with and without reduction: 12 trials a seed), one process, one BLAS thread. ``--span`` sets
``solver.comfort.joint_range.POSTURE_SPAN`` (``--wall``: 0, the elbow's span ends at its 0-degree limit),
``--no-rest`` starts non-low solves from the zero pose instead of the rested elbows (docs/TUNING.md).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import solver.comfort.joint_range as joint_range
import solver.problem.problem as problem_module
from solver.comfort import BEHAVIOUR, STANDARD
from solver.io.scenario.bodies import load_body
from solver.iteration import solve
from solver.problem.problem import Problem
from solver.problem.starts import crouched_pose, low_reach
from solver.threads import single_threaded_blas

from .random_targets import CONFIGS, LEVELS, PRESET, draw_targets, trial_problem, workspace_box


def _crouch_only(problem):
    """The start rule without the rested elbows (the crouch for a low reach, else the zero pose)."""
    on = problem.comfort.weights is not None and problem.comfort.weights.get("trunk", 0.0) > 0.0
    return crouched_pose(problem.model) if on and low_reach(problem) else None


def main(argv: list[str] | None = None) -> None:
    p = argparse.ArgumentParser(prog="python -m bench.behaviour_cost")
    p.add_argument("seeds", type=int, nargs="?", default=10)
    p.add_argument("--span", type=float, default=None)
    p.add_argument("--wall", action="store_true")
    p.add_argument("--no-rest", action="store_true")
    args = p.parse_args(argv)
    if args.span is not None or args.wall:
        joint_range.POSTURE_SPAN = 0.0 if args.wall else args.span
    if args.no_rest:
        problem_module.behaviour_start = _crouch_only
    model = load_body(preset=PRESET)
    box = workspace_box(model)
    rows = {"off": [], "on": []}
    with single_threaded_blas():
        for seed in range(7000, 7000 + args.seeds):
            for level in LEVELS:
                for config in ("physics + reduction", "physics, no reduction"):
                    targets = draw_targets(model, box, level, seed)
                    base = trial_problem(model, targets, *CONFIGS[config])
                    for name, weights in (("off", STANDARD), ("on", BEHAVIOUR)):
                        problem = Problem(model, base.spec.replace(comfort_weights=weights, comfort=None))
                        t0 = time.perf_counter()
                        r = solve(problem)
                        rows[name].append((r.converged, r.iterations, time.perf_counter() - t0))
    print("| model | converged | iterations (sum) | x off | median ms | p95 ms |\n|---|---:|---:|---:|---:|---:|")
    off = sum(r[1] for r in rows["off"])
    for name, got in rows.items():
        a = np.array(got, dtype=float)
        print(f"| {name} | {int(a[:, 0].sum())}/{len(a)} | {int(a[:, 1].sum())} | {a[:, 1].sum() / off:.2f} | "
              f"{1000 * np.median(a[:, 2]):.1f} | {1000 * np.percentile(a[:, 2], 95):.1f} |")


if __name__ == "__main__":
    main()
