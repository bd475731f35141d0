"""A/B of a refactor: record the random benchmark's per-trial iterates, compare another version's against them, and
time two versions in one process, interleaved.

    python -m bench.same_iterates record OUT.npz            # before the change
    python -m bench.same_iterates compare OUT.npz           # after: same iterations, success and x?
    python -m bench.same_iterates speed OLD_ROOT             # OLD_ROOT/solver_old: a copy of the old package
    python -m bench.same_iterates live OLD_ROOT [DRAGS [TRUNK]]  # the same for bench.live_drag's re-solves
    python -m bench.same_iterates scenarios OLD_ROOT [REPEATS]  # ... and for the shipped scenarios, cold
    python -m bench.same_iterates tuning FIELD VALUE [COUNT] # an algorithmic knob of Tuning, side by side
"""

from __future__ import annotations

import importlib
import sys
import time
from pathlib import Path
from types import ModuleType

import numpy as np

from . import one_core

PRESETS = Path(__file__).resolve().parents[1] / "presets"
SEEDS = (24, 12)  # trials per level: the four benchmark settings, then comfort off


def _first_module(*names: str) -> ModuleType:
    """The first of ``names`` that imports (a version from before the benchmarks left the package has them inside)."""
    for name in names[:-1]:
        try:
            return importlib.import_module(name)
        except ModuleNotFoundError:
            continue
    return importlib.import_module(names[-1])


def _package(name: str) -> tuple[ModuleType, ModuleType, object]:
    pkg = importlib.import_module(name)
    trials = _first_module(f"{name}.bench.random_targets", "bench.random_targets")
    model = _first_module(f"{name}.bodies", f"{name}.io.scenario.bodies").load_body(preset=trials.PRESET)
    return pkg, trials, model


def iterates(name: str = "solver") -> dict[str, np.ndarray]:
    """Per trial: [iterations, converged, comfort, *x], keyed setting_level_seed."""
    pkg, rt, model = _package(name)
    box = rt.workspace_box(model)
    out = {}
    for index, config in enumerate([*rt.CONFIGS, rt.NO_COMFORT]):
        balance, groups = rt.CONFIGS["physics + reduction" if config == rt.NO_COMFORT else config]
        options = pkg.SolverOptions(optimize_comfort=config != rt.NO_COMFORT)
        for level in range(len(rt.LEVELS)):
            for seed in range(SEEDS[index == len(rt.CONFIGS)]):
                problem = rt.trial_problem(
                    model, rt.draw_targets(model, box, rt.LEVELS[level], 1000 + seed), balance, groups
                )
                r = pkg.solve(problem, options=options)
                out[f"{index}_{level}_{seed}"] = np.concatenate([[r.iterations, r.converged, r.comfort], r.x])
    return out


def compare(path: str) -> str:
    ref, now = np.load(path), iterates()
    same_it = sum(ref[k][0] == v[0] for k, v in now.items())
    same_ok = sum(ref[k][1] == v[1] for k, v in now.items())
    dx = max(float(np.max(np.abs(ref[k][3:] - v[3:]))) for k, v in now.items())
    ok_now, ok_ref = sum(v[1] for v in now.values()), sum(ref[k][1] for k in now)
    both = [k for k, v in now.items() if v[1] and ref[k][1]]
    it_ref, it_now = sum(ref[k][0] for k in both), sum(now[k][0] for k in both)
    comfort = np.array([now[k][2] - ref[k][2] for k in both])
    return (f"{len(now)} trials: same iterations {same_it}, same success {same_ok}, max |dx| {dx:.3g}, "
            f"successes {ok_now:.0f} (before {ok_ref:.0f}); converged in both: iterations {it_now:.0f} (before "
            f"{it_ref:.0f}), comfort higher in {int((comfort > 1e-9).sum())}, lower in {int((comfort < -1e-9).sum())}, "
            f"mean change {comfort.mean():+.4f}")  # fmt: skip


def speed(old_root: str, repeats: int = 2) -> str:
    """Solve time of ``solver_old`` (under ``old_root``) and this tree on the same trials, alternating order."""
    sys.path.insert(0, old_root)
    sides = {name: _package(name) for name in ("solver_old", "solver")}
    times: dict[str, list[float]] = {name: [] for name in sides}
    for repeat in range(repeats):
        for config in ("physics + reduction", "physics, no reduction"):
            for level in range(6):
                for seed in range(8):
                    order = list(sides) if (seed + repeat) % 2 == 0 else list(sides)[::-1]
                    for name in order:
                        pkg, rt, model = sides[name]
                        balance, groups = rt.CONFIGS[config]
                        targets = rt.draw_targets(model, rt.workspace_box(model), rt.LEVELS[level], 7000 + seed)
                        problem = rt.trial_problem(model, targets, balance, groups)
                        t0 = time.perf_counter()
                        pkg.solve(problem)
                        times[name].append(time.perf_counter() - t0)
    old, new = np.array(times["solver_old"]), np.array(times["solver"])
    return (f"{len(old)} solves each, interleaved: before median {np.median(old) * 1e3:.1f} ms, p95 "
            f"{np.percentile(old, 95) * 1e3:.1f} ms; after median {np.median(new) * 1e3:.1f} ms, p95 "
            f"{np.percentile(new, 95) * 1e3:.1f} ms; per-solve ratio after/before: median {np.median(new / old):.3f}, "
            f"total {new.sum() / old.sum():.3f}")  # fmt: skip


def _interleaved(old_root: str, make_cases, label: str) -> str:
    """Solve time of ``solver_old`` (under ``old_root``) and this tree on the cases ``make_cases(package)`` gives
    (the same for both: a list of (problem, start, options)), alternating order; iterations and successes too."""
    sys.path.insert(0, old_root)
    packages = {name: importlib.import_module(name) for name in ("solver_old", "solver")}
    sides = {name: make_cases(pkg) for name, pkg in packages.items()}
    times: dict[str, list[float]] = {name: [] for name in sides}
    iterations, good = dict.fromkeys(sides, 0), dict.fromkeys(sides, 0)
    ends: dict[str, list[np.ndarray]] = {name: [] for name in sides}  # the poses reached: the same iterates?
    count = len(sides["solver"])
    for i in range(count):
        for name in list(sides) if i % 2 == 0 else list(sides)[::-1]:
            problem, start, options = sides[name][i]
            t0 = time.perf_counter()
            result = packages[name].solve(problem, start, options)
            times[name].append(time.perf_counter() - t0)
            iterations[name] += result.iterations
            good[name] += bool(result.converged)
            ends[name].append(result.x)

    def side(name: str) -> str:
        ms = np.array(times[name]) * 1e3
        return (f"median {np.median(ms):.2f} ms, p95 {np.percentile(ms, 95):.2f} ms, {iterations[name] / count:.2f} "
                f"iterations, converged {good[name]}")  # fmt: skip

    ratio = np.array(times["solver"]) / np.array(times["solver_old"])
    dx = max((float(np.max(np.abs(a - b), initial=0.0)) for a, b in zip(*ends.values(), strict=True)), default=0.0)
    return (f"{count} {label} each, interleaved: before {side('solver_old')}; after {side('solver')}; per-solve ratio "
            f"after/before: median {np.median(ratio):.3f}; max |dx| of the poses reached {dx:.3g}")  # fmt: skip


def live(old_root: str, drags: int = 200, trunk: float | None = None) -> str:
    """bench.live_drag's re-solves (the same drags for both; ``trunk``: the comfort's trunk weight instead)."""
    from .live_drag import cases

    label = "drags" if trunk is None else f"drags (trunk = {trunk:g})"
    return _interleaved(old_root, lambda pkg: cases(pkg, drags, trunk)[0], label)


def scenarios(old_root: str, repeats: int = 10) -> str:
    """bench.scenarios' shipped single-pose scenarios, cold from their start poses, ``repeats`` times each."""
    from .scenarios import SCENARIOS

    def make(pkg) -> list:
        loaded = [pkg.load_scenario(PRESETS / "scenarios" / f"{name}.toml") for name in SCENARIOS]
        return [(sc.problem, sc.start, sc.options) for sc in loaded] * repeats

    return _interleaved(old_root, make, f"cold solves of {', '.join(SCENARIOS)}")


def tuning(field: str, value: str, count: int = 100) -> str:
    """This tree with ``TUNING`` (A) and with its ``field`` set to ``value`` (B, a Python literal; several knobs:
    ``FIELD=VALUE,FIELD=VALUE`` as field and ``-`` as value), interleaved: live drags, random-benchmark trials
    (physics + reduction, comfort on, ``count // 10`` seeds per level) and every shipped single-pose scenario, cold
    (``count // 20`` repeats); per side the median time, iterations, trial points, successes and mean comfort, and
    in how many B's comfort beat A's. An algorithmic change alters the iterates on purpose: this is its record."""
    from collections import Counter

    import solver
    from solver.iteration import TUNING

    from .cold_scenarios import counting, replace_tuning, single_pose_scenarios
    from .live_drag import cases

    sides = {"A": TUNING, "B": replace_tuning(TUNING, field, value)}
    rt = importlib.import_module("bench.random_targets")
    model = rt.load_body(preset=rt.PRESET)
    balance, groups = rt.CONFIGS["physics + reduction"]
    box = rt.workspace_box(model)
    loaded = [solver.load_scenario(PRESETS / "scenarios" / f"{name}.toml") for name in single_pose_scenarios()]
    suites = {
        "live drags": cases(solver, count)[0],
        "random trials": [(rt.trial_problem(model, rt.draw_targets(model, box, rt.LEVELS[level], 7000 + seed),
                                            balance, groups), None, solver.SolverOptions())
                          for level in range(len(rt.LEVELS)) for seed in range(max(count // 10, 1))],
        "cold scenarios": [(sc.problem, sc.start, sc.options) for sc in loaded] * max(count // 20, 1),
    }  # fmt: skip
    lines = [f"A: TUNING; B: {field} = {value}"]
    with counting(Counter()) as tally:
        for label, items in suites.items():
            got = {k: ([], [], [], [], []) for k in sides}  # times, iterations, converged, comfort, trial points
            for i, (problem, start, options) in enumerate(items):
                for k in list(sides) if i % 2 == 0 else list(sides)[::-1]:
                    tally.clear()
                    t0 = time.perf_counter()
                    result = solver.solve(problem, start, options, sides[k])
                    for store, v in zip(got[k], (time.perf_counter() - t0, result.iterations, result.converged,
                                                 result.comfort, tally["evaluations"]), strict=True):  # fmt: skip
                        store.append(v)
            for k in sides:
                t, it, ok, comfort, points = got[k]
                lines.append(f"{label} {k}: median {np.median(t) * 1e3:.2f} ms, total {np.sum(t):.2f} s, iterations "
                             f"{sum(it)}, trial points {sum(points)}, converged {sum(ok)}/{len(items)}, mean comfort "
                             f"{np.mean(comfort):.4f}")  # fmt: skip
            both = np.array(got["A"][2], dtype=bool) & np.array(got["B"][2], dtype=bool)
            h_a, h_b = np.array(got["A"][3])[both], np.array(got["B"][3])[both]
            diff = h_b - h_a
            rel = diff / np.maximum(np.abs(h_a), 1e-9)
            ratio = np.median(np.array(got["B"][0]) / np.array(got["A"][0]))
            total = np.sum(got["B"][0]) / np.sum(got["A"][0])
            worst = 100 * min(rel.min(initial=0.0), 0.0)
            lines.append(f"{label}: B/A time median {ratio:.3f}, total {total:.3f}; "
                         f"converged in both {int(both.sum())}: comfort B higher in {int((diff > 1e-9).sum())}, lower "
                         f"in {int((diff < -1e-9).sum())} (by more than 1 %: {int((rel < -0.01).sum())}, largest "
                         f"{worst:.1f} %), mean A {h_a.mean():.4f}, B {h_b.mean():.4f}")  # fmt: skip
    return "\n".join(lines)


def main(argv: list[str]) -> None:
    # NumPy is loaded already (bench/__init__), so setting the variable here would be ignored: start again with one
    # BLAS thread. A record and a compare with different thread counts differ by rounding (measured: 1 of 648
    # trials took another iteration, max |dx| 1.5e-4, between 2 threads and 1).
    one_core("bench.same_iterates")
    command, arg = argv[0], argv[1]
    if command == "record":
        np.savez(arg, **iterates())
        print(f"recorded {arg}")
    elif command == "tuning":
        print(tuning(arg, argv[2], *map(int, argv[3:4])))
    elif command == "live":
        print(live(arg, *map(int, argv[2:3]), *map(float, argv[3:4])))
    elif command == "scenarios":
        print(scenarios(arg, *map(int, argv[2:3])))
    else:
        print(compare(arg) if command == "compare" else speed(arg))


if __name__ == "__main__":
    main(sys.argv[1:])
