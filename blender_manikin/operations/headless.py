"""``batch.py --operations FILE.toml`` (bpy): an operations scenario generated headlessly, as Import Operations and
Generate Motion do it from the sidebar, but in this process. The file is read and planned by the solver
(``solver.operations.generate.load_operations``, as ``manikin operate``: a bad file is one line before the scene
changes), imported onto a new manikin by Import Operations' function (:func:`.importing.import_operations`), every
frame solved by ``solve_operations`` (the command's code), keyed as Generate Motion keys a finished run (the joints
as Bake Motion keys them, the objects by :func:`.keys.key_objects`), then the batch's files are written by
:func:`..motion.job.write_outputs`. Ctrl-C while solving keys nothing (the result file keeps the frames solved).
"""

from __future__ import annotations

import sys
import time

import bpy
import numpy as np

from ...solver.ergonomics.niosh import hand_load_kg
from ...solver.io.result.frame import frame_of_result
from ...solver.operations.generate import Job as Planned
from ...solver.operations.generate import load_operations, solve_operations, summary
from ...solver.progress import Progress
from ..motion.bake import FrameRecord
from ..motion.frame_store import STORE_MAX
from ..motion.job import EXIT_NOT_CONVERGED, EXIT_OK, Job, Sinks, check_job, report_bake, write_outputs
from ..motion.quiet import quietly
from ..scene.armature import model_of
from .importing import import_operations
from .keys import ResultKeys, key_objects, object_starts

MAX_SHOWN = 5  # key poses in the picture at most (more: evenly spaced ones)


def _say(job: Job, text: str) -> None:
    if not job.quiet:
        print(text, flush=True)


def open_operations(job: Job) -> tuple[bpy.types.Object, Planned]:
    """A fresh scene with the file imported onto a new manikin, at its start frame; (the manikin, the plan)."""
    planned = load_operations(job.operations)  # read and planned first: a bad file is one line, nothing changed
    for ob in list(bpy.data.objects):  # a fresh session's default cube, camera and light would only be in the way
        bpy.data.objects.remove(ob, do_unlink=True)
    bpy.data.orphans_purge(do_recursive=True)  # and an earlier job's data (the demo's second one): its names
    arm, _, _, warnings = quietly(import_operations, bpy.context, job.operations, None, planned)
    for warning in warnings:
        _say(job, f"warning: {warning}")
    bpy.context.scene.frame_set(planned.frames[0])
    return arm, planned


def shown_frames(planned: Planned, thetas: np.ndarray) -> list[int]:
    """The picture's frames: the first, then for every object held its grasp, the middle of its carry and its
    release (the frames where the hands close and open); evenly spaced ones when that is more than MAX_SHOWN."""
    fps, start, frames = planned.operate.fps, planned.operate.start, planned.frames
    times, held_from, end = [0.0], None, 0.0
    for segment in planned.plan.segments:
        if segment.carried is not None and held_from is None:
            held_from = segment.t0
        elif segment.carried is None and held_from is not None:
            times += [held_from, (held_from + end) / 2, end]
            held_from = None
        end = segment.t1
    if held_from is not None:
        times += [held_from, (held_from + end) / 2, end]
    shown = sorted({min(max(start + round(t * fps), frames[0]), frames[-1]) for t in times})
    if len(shown) > MAX_SHOWN:
        return sorted({frames[round(i)] for i in np.linspace(0, len(frames) - 1, MAX_SHOWN)})
    return shown if len(shown) > 1 else [frames[0], frames[-1]]


def lifted(report, solved: list) -> None:
    """The report's motion scores (the NIOSH lift) over the lift: from the first frame whose hands hold a load to
    the last (the motion's ends hold nothing: the object is still on its support, or put down)."""
    held = [f for f in solved if hand_load_kg(f) > 0.0]
    if held:
        report.ends = [held[0], held[-1]]


def generate(job: Job, planned: Planned, sinks: Sinks) -> tuple[list[FrameRecord], np.ndarray, list, float]:
    """Solve every frame with a progress line, each handed to ``sinks`` (the result file, the report); (records,
    joint values (frames, n), the solved frames (``solver.io.result.Frame``), seconds)."""
    n = len(planned.frames)
    progress = Progress(n, enabled=not job.quiet, stream=sys.stdout)
    records, thetas, solved = [], [], []
    started = then = time.perf_counter()
    try:
        for frame, result in solve_operations(planned):
            state = result.state
            record = FrameRecord(frame, bool(result.converged), int(result.iterations), float(result.time_s),
                                 time.perf_counter() - then, list(result.unmet), list(result.notes),
                                 {k: float(v) for k, v in result.residuals.items()})  # fmt: skip
            sinks(record, result)
            record.residuals = {}
            records.append(record)
            thetas.append(result.theta)
            solved.append(frame_of_result(result, frame, state))
            progress.update(len(records), sum(not r.converged for r in records))
            then = time.perf_counter()
    except BaseException:
        progress.clear()
        if sinks.result is not None:  # the frames solved so far stay in the result file, which says it stopped
            sinks.result.close(interrupted_at=planned.frames[len(records)], reason="interrupted")
        if sinks.report is not None:
            sinks.report.discard()
        raise
    progress.clear()
    return records, np.array(thetas, dtype=float), solved, time.perf_counter() - started


def run(job: Job) -> int:
    """Generate, key and write; 0 when every frame converged, 3 when some did not (the files are written either
    way). ManikinError (one line) for a bad file or output path."""
    check_job(job)
    t0 = time.perf_counter()
    arm, planned = open_operations(job)
    scene = bpy.context.scene
    _say(
        job,
        f"generating {arm.name}: {len(planned.plan.spans)} operations, frames {planned.frames[0]}-"
        f"{planned.frames[-1]} ({len(planned.frames)}), cycle time {planned.plan.duration:.2f} s (MTM-1)",
    )
    starts = object_starts(scene, arm, planned.objects)  # where the objects lie at the start frame
    sinks = Sinks(job, arm, model_of(arm), len(planned.frames) <= STORE_MAX)
    records, thetas, solved, seconds = generate(job, planned, sinks)
    if sinks.report is not None:
        lifted(sinks.report, solved)
    keys = ResultKeys(scene, arm, records, thetas)  # keyed as Generate Motion keys a finished run
    keys.solved_frames = solved
    arm.manikin.live = False  # the keyed action drives the pose from now on
    keyed = keys.write(thin=True, ergo=sinks.report)
    objects = key_objects(scene, arm, keys, planned, starts)
    scene.frame_end = max(keys.frames[-1], scene.frame_start)
    report_bake(job, keys, seconds + keyed)
    for line in summary(planned, {r.frame: r.converged for r in records}, seconds)[1:]:
        _say(job, "  " + line)
    if objects:
        _say(job, f"keyed {', '.join(objects)} with the hands")
    write_outputs(job, arm, keys, sinks, None, posed=shown_frames(planned, thetas))
    _say(job, f"done in {time.perf_counter() - t0:.1f} s")
    sys.stdout.flush()
    return EXIT_NOT_CONVERGED if keys.not_converged() else EXIT_OK
