"""Operation sequences (issue 36): the time to generate each preset in presets/operations/ from its file alone
(plan: stances, ways, MTM-1 timing; then every frame solved), median / p95 over runs, and whether every frame
converged with 0 penetration and 0 swept crossings.

    python -m bench.operations [RUNS] [-o docs/BENCHMARKS.md]     # from the repository root; '-o -' only prints

The issue's target: a four-operation sequence generated in <= 10 s on this machine, every frame converged, 0
penetration, 0 swept collisions. Writes the ``operations-bench`` section of docs/BENCHMARKS.md.
"""

from __future__ import annotations

import argparse
import time
from datetime import date
from pathlib import Path

import numpy as np

from bench import one_core
from bench.scenarios import machine, speed_reference, write_section
from solver.operations.generate import load_operations, solve_operations

PRESETS = Path(__file__).resolve().parents[1] / "presets" / "operations"
NAMES = ("bin_to_fixture", "pallet_to_shelf", "table_to_table")
ROOM = 1e-3  # m: a floor or obstacle shortfall below this is within the solver's tolerance (no penetration)


def once(path: Path) -> dict:
    """One generation of ``path``: times (s), counts and what the checks found."""
    t0 = time.perf_counter()
    job = load_operations(path)
    t1 = time.perf_counter()
    frames = list(solve_operations(job))
    t2 = time.perf_counter()
    residual = ("floor.shortfall", "obstacles.shortfall")
    deepest = max(max(r.residuals.get(k, 0.0) for k in residual) for _, r in frames)
    crossed = sum(any("between frames" in s for s in r.unmet) for _, r in frames)
    return {"plan": t1 - t0, "total": t2 - t0, "operations": len(job.plan.spans), "frames": len(frames),
            "converged": sum(r.converged for _, r in frames), "deepest": deepest, "crossed": crossed,
            "cycle": job.plan.duration}  # fmt: skip


def report(rows: dict[str, list[dict]], runs: int, reference: list[float]) -> str:
    """The Markdown section."""
    lines = [
        "## Operation sequences (`manikin operate`)",
        "",
        f"Written by `python -m bench.operations {runs}` on {date.today().isoformat()}.",
        f"Machine: {machine()}; one core, single-threaded BLAS. Speed reference {reference[0]:.1f} ms before, "
        f"{reference[1]:.1f} ms after (lower is faster; see above).",
        "",
        "Each preset of presets/operations/ generated from its file alone (plan: stances, ways, MTM-1 timing; then "
        "every frame solved, warm-started from the one before, the swept check between frames), "
        f"{runs} runs. Times in s, median / p95; penetration: the deepest floor or obstacle shortfall of any frame "
        "(within the solver's tolerance below 1 mm); crossings: frames with a part swept through something.",
        "",
        "| sequence | operations | frames | cycle (s) | plan (s) | total (s) | converged | penetration (mm) | "
        "crossings |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for name, runs_of in rows.items():
        total = np.array([r["total"] for r in runs_of])
        plan = np.array([r["plan"] for r in runs_of])
        r = runs_of[-1]
        lines.append(f"| {name} | {r['operations']} | {r['frames']} | {r['cycle']:.2f} | {np.median(plan):.2f} | "
                     f"{np.median(total):.1f} / {np.percentile(total, 95):.1f} | {r['converged']}/{r['frames']} | "
                     f"{1e3 * max(x['deepest'] for x in runs_of):.1f} | {max(x['crossed'] for x in runs_of)} |")
    four = [n for n, rs in rows.items() if rs[-1]["operations"] == 4]
    if four:
        worst = max(np.percentile([r["total"] for r in rows[n]], 95) for n in four)
        lines += ["", f"The issue's target (a four-operation sequence in <= 10 s): {', '.join(four)} at p95 "
                      f"{worst:.1f} s."]  # fmt: skip
    return "\n".join(lines) + "\n"


def run(runs: int, output: Path | None) -> str:
    reference = [speed_reference()]
    rows = {name: [] for name in NAMES}
    for _ in range(runs):  # the sequences take turns, so the VM's drift hits them alike
        for name in NAMES:
            rows[name].append(once(PRESETS / f"{name}.toml"))
    reference.append(speed_reference())
    text = report(rows, runs, reference)
    if output is not None:
        write_section(output, "operations-bench", text)
    return text


def main() -> None:
    parser = argparse.ArgumentParser(prog="python -m bench.operations", description=__doc__.split("\n")[0])
    parser.add_argument("runs", nargs="?", type=int, default=5)
    parser.add_argument("-o", "--output", default="docs/BENCHMARKS.md", help="'-' to only print")
    args = parser.parse_args()
    one_core("bench.operations")
    print(run(args.runs, None if args.output == "-" else Path(args.output)))


if __name__ == "__main__":
    main()
