"""Bake throughput: a 240-frame box lift baked by Bake Motion's code path, written to docs/BENCHMARKS.md.

    python -m bench.blender_bake [-o docs/BENCHMARKS.md] [--runs 3]      # from the repository root, with bpy

The motion is presets/scenarios/box_lift_motion.toml played up, down, up and down (its hand keys repeated every
60 frames, so every frame moves as fast as in the preset). Each run starts from the scenario's start pose with no
action and times everything a user waits for: per frame setting the scene to the frame, reading the targets
and solving warm-started within the per-frame change bound, then keying all joints in bulk. Pinned to one core.
The extension is loaded as ``batch.py`` loads it (from this checkout, registered); its modules are reached through
the loaded package.
"""

from __future__ import annotations

import argparse
import datetime
import importlib
import os
import sys
import tempfile
import time
import tomllib
from pathlib import Path
from types import ModuleType

import numpy as np

from . import one_core

ROOT = Path(__file__).resolve().parents[1]  # the repository root
PRESET = ROOT / "presets" / "scenarios" / "box_lift_motion.toml"
FRAMES = 240
TARGET_FPS = 150.0  # issue 37: the demo's motion baked at >= 150 frames/s
SETTINGS = (("default (comfort re-optimised every frame)", True), ("constraints only (comfort off)", False))
PATTERN = (0, 1, 2, 1)  # key indices of one up-down cycle: floor, middle, table, middle, (floor again)


def ping_pong(frames: int = FRAMES) -> dict:
    """The box-lift scenario with its hand keys repeated up and down over ``frames`` frames."""
    data = tomllib.loads(PRESET.read_text(encoding="utf-8"))
    step = 30  # frames between the preset's keys
    for target in data["targets"]:
        keys = target.get("keys")
        if not keys:
            continue
        target["keys"] = [dict(keys[PATTERN[i % 4]], frame=1 + i * step) for i in range(frames // step + 1)]
    data["motion"].update(start=1, end=frames)
    data["name"] = f"box lift, {frames} frames up and down"
    return data


def _bake_once(ext: ModuleType, arm, start: np.ndarray, comfort: bool) -> dict:
    """One timed bake from the start pose: per-frame times, keying time, total, iterations, converged frames."""
    import bpy

    bake = importlib.import_module(f"{ext.__name__}.blender_manikin.motion.bake")
    armature = importlib.import_module(f"{ext.__name__}.blender_manikin.scene.armature")
    if arm.animation_data is not None:  # the action only: animation_data_clear would drop the twist drivers
        arm.animation_data.action = None
    armature.write_pose(arm, start)
    arm.manikin.comfort = comfort
    t0 = time.perf_counter()
    baker = bake.Baker(bpy.context.scene, arm, 1, FRAMES)
    baker.run()
    keying = baker.write()
    total = time.perf_counter() - t0
    return dict(
        wall=[r.wall_s for r in baker.records],
        solve=[r.time_s for r in baker.records],
        iterations=[r.iterations for r in baker.records],
        converged=sum(r.converged for r in baker.records),
        keying=keying,
        total=total,
    )


def _row(label: str, done: list[dict]) -> tuple:
    """(label, frames/s, median and p95 ms per frame, solver median ms, keying ms, median iterations, converged)."""
    wall = np.concatenate([d["wall"] for d in done]) * 1e3
    solve = np.concatenate([d["solve"] for d in done]) * 1e3
    fps = FRAMES / float(np.median([d["total"] for d in done]))
    keying = float(np.median([d["keying"] for d in done])) * 1e3
    iterations = float(np.median(np.concatenate([d["iterations"] for d in done])))
    converged = min(d["converged"] for d in done)
    print(f"{label}: {fps:.1f} frames/s, median {np.median(wall):.1f} ms/frame, keying {keying:.0f} ms")
    return label, fps, np.median(wall), np.percentile(wall, 95), np.median(solve), keying, iterations, converged


def run(output: Path, runs: int = 3) -> str:
    """Bake ``runs`` times per setting and write the bake-bench section of ``output``; the section's text."""
    from blender_manikin.batch import load_extension

    from .scenarios import machine, write_section

    ext, registered = load_extension()
    job = importlib.import_module(f"{ext.__name__}.blender_manikin.motion.job")
    solver = importlib.import_module(f"{ext.__name__}.solver")
    with tempfile.TemporaryDirectory(prefix="manikin-bench-") as tmp:
        path = Path(tmp) / "box_lift_240.toml"
        path.write_text(solver.dumps_scenario(ping_pong()), encoding="utf-8")
        arm = job.open_scene(job.Job(scenario=path, quiet=True))
        start = solver.load_scenario(path).start
    rows = [_row(label, [_bake_once(ext, arm, start, comfort) for _ in range(runs)]) for label, comfort in SETTINGS]
    if registered:
        ext.unregister()  # bpy 4.5 hangs at exit with the add-on still registered
    met = rows[0][1] >= TARGET_FPS
    share = rows[0][4] / rows[0][2]
    lines = [
        "## Bake throughput",
        "",
        f"Written by `python -m bench.blender_bake` on {datetime.date.today().isoformat()}.",
        f"Machine: {machine()}; the benchmark process is pinned to one core.",
        "",
        f"A {FRAMES}-frame box lift (the preset's hand keys played up, down, up, down; 10 kg box as a load; male_50)",
        "baked by Bake Motion's code (`blender_manikin/motion/bake.py`): per frame the scene is set to the frame, the",
        "targets are read and the frame is solved warm-started within the per-frame change bound; at the end the",
        f"160 joint channels are keyed in bulk. {runs} runs per setting, each from the start pose; frames/s = frames /",
        "wall time of the whole bake (median run); per-frame times are wall times per frame over all runs (setting",
        "the frame, reading the scene, solving) and, separately, the solver's own time.",
        "",
        "| setting | frames/s | median ms/frame | p95 ms/frame | solver median ms | keying ms (all frames) |"
        " median iterations | converged |",
        "|---|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for label, fps, med, p95, solve_med, keying, iterations, converged in rows:
        lines.append(f"| {label} | {fps:.1f} | {med:.1f} | {p95:.1f} | {solve_med:.1f} | {keying:.0f} | "
                     f"{iterations:.0f} | {converged}/{FRAMES} |")  # fmt: skip
    verdict = "met" if met else "not met"
    lines += [
        "",
        f"Target (issue 37): >= {TARGET_FPS:.0f} frames/s on one core with the default settings: **{verdict}** "
        f"({rows[0][1]:.1f} frames/s).",
        f"The solver's warm solve (comfort re-optimised) is {share:.0%} of a frame; setting the frame and reading",
        "the scene into a problem are the rest, and keying all frames at the end takes milliseconds. With comfort",
        "off each frame only restores the constraints from the previous pose: fast, but a different (less",
        "comfortable) motion.",
    ]
    text = "\n".join(lines) + "\n"
    write_section(Path(output), "bake-bench", text)
    print(f"wrote {output}")
    return text


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bench.blender_bake", description=__doc__.splitlines()[0])
    parser.add_argument("-o", "--output", type=Path, default=ROOT / "docs" / "BENCHMARKS.md")
    parser.add_argument("--runs", type=int, default=3, help="bakes per setting")
    args = parser.parse_args(argv)
    one_core("bench.blender_bake")  # one core, one BLAS thread
    with tempfile.TemporaryDirectory(prefix="manikin-bench-user-") as user:
        os.environ.setdefault("BLENDER_USER_RESOURCES", user)
        run(args.output, args.runs)
    return 0


if __name__ == "__main__":
    sys.exit(main())
