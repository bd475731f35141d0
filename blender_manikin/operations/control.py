"""Generate Motion (bpy): the scene's operation list as a scenario, checked by the solver's reader and planner here
(a bad operation is one line at once, before anything runs), solved by ``python -m solver operate`` in the
background (:class:`.job.OperateJob`), watched by a ``bpy.app.timers`` timer (:func:`poll_job`, shared machinery:
:mod:`..scene.watch`) and, when it ends, keyed onto the manikin and the objects (:mod:`.keys`). Light to import:
the solver's numerics load inside the functions.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import TYPE_CHECKING

import bpy

from ...solver.errors import ManikinError, UsageError
from ..scene.schema import is_manikin, rig_of
from ..scene.watch import Watch, base_folder

if TYPE_CHECKING:
    from .job import OperateJob

SCENARIO = "operations.toml"  # the scenario the run reads, in its folder


def _ended(scene: bpy.types.Scene | None, job: OperateJob) -> None:
    """The run ended: key its result (if it finished) and say how it went."""
    if scene is None:
        return
    settings = scene.manikin_operations
    settings.summary = "\n".join(job.summary())
    if job.state != "done":
        settings.status = job.line()
        return
    arm = settings.manikin
    if arm is None or not arm.users_scene:
        settings.status = "Generated, but the manikin is gone from the scene: nothing keyed"
        return
    try:
        settings.status = key_run(scene, arm, job)
    except (ManikinError, OSError) as exc:
        settings.status = f"Generated, but could not key it: {' '.join(str(exc).split())}"


WATCH = Watch(_ended)
poll_job = WATCH.timer  # the timer (:mod:`..scene.watch`)
is_running, stop_job = WATCH.running, WATCH.stop


def current_job() -> OperateJob | None:
    """The run started last in this session (running or ended), or None."""
    return WATCH.job


def manikin_for(context: bpy.types.Context) -> bpy.types.Object | None:
    """The manikin the operations move: the active object's, else the scene's only manikin."""
    arm = rig_of(context.active_object)
    if arm is not None:
        return arm
    found = [ob for ob in context.scene.objects if is_manikin(ob)]
    return found[0] if len(found) == 1 else None


def _one_line(exc: Exception, path: Path) -> str:
    """The reader's or planner's line without the temporary scenario's path, the operation numbered as listed."""
    from .job import numbered

    text = " ".join(str(exc).split())
    text = text.removeprefix(f"{path}: ").removeprefix(f"{path.resolve()}: ")
    return numbered(re.sub(r"^operations\[(\d+)\]\.", r"operations[\1] ", text))


def start_generate(scene: bpy.types.Scene, arm: bpy.types.Object) -> OperateJob:
    """Write the scenario of ``scene``'s list for ``arm``, plan it here (UsageError or ScenarioError: one line
    naming the operation) and start solving it in the background; the job."""
    from ...solver.io.scenario.write import write_scenario_files
    from ...solver.operations.generate import load_operations
    from .job import OperateJob
    from .keys import object_starts
    from .scenario import operations_scenario

    settings = scene.manikin_operations
    if scene.frame_current != scene.frame_start:  # the objects and targets where the motion starts
        scene.frame_set(scene.frame_start)
    data = operations_scenario(scene, arm)
    folder = base_folder(settings.folder, "manikin_operations") / bpy.path.clean_name(arm.name)
    path = write_scenario_files(folder / SCENARIO, data)[-1]
    try:
        planned = load_operations(path)
    except ManikinError as exc:
        raise UsageError(_one_line(exc, path)) from None
    starts = object_starts(scene, arm, planned.objects)
    job = OperateJob(path, folder / "out", len(planned.frames), plan=(planned, starts))
    settings.status, settings.summary, settings.manikin = "", "", arm
    WATCH.start(job, scene)
    return job


def key_run(scene: bpy.types.Scene, arm: bpy.types.Object, job: OperateJob) -> str:
    """Key the finished ``job``'s motion onto ``arm`` and its objects, set the scene's end to its last frame; the
    status line."""
    from .keys import key_objects, key_result

    planned, starts = job.plan
    keys = key_result(scene, arm, job.result)
    keyed = key_objects(scene, arm, keys, planned, starts)
    first, last = keys.frames[0], keys.frames[-1]
    scene.frame_end = max(last, scene.frame_start)
    good = len(keys.frames) - keys.failed
    objects = f"; {', '.join(keyed)} keyed too" if keyed else ""
    return (f"Keyed frames {first}-{last}: {good}/{len(keys.frames)} converged, cycle time "
            f"{planned.plan.duration:.2f} s{objects}")  # fmt: skip
