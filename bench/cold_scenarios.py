"""Cold solves of the shipped single-pose scenarios against issue 37's 50 ms target, and where their iterations go.

Every scenario of presets/scenarios without a motion is solved from its own start pose ``REPEATS`` times (the
scenarios taking turns), on one core with one BLAS thread; per scenario the median and p95 time, the iterations,
and what a solve spent beyond one trial point per iteration, counted by wrapping (not changing) the solver's
functions: trial evaluations, line searches that cut the step back (an accepted step length below 1, or the
comfort part dropped) or found nothing, the evaluations those cut-backs cost, and attempts beyond the first
(restarts from another pose, the ranked re-solve of an unmet problem).

    python -m bench.cold_scenarios [REPEATS [FIELD=VALUE,...]]   # default 10; knobs of Tuning changed
"""

from __future__ import annotations

import sys
import time
from collections import Counter
from contextlib import contextmanager
from pathlib import Path

import numpy as np

from . import one_core

PRESETS = Path(__file__).resolve().parents[1] / "presets" / "scenarios"
TARGET_MS = 50.0  # issue 37: each shipped single-pose scenario's cold solve, median


def single_pose_scenarios() -> list[str]:
    """Names of the shipped scenarios that are one pose (no [motion] / key frames)."""
    import tomllib

    names = []
    for path in sorted(PRESETS.glob("*.toml")):
        data = tomllib.loads(path.read_text(encoding="utf-8"))
        if not any(key in data for key in ("motion", "frames", "keys")):
            names.append(path.stem)
    return names


@contextmanager
def counting(count: Counter):
    """Within: the evaluator, the line search and the attempt wrapped so that ``count`` tallies what solves do
    (the solver's own functions again afterwards)."""
    from solver.iteration import line_search, phases, trial

    evaluate, search, attempt = trial.Evaluator.__call__, line_search.LineSearch.run, phases.attempt

    def counted_evaluate(self, x):
        count["evaluations"] += 1
        return evaluate(self, x)

    def counted_search(self):
        before = count["evaluations"]
        outcome = search(self)
        spent = count["evaluations"] - before
        count["line searches"] += 1
        first = self.attempts()[0][0]  # with comfort first, when the step predicts a gain
        if outcome.trial is None:
            count["found nothing"] += 1
            count["evaluations in cut-backs"] += spent
        elif outcome.alpha < 1.0 or outcome.with_comfort != first:
            count["cut back"] += 1
            count["evaluations in cut-backs"] += spent - 1  # the accepted trial itself is no waste
            count["cut back near" if self.near else "cut back far"] += 1
            count["comfort dropped"] += outcome.with_comfort != first
        return outcome

    def counted_attempt(*args, **kwargs):
        count["attempts"] += 1
        return attempt(*args, **kwargs)

    trial.Evaluator.__call__ = counted_evaluate
    line_search.LineSearch.run = counted_search
    phases.attempt = counted_attempt
    try:
        yield count
    finally:
        trial.Evaluator.__call__, line_search.LineSearch.run, phases.attempt = evaluate, search, attempt


def replace_tuning(tuning, field: str, value: str):
    """``tuning`` with ``field`` = ``value`` (a Python literal), or with each ``F=V`` of a comma-separated ``field``
    when ``value`` is ``-``."""
    import ast
    from dataclasses import replace

    pairs = [item.split("=", 1) for item in field.split(",")] if value == "-" else [(field, value)]
    return replace(tuning, **{name: ast.literal_eval(literal) for name, literal in pairs})


def run(repeats: int = 10, knobs: str = "") -> str:
    """The table; ``knobs``: ``FIELD=VALUE,...`` of ``Tuning`` to solve with instead of the default."""
    import solver
    from solver.iteration import TUNING

    tuning = replace_tuning(TUNING, knobs, "-") if knobs else TUNING

    names = single_pose_scenarios()
    loaded = {name: solver.load_scenario(PRESETS / f"{name}.toml") for name in names}
    per: dict[str, list[tuple[float, int, bool, Counter]]] = {name: [] for name in names}
    with counting(Counter()) as count:
        for _ in range(repeats):
            for name in names:
                sc = loaded[name]
                count.clear()
                t0 = time.perf_counter()
                result = solver.solve(sc.problem, sc.start, sc.options, tuning)
                per[name].append((time.perf_counter() - t0, result.iterations, bool(result.converged), Counter(count)))
    lines = [
        "| scenario | median ms | p95 ms | <= 50 ms | iterations | converged | evaluations | line searches cut back "
        "/ found nothing | of those cut back: near / far / comfort dropped | evaluations in cut-backs | attempts |",
        "|---|---:|---:|---|---:|---:|---:|---:|---|---:|---:|",
    ]
    for name in names:
        ms = np.array([t for t, *_ in per[name]]) * 1e3
        counts = [c for *_, c in per[name]]

        def mean(key: str, counts=counts) -> float:
            return float(np.mean([c[key] for c in counts]))

        iters = np.median([it for _, it, _, _ in per[name]])
        good = sum(ok for _, _, ok, _ in per[name])
        met = "yes" if np.median(ms) <= TARGET_MS else "**no**"
        lines.append(
            f"| {name} | {np.median(ms):.1f} | {np.percentile(ms, 95):.1f} | {met} | {iters:.0f} | {good}/{repeats} | "
            f"{mean('evaluations'):.1f} | {mean('cut back'):.1f} / {mean('found nothing'):.1f} | "
            f"{mean('cut back near'):.1f} / {mean('cut back far'):.1f} / {mean('comfort dropped'):.1f} | "
            f"{mean('evaluations in cut-backs'):.1f} | {mean('attempts'):.1f} |"
        )
    return "\n".join(lines)


if __name__ == "__main__":
    one_core("bench.cold_scenarios")
    print(run(*map(int, sys.argv[1:2]), *sys.argv[2:3]))
