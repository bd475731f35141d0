"""The report of a baked motion (plain Python, no bpy): per frame how the solve went and its ergonomics.

Each frame holds ``frame``, ``converged``, ``iterations``, ``time_s`` (solver), ``wall_s`` (with reading the
scene), ``unmet``, ``notes``, ``residuals`` (per constraint in its own units) and ``ergonomics`` (posture, joint
loads, RULA, REBA, OWAS, worksheet, NIOSH at that frame: :func:`solver.evaluate` on the frames' results).
Top level: the source, the manikin, the range, the frames that did not converge,
timing and the NIOSH lift from the first to the last frame.
"""

from __future__ import annotations

import os
from dataclasses import asdict
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ... import solver
from ...solver.ergonomics import ErgoOptions
from ...solver.ergonomics.report import clean
from ...solver.io.files import write_json as write_file

if TYPE_CHECKING:
    from ..scene.bake import Baker

ERGONOMICS = ("posture", "joint_loads", "rula", "reba", "owas", "worksheet", "niosh")


def evaluate_motion(baker: Baker, body: str) -> dict:
    """The ergonomics of every baked frame (the format of ``python -m solver ergo``, which its plots draw), with
    the strengths of the baked manikin (``body``, its preset name or body file, only names it in the report)."""
    return solver.evaluate(baker.results, ErgoOptions(manikin=body or None), model=baker.model)


def motion_report(baker: Baker, source: dict, body: str, ergo: dict) -> dict:
    """The report of ``baker`` (baked with ``keep_results``) with its ergonomics ``ergo`` (:func:`evaluate_motion`)."""
    frames = []
    for record, evaluated in zip(baker.records, ergo["frames"], strict=True):
        frames.append(dict(asdict(record), ergonomics={k: evaluated[k] for k in ERGONOMICS}))
    wall = [r.wall_s for r in baker.records]
    return clean(
        dict(
            source=source,
            manikin=body,
            armature=baker.arm.name,
            frame_start=baker.frames[0],
            frame_end=baker.frames[-1],
            converged=not baker.not_converged(),
            not_converged=baker.not_converged(),
            timing=dict(
                solve_s=sum(r.time_s for r in baker.records),
                wall_s=sum(wall),
                median_frame_ms=1e3 * float(np.median(wall)),
                p95_frame_ms=1e3 * float(np.percentile(wall, 95)),
            ),
            niosh_lift=ergo["niosh"],
            working_area=ergo["working_area"],
            ergonomics_options=ergo["options"],
            ergonomics_sources=ergo["sources"],
            frames=frames,
        )
    )


def write_json(data: dict, path: Path) -> Path:
    """Write ``data`` as :func:`solver.io.files.open_output` does (atomic for files, devices in place); the
    absolute path."""
    return Path(write_file(Path(os.path.abspath(path)), data, allow_nan=False))


def _worst(report: dict, *keys: str) -> tuple[float | None, int | None]:
    best, at = None, None
    for f in report["frames"]:
        value = f["ergonomics"]
        for k in keys:
            value = value.get(k) if isinstance(value, dict) else None
        if isinstance(value, (int, float)) and (best is None or value > best):
            best, at = value, f["frame"]
    return best, at


def summary_lines(report: dict) -> list[str]:
    """A few lines for the terminal: the worst scores and loads over the motion and the NIOSH lift."""
    lines = []
    reba, reba_at = _worst(report, "reba", "score")
    rula, rula_at = _worst(report, "rula", "score")
    if reba is not None and rula is not None:
        lines.append(f"highest REBA {reba:.0f} (frame {reba_at}), highest RULA {rula:.0f} (frame {rula_at})")
    compression, at = _worst(report, "joint_loads", "l4_l5", "compression")
    if compression is not None:
        lines.append(f"L4/L5 compression up to {compression / 1e3:.2f} kN (frame {at}; NIOSH action limit 3.4 kN)")
    lift = report.get("niosh_lift") or {}
    if lift.get("LI") is not None:
        load, rwl, index = lift["load_kg"], lift["RWL"], lift["LI"]
        lines.append(f"NIOSH lift: recommended weight limit {rwl:.1f} kg for {load:.1f} kg, lifting index {index:.2f}")
    return lines


def captions(report: dict | None) -> dict[int, str]:
    """A short caption per frame for the key-pose picture: scores, trunk bend, L4/L5 compression."""
    out: dict[int, str] = {}
    for f in (report or {}).get("frames", []):
        e = f["ergonomics"]
        scores = [f"{name} {e[key]['score']}" for name, key in (("REBA", "reba"), ("RULA", "rula"))
                  if isinstance(e[key].get("score"), int)]  # fmt: skip
        lines = [" · ".join(scores)] if scores else []
        trunk = e["posture"].get("trunk_flexion")
        if isinstance(trunk, (int, float)):
            lines.append(f"trunk bent {trunk:.0f}°")
        compression = e["joint_loads"].get("l4_l5", {}).get("compression")
        if isinstance(compression, (int, float)):
            lines.append(f"L4/L5 {compression / 1e3:.1f} kN")
        if not f["converged"]:
            lines.append("NOT converged")
        out[f["frame"]] = "\n".join(lines)
    return out


def choose_frames(frames: list[int], thetas: np.ndarray, keys: list[int], count: int = 4) -> list[int]:
    """``count`` frames worth showing: the ends and the targets' key frames, then the middle of whichever stretch
    changes the pose most, until there are ``count`` (evenly spaced frames when there are too many keys)."""
    first, last = frames[0], frames[-1]
    chosen = sorted({first, last} | {k for k in keys if first < k < last})
    if len(chosen) > count:
        return sorted({frames[round(i)] for i in np.linspace(0, len(frames) - 1, count)})
    while len(chosen) < count:
        gaps = [(a, b) for a, b in zip(chosen, chosen[1:], strict=False) if b - a > 1]
        if not gaps:
            break
        a, b = max(gaps, key=lambda g: float(np.linalg.norm(thetas[g[1] - first] - thetas[g[0] - first])))
        chosen = sorted({*chosen, (a + b) // 2})
    return chosen
