"""Planning queries (issue 36, "Paths"): median / p95 time of :func:`solver.planning.find_way` over seeds.

    python -m bench.planning [RUNS] [-o docs/BENCHMARKS.md]     # from the repository root; '-o -' only prints

The issue's target is a four-operation sequence generated (stances, ways, timing, every frame solved) in <= 10 s, so
one way should take well under a second. Cases: a tote carried from a floor pallet over a bench onto a shelf behind
it (the issue's first preset), a hand round a wall, and a straight reach (nothing searched). Each run uses another
seed. Writes the ``planning-bench`` section of docs/BENCHMARKS.md.
"""

from __future__ import annotations

import argparse
import time
from datetime import date
from pathlib import Path

import numpy as np

from bench import one_core
from bench.scenarios import machine, speed_reference, write_section
from solver.collision import Box, HalfSpace
from solver.planning import CarriedBox, find_way

FLOOR = HalfSpace([0.0, 0.0, 0.0], [0.0, 0.0, 1.0], name="floor")
STATION = [
    FLOOR,
    Box([0.0, -0.6, 0.075], [0.8, 0.6, 0.15], name="pallet"),
    Box([0.0, 0.2, 0.45], [1.2, 0.5, 0.9], name="bench"),
    Box([0.0, 1.0, 1.0], [1.0, 0.4, 0.04], name="shelf"),
]
CASES = {
    "tote: pallet -> over the bench -> shelf (carried 0.4 x 0.3 x 0.3 m)": (
        [0.0, -0.6, 0.30], [0.0, 1.0, 1.17], CarriedBox(np.array([0.4, 0.3, 0.3]), name="tote"), STATION),
    "hand round a wall (0.6 x 0.05 x 0.6 m)": (
        [0.0, -0.4, 1.0], [0.0, 0.4, 1.0], None, [FLOOR, Box([0.0, 0.0, 1.0], [0.6, 0.05, 0.6], name="wall")]),
    "straight reach, nothing in the way": ([0.5, -0.6, 1.0], [0.5, -0.2, 1.3], None, STATION),
}  # fmt: skip


def measure(runs: int) -> list[tuple[str, np.ndarray, np.ndarray, np.ndarray, int]]:
    """Per case: (name, times s, samples, way points, ways found) over ``runs`` seeds."""
    rows = []
    for name, (start, goal, carried, obstacles) in CASES.items():
        times, samples, points, found = [], [], [], 0
        for seed in range(runs):
            t0 = time.perf_counter()
            way = find_way(start, goal, carried, obstacles, seed=seed)
            times.append(time.perf_counter() - t0)
            samples.append(way.samples)
            points.append(len(way.points))
            found += way.found
        rows.append((name, np.array(times), np.array(samples), np.array(points), found))
    return rows


def report(rows, runs: int, reference: list[float]) -> str:
    """The Markdown section."""
    lines = [
        "## Planning a way (collision-free hand and carried-box paths)",
        "",
        f"Written by `python -m bench.planning {runs}` on {date.today().isoformat()}.",
        f"Machine: {machine()}; one core, single-threaded BLAS. Speed reference {reference[0]:.1f} ms before, "
        f"{reference[1]:.1f} ms after (lower is faster; see above).",
        "",
        f"`find_way` (RRT-Connect in the workspace of the hand or the carried box, shortened and smoothed; "
        f"[](explanation/path-planning.md)), one run per seed 0..{runs - 1}. Times in ms, median / p95; samples: "
        "the RRT-Connect iterations (0: the straight way was free).",
        "",
        "| case | found | time (ms) | samples (median / max) | way points (median) |",
        "|---|---:|---:|---:|---:|",
    ]
    for name, times, samples, points, found in rows:
        ms = times * 1e3
        lines.append(f"| {name} | {found}/{len(times)} | {np.median(ms):.0f} / {np.percentile(ms, 95):.0f} | "
                     f"{np.median(samples):.0f} / {samples.max()} | {np.median(points):.0f} |")  # fmt: skip
    worst = max(np.percentile(times, 95) for _, times, *_ in rows)
    lines += ["", f"Against the issue's target (a four-operation sequence in <= 10 s): four ways at the slowest p95 "
                  f"above take {4 * worst:.1f} s, {40 * worst:.0f} % of the budget; the rest is for the frames' "
                  "solves."]  # fmt: skip
    return "\n".join(lines) + "\n"


def run(runs: int, output: Path | None) -> str:
    reference = [speed_reference()]
    rows = measure(runs)
    reference.append(speed_reference())
    text = report(rows, runs, reference)
    if output is not None:
        write_section(output, "planning-bench", text)
    return text


def main() -> None:
    parser = argparse.ArgumentParser(prog="python -m bench.planning", description=__doc__.split("\n")[0])
    parser.add_argument("runs", nargs="?", type=int, default=20)
    parser.add_argument("-o", "--output", default="docs/BENCHMARKS.md", help="'-' to only print")
    args = parser.parse_args()
    one_core("bench.planning")
    print(run(args.runs, None if args.output == "-" else Path(args.output)))


if __name__ == "__main__":
    main()
