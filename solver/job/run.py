"""Evaluate a job: get each task's motion (read its result file, or solve its scenario into ``OUT/``), evaluate the
frames' ergonomics with the task's load, run every registered method on each task and combine the tasks as each
method's published form does (:meth:`.base.Method.combine`), write job.json, job.csv and job.html."""

from __future__ import annotations

import csv
from pathlib import Path
from typing import TYPE_CHECKING

from ..ergonomics import ErgoOptions, evaluate
from ..ergonomics.report import clean
from ..errors import UsageError
from ..io.files import open_output, write_json, write_text
from ..io.result.read import ResultFile
from .base import JobInputs, TaskResult
from .motions import TaskMotion, motions_of
from .registry import METHODS
from .spec import Job, read_job
from .tasks import Task

if TYPE_CHECKING:
    from ..body.model import Model

OUTPUTS = ("job.json", "job.csv", "job.html")


def motion_of(job: Job, out_dir: Path) -> ResultFile:
    """The single-form job's motion: its result file, or its scenario solved now into ``out_dir/motion.json``."""
    return motions_of(tasks_of(job), out_dir)[0].motion


def tasks_of(job: Job) -> tuple[Task, ...]:
    """The job's tasks; a Job built by hand without any: its own motion and load as the one task."""
    if job.tasks:
        return job.tasks
    kind, source = ("scenario", job.scenario) if job.scenario is not None else ("result", job.result)
    return (Task(job.name, kind, source, job.fps, 1, None, job.lifts_per_cycle, job.load_mass, job.hands),)


def _check_times(job: Job, motions: list[TaskMotion]) -> None:
    """The tasks' motions must fit in the cycle (those done per cycle) and in the shift (all of them)."""
    for i, m in enumerate(motions):
        if not m.motion.frames:
            where = "motion" if job.single else f"tasks[{i}]"
            raise UsageError(f"{job.path}: {where}: the result has no frames")
    if job.single:
        n, fps = len(motions[0].motion.frames), motions[0].fps
        if n / fps > job.cycle_time * (1 + 1e-9):
            raise UsageError(f"{job.path}: work.cycle_time: expected at least the motion's {n} frames at {fps:g} "
                             f"fps ({n / fps:.2f} s), got {job.cycle_time:g}")  # fmt: skip
        return
    per_cycle = sum((m.task.per_cycle or 0) * len(m.motion.frames) / m.fps for m in motions)
    if per_cycle > job.cycle_time * (1 + 1e-9):
        raise UsageError(f"{job.path}: work.cycle_time: expected at least the {per_cycle:.2f} s the tasks done per "
                         f"cycle take (repetitions x motion), got {job.cycle_time:g}")  # fmt: skip
    per_shift = sum(m.task.repetitions(job.repetitions) * len(m.motion.frames) / m.fps for m in motions)
    if per_shift > job.shift * 3600.0 * (1 + 1e-9):
        raise UsageError(f"{job.path}: tasks: expected the tasks' repetitions to fit in the {job.shift:g} h shift, "
                         f"they take {per_shift / 3600.0:.2f} h")  # fmt: skip


def _task_report(job: Job, m: TaskMotion, model: Model | None) -> tuple[dict, dict]:
    """(the task's entry of the report, its methods' results by name)."""
    task = m.task
    ergo = evaluate(m.motion, ErgoOptions(load_mass=task.load_mass), model)
    inputs = JobInputs(job.for_task(task, m.fps), m.motion.frames, ergo)
    methods = {name: method.evaluate(inputs) for name, method in METHODS.items()}
    entry = dict(
        name=task.name, inputs=task.as_dict(job.repetitions), motion_file=str(m.motion.path), fps=m.fps,
        motion_time_s=inputs.motion_time, frames=[f.number for f in m.motion.frames],
        times_s=[i * inputs.frame_time for i in range(len(m.motion.frames))], notes=list(m.notes),
        verdicts={name: r["verdict"] | {"title": METHODS[name].title} for name, r in methods.items()},
        methods=methods,
    )  # fmt: skip
    return entry, methods


def evaluate_job(job: Job, motions: ResultFile | list[TaskMotion], model: Model | None = None) -> dict:
    """The job report (JSON-safe): the job's inputs, per task its frames, times and each method's result, and the
    job's result of each method (its ``verdict`` first) combined over the tasks. ``motions``: one per task, or one
    ResultFile for a one-task job (its fps the job's). ``model``: the manikin that moved (default: each result's
    scenario's; Blender and the study give their own body)."""
    tasks = tasks_of(job)
    if isinstance(motions, ResultFile):
        if len(tasks) != 1:
            raise UsageError(f"{job.path}: tasks: one motion rates a job of one task; this job has {len(tasks)}")
        motions = [TaskMotion(tasks[0], motions, job.fps)]
    _check_times(job, motions)
    entries, per_task = [], []
    for m in motions:
        entry, methods = _task_report(job, m, model)
        entries.append(entry)
        per_cycle = m.task.per_cycle if m.task.per_cycle is not None else \
            (m.task.per_shift / job.repetitions if job.repetitions else 0.0)  # fmt: skip
        per_task.append((m.task, methods, per_cycle, entry["motion_time_s"]))
    combined = {name: method.combine(job, [TaskResult(t.name, methods[name], t.repetitions(job.repetitions), c, s)
                                           for t, methods, c, s in per_task])
                for name, method in METHODS.items()}  # fmt: skip
    report = dict(
        job=job.as_dict(), tasks=entries, sources={name: m.source for name, m in METHODS.items()},
        verdicts={name: r["verdict"] | {"title": METHODS[name].title} for name, r in combined.items()},
        methods=combined,
    )  # fmt: skip
    first = entries[0]
    if len(entries) == 1:  # the one task's motion is the job's (the single form's report, unchanged)
        report |= {k: first[k] for k in ("motion_file", "motion_time_s", "frames", "times_s")}
    else:
        report["motion_time_s"] = sum(c * s for _, _, c, s in per_task)  # s of motion per cycle
    return clean(report)


def write_csv(report: dict, path: Path) -> Path:
    """One row per frame of each task: task, frame, time, then every method's per-frame columns (blank where a
    task has none)."""
    names: dict[str, None] = {}
    for task in report["tasks"]:
        for result in task["methods"].values():
            names |= dict.fromkeys(result.get("per_frame", {}))
    with open_output(path) as out:
        w = csv.writer(out, lineterminator="\n")
        w.writerow(["task", "frame", "time_s", *names])
        for task in report["tasks"]:
            columns: dict[str, list] = {}
            for result in task["methods"].values():
                columns |= result.get("per_frame", {})
            for i, (frame, time) in enumerate(zip(task["frames"], task["times_s"], strict=True)):
                values = [columns[c][i] if c in columns else None for c in names]
                w.writerow(
                    [task["name"], frame, f"{time:.6g}"]
                    + ["" if v is None else f"{v:.6g}" if isinstance(v, float) else v for v in values]
                )
    return path


def run_job(job_path: str | Path, out_dir: str | Path) -> dict:
    """Read the job file, evaluate it and write ``out_dir``/job.json, job.csv, job.html; the report, with the written
    paths under ``written``."""
    from .html import html_report

    job = read_job(job_path)
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    motions = motions_of(tasks_of(job), out_dir, job.path)
    report = evaluate_job(job, motions)
    frames = [m.motion.frames for m in motions]
    written = [write_json(out_dir / OUTPUTS[0], report, allow_nan=False), write_csv(report, out_dir / OUTPUTS[1]),
               write_text(out_dir / OUTPUTS[2], html_report(report, task_frames=frames))]  # fmt: skip
    return report | {"written": [str(p) for p in written]}


def summary_lines(report: dict) -> list[str]:
    """The verdicts, one line each, for the terminal; with several tasks, a line per task first."""
    tasks = report["tasks"]
    if len(tasks) == 1:
        lines = [f"job {report['job']['name']}: {len(report['frames'])} frames, {report['motion_time_s']:.2f} s motion"]
    else:
        lines = [f"job {report['job']['name']}: {len(tasks)} tasks"]
        lines += [f"  task {t['name']}: {len(t['frames'])} frames, {t['motion_time_s']:.2f} s motion, "
                  f"{t['inputs']['repetitions_per_shift']} per shift" for t in tasks]  # fmt: skip
    lines += [f"  {v['title']}: {v['text']}" for v in report["verdicts"].values()]
    lines += [f"  note ({t['name']}): {n}" for t in tasks for n in t["notes"]]
    return lines + [f"wrote {p}" for p in report.get("written", [])]
