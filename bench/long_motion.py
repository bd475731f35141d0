"""Long motions: the box lift played over 10,000 frames through ``python -m solver solve`` (both
result formats) and ``blender_manikin/batch.py``, timed with each process's peak memory, into docs/BENCHMARKS.md.

    python -m bench.long_motion [--frames 10000] [--runs 3] [--no-batch] [-o docs/BENCHMARKS.md]

The motion is presets/scenarios/box_lift_motion.toml with its keys spread over the frames (the same lift, each
frame a smaller step). Every command runs in its own process; its wall time is measured around it and its peak
resident memory is the kernel's figure for that process (``os.wait4``).
"""

from __future__ import annotations

import argparse
import datetime
import importlib.util
import os
import subprocess
import sys
import tempfile
import time
import tomllib
from pathlib import Path

import numpy as np

from solver.io.scenario.bodies import PRESETS_DIR
from solver.io.toml_write import dumps_toml

PRESET = PRESETS_DIR / "scenarios" / "box_lift_motion.toml"
ROOT = PRESETS_DIR.parent
TARGET_S, TARGET_MB = 60.0, 500.0
NOTES = (  # what was measured once, by profiling: kept with the figures
    "Each frame is written as it is solved and nothing per frame is kept but a few numbers.",
    "Where `batch.py`'s memory goes (resident set sampled every 20 ms, 2026-11-27, 10,000 frames, `--report`):",
    "importing bpy, numpy, scipy and numba and registering the extension 391 MB (numba ~133 MB of it: llvmlite's",
    "LLVM 51 MB, numba 17 MB, its compiled target ~57 MB once the first kernel loads, the cached kernels ~13 MB);",
    "the scene with its manikin 427 MB before the first frame (460 MB until the body-mesh data the skin was fitted",
    "from, ~32 MB, was kept through the bake); the bake then adds ~15 MB (the joint values kept for keying, dropped",
    "once keyed where no picture needs them), keying ~17 MB (Blender's F-curves), evaluating the keyed scene ~19 MB",
    "(Blender holds every key twice once it is evaluated) and writing the report and saving the .blend the rest.",
    "About half of the peak is the libraries' code mapped from disk (RssFile ~251 MB: bpy's own library, LLVM),",
    "which processes share and the system can drop; the process's own memory (RssAnon) peaks at ~260 MB. The peak",
    "moves by ~10 MB between otherwise equal runs (with `--report`, 501 and 514 MB in two environments and working",
    "folders before the joint values were dropped once keyed).",
    "Where a frame's time goes (py-spy, 2026-11-28, ninth step, 10,000 frames of `solve -o R.jsonl`): the iteration",
    "~40 % (a frame starts where the last one ended and adopts what was computed there, so only the moved targets'",
    "rows, the step and, in ~15 % of the frames, a line search are new; the step's compiled kernel is the largest",
    "part), the compact line ~17 % (mostly `repr` of the ~176 numbers that change a frame), the frame's problem ~9 %,",
    "the Result ~8 %, the check of the way from the previous frame ~7 % and start-up ~15 % (imports, loading the",
    "cached kernels); in `batch.py` also reading the scene into a problem (~0.3 ms a frame: the targets, settings and",
    "obstacles' places; meshes that cannot change are read once per bake) and, with `--report`, the report's",
    "ergonomics (~1.2 ms a frame). Keys inside runs of equal values are left out (same curves): Blender holds every",
    "key twice once the scene is evaluated.",
)


def long_motion(frames: int = 10000) -> dict:
    """The box-lift motion scenario (as a dict) with its key frames spread evenly over ``frames`` frames."""
    data = tomllib.loads(PRESET.read_text(encoding="utf-8"))
    first, last = data["motion"]["start"], data["motion"]["end"]
    for target in data["targets"]:
        for key in target.get("keys", []):
            key["frame"] = 1 + round((key["frame"] - first) * (frames - 1) / (last - first))
    data["motion"].update(start=1, end=frames)
    data["name"] = f"box lift over {frames} frames"
    return data


def write_long_motion(path: Path, frames: int = 10000) -> Path:
    """Write :func:`long_motion` as a scenario file."""
    path.write_text(dumps_toml(long_motion(frames)), encoding="utf-8")
    return path


def measure(command: list[str], cwd: Path, env: dict | None = None) -> dict:
    """Run ``command``: its exit code, wall time (s), peak resident memory (MB) and the last line it printed."""
    t0 = time.perf_counter()
    proc = subprocess.Popen(command, cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    output = proc.stdout.read()
    _, status, usage = os.wait4(proc.pid, 0)
    proc.returncode = os.waitstatus_to_exitcode(status)
    wall = time.perf_counter() - t0
    lines = output.strip().splitlines()
    return dict(code=proc.returncode, wall_s=wall, peak_mb=usage.ru_maxrss / 1024.0, last=lines[-1] if lines else "")


def cases(scenario: Path, work: Path, python: str, batch: bool) -> list[tuple[str, list[str]]]:
    """(label, command) of every measured run; outputs go to ``work``."""
    solve = [python, "-m", "solver", "solve", str(scenario), "-q", "-o"]
    out = [
        ("`solve -o R.json` (result JSON)", solve + [str(work / "r.json")]),
        ("`solve -o R.jsonl` (compact)", solve + [str(work / "r.jsonl")]),
        ("`ergo R.jsonl` (report JSON, CSV, plots)", [python, "-m", "solver", "ergo", str(work / "r.jsonl"), "-q",
                                                     "-o", str(work / "ergo.json")]),
    ]  # fmt: skip
    if batch:
        script = str(ROOT / "blender_manikin" / "batch.py")
        files = ["--out", str(work / "b.blend"), "--result", str(work / "b.jsonl")]
        batch = [python, script, "--scenario", str(scenario), "-q", *files]
        out.append(("`batch.py --out --result R.jsonl`", batch))
        out.append(("`batch.py --out --result R.jsonl --report`", batch + ["--report", str(work / "b.json")]))
    return out


def run(output: Path, frames: int = 10000, runs: int = 3, batch: bool = True) -> str:
    """Measure every case ``runs`` times (the cases take turns) and write the long-motion section of ``output``."""
    from .scenarios import machine, write_section

    loads = []  # the 1-minute load average as each command starts
    done: dict[str, list[dict]] = {}
    sizes: dict[str, float] = {}
    with tempfile.TemporaryDirectory(prefix="manikin-long-") as tmp:
        work = Path(tmp)
        scenario = write_long_motion(work / f"box_lift_{frames}.toml", frames)
        env = dict(os.environ, PYTHONPATH=str(ROOT))
        short = write_long_motion(work / "box_lift_10.toml", 10)
        for label, command in cases(short, work, sys.executable, batch):  # the kernels compiled before any timing
            if measure(command, ROOT, env)["code"] not in (0, 3):
                raise SystemExit(f"{label} failed on a 10-frame motion")
        for i in range(runs):
            for label, command in cases(scenario, work, sys.executable, batch):
                loads.append(os.getloadavg()[0])
                result = measure(command, ROOT, env)
                if result["code"] not in (0, 3):
                    raise SystemExit(f"{label} failed (exit {result['code']}): {result['last']}")
                done.setdefault(label, []).append(result)
                print(f"run {i + 1}/{runs} {label}: {result['wall_s']:.1f} s, {result['peak_mb']:.0f} MB", flush=True)
        sizes = {name: (work / name).stat().st_size / 1e6 for name in ("r.json", "r.jsonl", "ergo.json", "b.json")
                 if (work / name).exists()}  # fmt: skip
    text = section(frames, runs, done, sizes, machine(), (min(loads), max(loads)))
    write_section(Path(output), "long-motion", text)
    print(f"wrote {output}")
    return text


def section(frames: int, runs: int, done: dict, sizes: dict, host: str, loads: tuple) -> str:
    """The Markdown section: per case median and p95 of wall time and peak memory, against the targets."""
    lines = [
        "## Long motions",
        "",
        f"Written by `python -m bench.long_motion` on {datetime.date.today().isoformat()}.",
        f"Machine: {host}; not pinned (each command runs as a user runs it, in its own process). The load average"
        f" (1 min) was {loads[0]:.1f} to {loads[1]:.1f} as the commands started (other work shares the cores).",
        "",
        f"The box-lift motion (presets/scenarios/box_lift_motion.toml) with its keys spread over {frames} frames; "
        f"{runs} runs per command, the commands taking turns. Wall time measured around each process, peak memory"
        " = the process's maximum resident set (`os.wait4`). Each command first ran once on 10 frames, untimed: the"
        " compiled kernels are in their cache (a first run compiles them once, ~20 s: section 'Issue 37, sixth step').",
        "",
        "| command | wall median s | wall p95 s | peak memory median MB | peak p95 MB | target |",
        "|---|---:|---:|---:|---:|---|",
    ]
    for label, results in done.items():
        wall = np.array([r["wall_s"] for r in results])
        peak = np.array([r["peak_mb"] for r in results])
        met = np.percentile(wall, 95) <= TARGET_S and np.percentile(peak, 95) <= TARGET_MB
        target = "-" if "ergo" in label or frames < 10000 else ("met" if met else "**not met**")
        lines.append(f"| {label} | {np.median(wall):.1f} | {np.percentile(wall, 95):.1f} | {np.median(peak):.0f} | "
                     f"{np.percentile(peak, 95):.0f} | {target} |")  # fmt: skip
    shown = ", ".join(f"{name} {mb:.0f} MB" for name, mb in sizes.items())
    lines += [
        "",
        f"Targets: at most {TARGET_S:.0f} s and {TARGET_MB:.0f} MB for `solve` and for `batch.py` (p95 of the runs).",
        f"File sizes: {shown}.",
        "",
        *NOTES,
    ]
    return "\n".join(lines) + "\n"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bench.long_motion", description=__doc__.splitlines()[0])
    parser.add_argument("-o", "--output", type=Path, default=ROOT / "docs" / "BENCHMARKS.md")
    parser.add_argument("--frames", type=int, default=10000)
    parser.add_argument("--runs", type=int, default=3, help="runs per command")
    parser.add_argument("--no-batch", action="store_true", help="leave out batch.py (needs the bpy module)")
    args = parser.parse_args(argv)
    batch = not args.no_batch and importlib.util.find_spec("bpy") is not None
    run(args.output, args.frames, args.runs, batch)
    return 0


if __name__ == "__main__":
    sys.exit(main())
