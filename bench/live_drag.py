"""What Blender's Live mode does after a 5 cm drag, timed without Blender's scene: the box lift (floor and
self-collision on, the default comfort) solved once, then each hand target moved 5 cm in a random direction and
re-solved warm from the solved pose with Live's options (``live_iterations`` 30, no restarts), followed by the
summary the Result panel shows (``blender_manikin.scene.problem_io.summarize``; it imports ``bpy``, which the
repository's ``.venv`` has) with the ergonomics scores (as before issue 37: every live solve) or without them (while
dragging, since issue 37: they follow when the drag ends).

    python -m bench.live_drag [REPEATS]        # writes the "live-drag" section of docs/BENCHMARKS.md
"""

from __future__ import annotations

import datetime
import importlib
import sys
import tempfile
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from . import one_core
from .scenarios import _moved, machine, speed_reference, write_section

SCENARIO = "box_lift"
LIVE_ITERATIONS = 30  # the Live iterations default of Blender's Solver Settings
ROOT = Path(__file__).resolve().parents[1]


def _addon() -> tuple:
    """(solver, problem_io) imported as the extension's own package (``manikin``: a link to the repository), so
    that the add-on's relative imports of the solver work, as in Blender."""
    folder = tempfile.mkdtemp(prefix="manikin-bench-")
    (Path(folder) / "manikin").symlink_to(ROOT)
    sys.path.insert(0, folder)
    io = importlib.import_module("manikin.blender_manikin.scene.problem_io")
    return importlib.import_module("manikin.solver"), io


def cases(pkg, repeats: int, trunk: float | None = None) -> tuple[list, object]:
    """``repeats`` (problem, start, options) drags of the box lift, and Live's options (``pkg``: the solver);
    ``trunk``: the comfort's trunk weight instead of the scenario's (5: the behaviour model)."""
    sc = pkg.load_scenario(ROOT / "presets" / "scenarios" / f"{SCENARIO}.toml")
    problem = sc.problem
    assert problem.floor and problem.self_collision, "the live drag is measured with floor and self-collision"
    if trunk is not None:
        weights = importlib.import_module(f"{pkg.__name__}.comfort").ComfortWeights(trunk=trunk)
        problem = type(problem)(problem.model, problem.spec.replace(comfort_weights=weights))
    base = pkg.solve(problem, sc.start, sc.options)
    live = replace(sc.options, max_iterations=LIVE_ITERATIONS, restarts=0)
    rng = np.random.default_rng(0)
    return [(_moved(problem, rng), base.x, live) for _ in range(repeats)], live


def run(repeats: int) -> str:
    """Time solve, summary without and with the ergonomics, per drag; return the Markdown section."""
    pkg, problem_io = _addon()  # imports bpy
    drags, _ = cases(pkg, repeats)
    reference = [speed_reference()]
    solve_t, bare_t, ergo_t, iters, good = [], [], [], [], 0
    for problem, start, options in drags:
        t0 = time.perf_counter()
        result = pkg.solve(problem, start, options)
        t1 = time.perf_counter()
        problem_io.summarize(result, scores=False)
        t2 = time.perf_counter()
        problem_io.ergonomics(result)
        t3 = time.perf_counter()
        solve_t.append(t1 - t0)
        bare_t.append(t2 - t1)
        ergo_t.append(t3 - t2)
        iters.append(result.iterations)
        good += bool(result.converged)
    reference.append(speed_reference())
    solve_a, bare_a, ergo_a = (np.array(v) * 1e3 for v in (solve_t, bare_t, ergo_t))

    def row(label: str, ms: np.ndarray) -> str:
        return f"| {label} | {np.median(ms):.2f} | {np.percentile(ms, 95):.2f} |"

    lines = [
        "## Live drag",
        "",
        f"Written by `python -m bench.live_drag {repeats}` on {datetime.date.today().isoformat()}.",
        f"Machine: {machine()}; one core, one BLAS thread. Speed reference (a fixed NumPy workload, lower is faster):",
        f"{reference[0]:.1f} ms before, {reference[1]:.1f} ms after.",
        "",
        f"What Blender's Live mode does after a 5 cm drag: the {SCENARIO} scenario (floor and self-collision on, the",
        "default comfort) solved once; then, per drag, every hand target moved 5 cm in a random direction and the",
        f"pose re-solved warm with Live's options ({LIVE_ITERATIONS} iterations at most, no restarts), then the",
        "summary the Result panel shows. The scene's read and write (a few ms in Blender) are not included.",
        f"Median iterations {np.median(iters):.0f}; converged {good}/{len(drags)}.",
        "",
        "| part | median ms | p95 ms |",
        "|---|---:|---:|",
        row("solve", solve_a),
        row("summary without the ergonomics scores (while dragging)", bare_a),
        row("ergonomics scores (RULA, REBA, OWAS, ...; once, when the drag ends)", ergo_a),
        row("a live re-solve while dragging: solve + summary", solve_a + bare_a),
        row("the same with the scores every time (before issue 37)", solve_a + bare_a + ergo_a),
    ]
    return "\n".join(lines) + "\n"


def main(argv: list[str]) -> None:
    one_core("bench.live_drag")
    repeats = int(argv[0]) if argv else 200
    text = run(repeats)
    print(text)
    write_section(ROOT / "docs" / "BENCHMARKS.md", "live-drag", text)


if __name__ == "__main__":
    main(sys.argv[1:])
