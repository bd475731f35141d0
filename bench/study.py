"""Population studies at scale: runs per second of a study on local processes and on a local Dask
cluster, 1 and 2 workers, the cost of a run and of a task, and what a 100,000-run study takes on paper.

    python -m bench.study [--runs 600] [--repeats 3] [-o docs/BENCHMARKS.md]     # about 6 min here
    python -m bench.study --runs 24 --repeats 1 -o /tmp/b.md      # a quick check that it works

The study: the three preset manikins lift the box (presets/scenarios/box_lift.toml, a single balanced pose with
its ergonomics) with the handles raised by evenly spaced heights from 0 to 0.45 m, ``--runs`` runs in all. Each
case runs the study's runs through the executor the ``study`` command uses (no outputs written) and
measures its start-up on its own first (fresh workers, one run each: the wall time less a usual run: spawning
the processes, importing NumPy/SciPy and the solver, loading the compiled kernels, starting the cluster); the
steady rate is the study's runs over
its wall time less that start-up. The cases
take turns, so drifts of the shared machine hit them alike. The 100,000-run plan (100 bodies x 50 tasks x 20
variants) is built for real, to time the planning the parent does before any run starts.
"""

from __future__ import annotations

import argparse
import datetime
import os
import sys
import tempfile
import time
import tracemalloc
from pathlib import Path

import numpy as np

from solver.io.scenario.bodies import PRESETS_DIR
from solver.study import load_study
from solver.study.execute import chunk_size, run_dask, run_local
from solver.study.plan import plan

ROOT = PRESETS_DIR.parent
LIFT = PRESETS_DIR / "scenarios" / "box_lift.toml"
MANIKINS = ("female_5", "male_50", "male_95")
CASES = [  # (label, engine, workers, chunk: None = the study's default)
    ("local processes, 1 worker", "local", 1, None),
    ("local processes, 2 workers", "local", 2, None),
    ("Dask LocalCluster, 1 worker", "dask", 1, None),
    ("Dask LocalCluster, 2 workers", "dask", 2, None),
    ("local processes, 2 workers, 1 run per task", "local", 2, 1),
    ("Dask LocalCluster, 2 workers, 1 run per task", "dask", 2, 1),
]
PAPER_WORKERS = (1, 2, 8, 32, 100)
TARGET_SPEEDUP = 1.8


def study_text(runs: int, scenario: Path = LIFT) -> str:
    """A study of about ``runs`` runs: the preset manikins x evenly spaced handle raises (0 to 0.45 m)."""
    heights = max(1, round(runs / len(MANIKINS)))
    raises = ", ".join(f"{v:.5f}" for v in np.linspace(0.0, 0.45, heights))
    return (f"manikins = {list(MANIKINS)!r}\n\n[[scenarios]]\nfile = \"{scenario}\"\nname = \"lift\"\n"
            f"[scenarios.parameters.raise]\nvalues = [{raises}]\n"
            f"add = [\"targets.hand_r.position[2]\", \"targets.hand_l.position[2]\"]\n").replace("'", '"')  # fmt: skip


def execute(runs: list, engine: str, workers: int, chunk: int | None) -> tuple[float, list[dict]]:
    """Run ``runs`` through the study's executor for ``engine`` (fresh workers): the wall time (s) and the rows."""
    rows: list[dict] = []
    t0 = time.perf_counter()
    if engine == "local":
        run_local(runs, workers, chunk or chunk_size(len(runs), workers), lambda new, keep: rows.extend(new))
    else:
        run_dask(runs, "local", workers, chunk, lambda new, keep: rows.extend(new))
    wall = time.perf_counter() - t0
    failed = [r for r in rows if r.get("status") == "failed"]
    if failed:
        raise SystemExit(f"{len(failed)} runs failed, e.g. {failed[0].get('failure')}")
    return wall, rows


def measure(runs: list, engine: str, workers: int, chunk: int | None) -> dict:
    """One case: its start-up (s: a run per worker, less the slowest of those runs), the steady rate (runs/s: the
    runs over the wall time less the start-up) and the mean in-worker time per run (s)."""
    first, first_rows = execute(runs[:workers], engine, workers, 1)
    wall, rows = execute(runs, engine, workers, chunk)
    usual = float(np.median([r["run_s"] for r in rows]))
    # a fresh worker's first run also loads the compiled kernels (~0.5 s): start-up, like its imports, which each
    # worker pays once and in parallel, so it is not counted as the runs' work
    loading = max(float(np.mean([r["run_s"] for r in first_rows])) - usual, 0.0)
    startup = max(first - usual, 0.0)
    rate = len(runs) / max(wall - startup, 1e-9)
    run_s = (sum(r["run_s"] for r in rows) - workers * loading) / len(rows)
    return dict(wall=wall, rate=rate, startup=startup, workers=workers, run_s=run_s)


def plan_100k(folder: Path) -> dict:
    """Plan (not run) 100 bodies x 50 tasks x 20 variants: the seconds and peak memory (MB) the parent spends."""
    family = folder / "family"
    family.mkdir()
    for i, stature in enumerate(np.linspace(1.50, 1.95, 100)):
        sex = "female" if i % 2 else "male"
        body = f'[body]\nkind = "human"\nsex = "{sex}"\nstature = {stature:.4f}\nmass = {23.0 * stature**2:.2f}\n'
        (family / f"m{i:03d}.toml").write_text(body, encoding="utf-8")
    variants = ", ".join(f"{v:.4f}" for v in np.linspace(0.0, 0.45, 20))
    tasks = "".join(
        f'\n[[scenarios]]\nfile = "{LIFT}"\nname = "task{t:02d}"\n[scenarios.parameters.raise]\nvalues = [{variants}]\n'
        'add = ["targets.hand_r.position[2]", "targets.hand_l.position[2]"]\n'
        for t in range(50)
    )
    study = folder / "big.toml"
    study.write_text('manikins = ["family"]\n' + tasks, encoding="utf-8")
    t0 = time.perf_counter()
    loaded = load_study(study)
    t1 = time.perf_counter()
    runs = len(plan(loaded))
    t2 = time.perf_counter()
    tracemalloc.start()  # a second plan for its memory: tracing slows the first one down several times
    planned = plan(loaded)
    peak = tracemalloc.get_traced_memory()[1] / 1e6
    tracemalloc.stop()
    del planned
    return dict(runs=runs, read_s=t1 - t0, plan_s=t2 - t1, peak_mb=peak)


def run(output: Path, runs: int = 600, repeats: int = 3) -> str:
    """Measure every case ``repeats`` times (taking turns) and write the study section of ``output``."""
    from .scenarios import machine, write_section

    results: dict[str, list[dict]] = {label: [] for label, *_ in CASES}
    loads = []
    with tempfile.TemporaryDirectory(prefix="manikin-study-") as tmp:
        path = Path(tmp) / "bench.toml"
        path.write_text(study_text(runs), encoding="utf-8")
        planned = plan(load_study(path))
        for i in range(repeats):
            for label, engine, workers, chunk in CASES:
                loads.append(os.getloadavg()[0])
                results[label].append(measure(planned, engine, workers, chunk))
                r = results[label][-1]
                print(f"{i + 1}/{repeats} {label}: {r['rate']:.1f} runs/s, start-up {r['startup']:.1f} s", flush=True)
        paper = plan_100k(Path(tmp))
    text = section(results, len(planned), repeats, paper, machine(), (min(loads), max(loads)))
    write_section(Path(output), "study", text)
    print(f"wrote {output}")
    return text


def _median(results: list[dict], key: str) -> float:
    return float(np.median([r[key] for r in results]))


def _core_ms(r: dict) -> float:
    """Core time per run (ms): what each run costs the workers, start-up left out."""
    return 1e3 * r["workers"] / r["rate"]


def section(results: dict, n: int, repeats: int, paper: dict, host: str, loads: tuple) -> str:
    """The Markdown section: the cases, the speed-ups against the target, the task overhead, the 100,000-run study."""
    lines = [
        "## Population studies at scale",
        "",
        f"Written by `python -m bench.study` on {datetime.date.today().isoformat()}. Machine: {host}; the load"
        f" average (1 min) was {loads[0]:.1f} to {loads[1]:.1f} as the cases started.",
        "",
        f"The study: {n} runs (the 3 preset manikins x handle heights of presets/scenarios/box_lift.toml, one balanced"
        f" pose each with its ergonomics), through the `study` command's executors, {repeats} times per case, the"
        " cases taking turns. Start-up (fresh workers, one run each, less a usual run (the median `run_s`): spawning"
        " the workers, their imports, loading the compiled kernels, the cluster) apart; steady rate = runs / (wall"
        " time - start-up). Core ms per run = workers / rate; in-worker = the run itself (building the scenario,"
        " solving, ergonomics: the rows' `run_s`, less each worker's first kernel load); overhead = the"
        " difference (sending, scheduling, waiting for the last chunks).",
        "",
        "| case | runs/s median | runs/s p5 | start-up s | core ms per run | in-worker ms per run | overhead ms per run"
        " |",
        "|---|---:|---:|---:|---:|---:|---:|",
    ]
    for label, rs in results.items():
        core = _median(rs, "workers") * 1e3 / _median(rs, "rate")
        inside = 1e3 * _median(rs, "run_s")
        lines.append(f"| {label} | {_median(rs, 'rate'):.1f} | {np.percentile([r['rate'] for r in rs], 5):.1f} | "
                     f"{_median(rs, 'startup'):.1f} | {core:.1f} | {inside:.1f} | {core - inside:.1f} |")  # fmt: skip
    labels = [label for label, *_ in CASES]
    lines += ["", *speedups(results, labels), "", *paper_lines(results, labels, paper)]
    return "\n".join(lines) + "\n"


def speedups(results: dict, labels: list[str]) -> list[str]:
    out = []
    for one, two, what in ((labels[0], labels[1], "local processes"), (labels[2], labels[3], "local Dask cluster")):
        ratio = _median(results[two], "rate") / _median(results[one], "rate")
        met = "met" if ratio >= TARGET_SPEEDUP else "**not met**"
        out.append(f"Speed-up, 2 workers over 1, {what}: {ratio:.2f}x (target {TARGET_SPEEDUP}x: {met}).")
    for single, what in ((labels[4], "a local process pool"), (labels[5], "Dask")):
        out.append(f"Cost of a task on {what} (the overhead per run with 1 run per task): about "
                   f"{1e3 * task_cost(results[single]):.1f} ms.")  # fmt: skip
    return out


def task_cost(results: list[dict]) -> float:
    """The median overhead (s) per run of a case with 1 run per task: the core time not spent in the runs."""
    return max(float(np.median([_core_ms(r) / 1e3 - r["run_s"] for r in results])), 0.0)


def paper_lines(results: dict, labels: list[str], paper: dict) -> list[str]:
    """What 100,000 runs take on N Dask workers, from the measured costs: a run's work (its in-worker time in the
    least contended case), a task's cost (Dask, 1 run per task), the start-up (Dask, 2 workers) and the planning."""
    dask = results[labels[3]]
    per_run = min(_median(rs, "run_s") for rs in results.values())  # the least contended case: the run's own work
    task = task_cost(results[labels[5]])
    startup, parent = _median(dask, "startup"), paper["read_s"] + paper["plan_s"]
    lines = [
        f"On paper, {paper['runs']:,} runs (100 bodies x 50 tasks x 20 variants; planned for real here: reading the"
        f" study and its 100 bodies {paper['read_s']:.1f} s, planning {paper['plan_s']:.1f} s, peak"
        f" {paper['peak_mb']:.0f} MB) at {1e3 * per_run:.0f} ms of work per run and {1e3 * task:.1f} ms per task:",
        "",
        "| workers | runs per task | tasks | time |",
        "|---:|---:|---:|---:|",
    ]
    for n in PAPER_WORKERS:
        size = chunk_size(paper["runs"], n)
        tasks = -(-paper["runs"] // size)
        seconds = parent + startup + (paper["runs"] * per_run + tasks * task) / n
        lines.append(f"| {n} | {size} | {tasks:,} | {datetime.timedelta(seconds=round(seconds))} |")
    lines += [
        "",
        "What limits it: the work of the runs themselves (it divides by the workers); the parent's planning and"
        " bookkeeping (journal line, progress) stay on one core, and at 1 run per task the scheduling cost would"
        " be paid 100,000 times: the executors send chunks of up to 50 runs, about 8 per worker, so a task carries"
        " ~1 s of work and a lost worker costs one chunk. The scenarios must also be reachable on every worker"
        " (the same checkout installed there: `pip install -e .` and requirements-dask.txt).",
    ]
    return lines


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bench.study", description=__doc__.splitlines()[0])
    parser.add_argument("-o", "--output", type=Path, default=ROOT / "docs" / "BENCHMARKS.md")
    parser.add_argument("--runs", type=int, default=600, help="runs of the measured study")
    parser.add_argument("--repeats", type=int, default=3, help="times each case runs")
    args = parser.parse_args(argv)
    run(args.output, args.runs, args.repeats)
    return 0


if __name__ == "__main__":
    sys.exit(main())
