"""Long motions (issue 19): the box lift played over 10,000 frames through ``python -m solver solve`` (both
result formats) and ``blender_manikin/batch.py``, timed with each process's peak memory, into docs/BENCHMARKS.md.

    python -m solver.bench.long_motion [--frames 10000] [--runs 3] [--no-batch] [-o docs/BENCHMARKS.md]

The motion is presets/scenarios/box_lift_motion.toml with its keys spread over the frames (the same lift, each
frame a smaller step). Every command runs in its own process; its wall time is measured around it and its peak
resident memory is the kernel's figure for that process (``os.wait4``).
"""

from __future__ import annotations

import argparse
import datetime
import os
import statistics
import subprocess
import sys
import tempfile
import time
import tomllib
from pathlib import Path

from ..bodies import PRESETS_DIR
from ..io.toml_write import dumps_toml

PRESET = PRESETS_DIR / "scenarios" / "box_lift_motion.toml"
ROOT = PRESETS_DIR.parent
TARGET_S, TARGET_MB = 60.0, 500.0


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
