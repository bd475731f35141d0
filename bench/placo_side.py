"""Issue 37's table: ours (comfort on, comfort off) and placo on the same random trials, side by side in one run.

Each trial (the random benchmark's targets, ``SEEDS`` seeds at each of its six Max Dev levels) is solved by the
three sides in turn, the order rotating from trial to trial, on one core with one BLAS thread, so that a load from
other jobs falls on all three alike. Ours: physics + reduction with and without comfort (``SolverOptions``); placo:
``bench.peers.placo_peer`` (its own solve and kinematics updates timed, on the no-reduction problem it needs).
Success is judged by our constraint function for all three. placo is a benchmark extra (requirements-bench.txt):

    python3 -m venv /work/venv-bench
    /work/venv-bench/bin/pip install numpy==1.26.4 scipy==1.15.3
    /work/venv-bench/bin/pip install --no-deps -r requirements-bench.txt
    /work/venv-bench/bin/python -m bench.placo_side [SEEDS [FIELD=VALUE,...]]   # 20: 120 trials
    # with knobs of Tuning: a fourth side, ours with comfort on and those knobs (an A/B of an algorithmic change)
"""

from __future__ import annotations

import sys
import time

import numpy as np

from . import one_core

SIDES = ("ours, comfort on", "ours, comfort off", "placo")


def run(seeds: int = 20, knobs: str = "") -> str:
    """Median ms and successes per side, and the ratios placo / ours of the medians; Markdown table rows."""
    from solver.iteration import TUNING, solve
    from solver.options import SolverOptions

    from . import random_targets as rt
    from .peers import placo_available, placo_peer

    if not placo_available():
        return "placo is not installed (requirements-bench.txt): nothing to compare"
    model = rt.load_body(preset=rt.PRESET)
    box = rt.workspace_box(model)
    balance, groups = rt.CONFIGS["physics + reduction"]
    from .cold_scenarios import replace_tuning

    knob_side = f"ours, comfort on, {knobs}"
    sides = (*SIDES, knob_side) if knobs else SIDES
    tunings = {knob_side: replace_tuning(TUNING, knobs, "-")} if knobs else {}
    times: dict[str, list[float]] = {s: [] for s in sides}
    good = dict.fromkeys(sides, 0)
    steps: dict[str, list[int]] = {s: [] for s in sides}  # iterations (placo: QP steps)
    trial = 0
    for level in range(len(rt.LEVELS)):
        for seed in range(seeds):
            targets = rt.draw_targets(model, box, rt.LEVELS[level], 7000 + seed)
            order = sides[trial % len(sides) :] + sides[: trial % len(sides)]
            trial += 1
            for side in order:
                if side == "placo":
                    peer = placo_peer(rt.trial_problem(model, targets, True, ()))
                    times[side].append(peer.time_s)
                    good[side] += bool(peer.converged)
                    steps[side].append(peer.iterations)
                    continue
                problem = rt.trial_problem(model, targets, balance, groups)
                options = SolverOptions(optimize_comfort=side != "ours, comfort off")
                t0 = time.perf_counter()
                result = solve(problem, options=options, tuning=tunings.get(side, TUNING))
                times[side].append(time.perf_counter() - t0)
                good[side] += bool(result.converged)
                steps[side].append(result.iterations)
    median = {s: float(np.median(times[s])) * 1e3 for s in sides}
    lines = ["| | median ms | p95 ms | succeeded | iterations (median, mean) | placo / this (medians) |",
             "|---|---:|---:|---:|---:|---:|"]  # fmt: skip
    for s in sides:
        p95 = float(np.percentile(times[s], 95)) * 1e3
        its = f"{np.median(steps[s]):.0f}, {np.mean(steps[s]):.1f}"
        lines.append(f"| {s} | {median[s]:.1f} | {p95:.1f} | {good[s]}/{trial} | {its} | "
                     f"{median['placo'] / median[s]:.2f} |")  # fmt: skip
    return "\n".join(lines)


if __name__ == "__main__":
    one_core("bench.placo_side")
    print(run(*map(int, sys.argv[1:2]), *sys.argv[2:3]))
