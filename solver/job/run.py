"""Evaluate a job: get its motion (read the result file, or solve the scenario into ``OUT/motion.json``), evaluate
the frames' ergonomics with the job's load, run every registered method, write job.json, job.csv and job.html."""

from __future__ import annotations

import csv
from pathlib import Path
from typing import TYPE_CHECKING

from ..ergonomics import ErgoOptions, evaluate
from ..ergonomics.report import clean
from ..errors import UsageError
from ..io.files import open_output, write_json, write_text
from ..io.result.read import ResultFile, read_result
from .base import JobInputs
from .registry import METHODS
from .spec import Job, read_job

if TYPE_CHECKING:
    from ..body.model import Model

OUTPUTS = ("job.json", "job.csv", "job.html")


def motion_of(job: Job, out_dir: Path) -> ResultFile:
    """The job's motion: its result file, or its scenario solved now and written to ``out_dir/motion.json``."""
    if job.result is not None:
        return read_result(job.result)
    from ..io.result.write import ResultWriter
    from ..io.scenario.read import load_scenario
    from ..motion.frames import solve_motion

    scenario = load_scenario(job.scenario)
    writer = ResultWriter(out_dir / "motion.json", Path(scenario.path).resolve(), None)  # found from anywhere
    for frame, result in solve_motion(scenario):
        writer.add(frame, result)
    return read_result(writer.close())


def evaluate_job(job: Job, motion: ResultFile, model: Model | None = None) -> dict:
    """The job report (JSON-safe): the job's inputs, each method's result (its ``verdict`` first) and the motion's
    frame numbers and times. ``model``: the manikin that moved (default: the result's scenario's; Blender and the
    study give their own body)."""
    if not motion.frames:
        raise UsageError(f"{job.path}: motion: the result has no frames")
    if len(motion.frames) / job.fps > job.cycle_time * (1 + 1e-9):
        n = len(motion.frames)
        raise UsageError(f"{job.path}: work.cycle_time: expected at least the motion's {n} frames at {job.fps:g} "
                         f"fps ({n / job.fps:.2f} s), got {job.cycle_time:g}")  # fmt: skip
    ergo = evaluate(motion, ErgoOptions(load_mass=job.load_mass), model)
    inputs = JobInputs(job, motion.frames, ergo)
    methods = {name: method.evaluate(inputs) for name, method in METHODS.items()}
    return clean(dict(
        job=job.as_dict(), motion_file=str(motion.path), motion_time_s=inputs.motion_time,
        frames=[f.number for f in motion.frames], times_s=[i * inputs.frame_time for i in range(len(motion.frames))],
        sources={name: m.source for name, m in METHODS.items()},
        verdicts={name: r["verdict"] | {"title": METHODS[name].title} for name, r in methods.items()},
        methods=methods,
    ))  # fmt: skip


def write_csv(report: dict, path: Path) -> Path:
    """One row per frame: frame, time, then every method's per-frame columns."""
    columns = {"frame": report["frames"], "time_s": report["times_s"]}
    for result in report["methods"].values():
        columns |= result.get("per_frame", {})
    with open_output(path) as out:
        w = csv.writer(out, lineterminator="\n")
        w.writerow(list(columns))
        for row in zip(*columns.values(), strict=True):
            w.writerow(["" if v is None else f"{v:.6g}" if isinstance(v, float) else v for v in row])
    return path


def run_job(job_path: str | Path, out_dir: str | Path) -> dict:
    """Read the job file, evaluate it and write ``out_dir``/job.json, job.csv, job.html; the report, with the written
    paths under ``written``."""
    from .html import html_report

    job = read_job(job_path)
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    motion = motion_of(job, out_dir)
    report = evaluate_job(job, motion)
    written = [write_json(out_dir / OUTPUTS[0], report, allow_nan=False), write_csv(report, out_dir / OUTPUTS[1]),
               write_text(out_dir / OUTPUTS[2], html_report(report, motion.frames))]  # fmt: skip
    return report | {"written": [str(p) for p in written]}


def summary_lines(report: dict) -> list[str]:
    """The verdicts, one line each, for the terminal."""
    lines = [f"job {report['job']['name']}: {len(report['frames'])} frames, {report['motion_time_s']:.2f} s motion"]
    lines += [f"  {v['title']}: {v['text']}" for v in report["verdicts"].values()]
    return lines + [f"wrote {p}" for p in report.get("written", [])]
