"""A population study of the scene's manikin (bpy): start it in the background, watch it, stop it, and load one of
its rows into the scene. What the operators of the "Population Study" panel call, as functions.

:func:`start_study` writes the scene as a scenario (as Export Scenario does, without the pose: every run starts
from the scenario's default start) and a study file into ``<output>/<manikin>_<family>_<hash>/``, checks them as
the study command will (so bad input is one line at once) and starts a :class:`.job.StudyJob`. A
``bpy.app.timers`` timer (:func:`poll_job`) reads its journal twice a second and fills the table when it ends;
nothing waits on the subprocess. :func:`load_row` solves the row's scenario (``python -m solver study
--scenario-of RUN_ID``, through the solver API) and poses a manikin of that body where the study's manikin stands,
as Solve Pose does. Light to import: the solver's numerics load inside the functions.
"""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import TYPE_CHECKING

import bpy

from ...solver.errors import UsageError
from ..scene.schema import is_manikin
from ..scene.watch import Watch, base_folder
from .properties import FAMILIES, FOLDER

if TYPE_CHECKING:
    from ...solver import Result
    from .job import StudyJob



def _ended(scene: bpy.types.Scene | None, job: StudyJob) -> None:
    """The study ended: fill its scene's table with the rows, in the study's order, and say how it ended."""
    if scene is not None:
        fill_table(scene.manikin_study, job.ordered_rows())
        scene.manikin_study.status = job.line()


WATCH = Watch(_ended)
poll_job = WATCH.timer  # the timer (:mod:`..scene.watch`)
is_running, stop_job = WATCH.running, WATCH.stop


def current_job() -> StudyJob | None:
    """The study started last in this session (running or ended), or None."""
    return WATCH.job


def fill_table(settings, rows: list[dict]) -> None:
    """The table's rows from the study's rows (in its order), its score columns from the registry
    (:func:`.table.score_columns`)."""
    from .table import SEP, cell, score_cells, score_columns

    columns = score_columns()
    settings.score_titles = SEP.join(title for title, _ in columns)
    settings.rows.clear()
    for row in rows:
        item = settings.rows.add()
        item.name = str(row.get("manikin", ""))
        item.run_id = str(row.get("run_id", ""))
        item.role = str(row.get("role") or "")
        item.parameters = " ".join(f"{k[2:]}={v:g}" if isinstance(v, float) else f"{k[2:]}={v}"
                                   for k, v in row.items() if k.startswith("p_"))  # fmt: skip
        item.status = str(row.get("failure") or row.get("status", ""))
        item.converged = bool(row.get("converged"))
        item.scores = score_cells(row, columns)
        item.l4_l5, item.shortfall = cell(row.get("l4_l5_peak_N")), cell(row.get("shortfall_m"), 1e3)
    settings.row_index = 0


def family_folder(settings) -> Path:
    """The chosen family's folder, checked by reading its index (one ManikinError line if it does not read)."""
    from ...solver.population import read_family

    if settings.family != FOLDER:
        folder = FAMILIES / settings.family
    elif not settings.family_folder.strip():
        raise UsageError("Family folder: choose a folder written by `python -m solver family`")
    else:
        folder = Path(bpy.path.abspath(settings.family_folder))
    read_family(folder)
    return folder.resolve()


def offsets(settings) -> tuple[str, tuple[str, ...], tuple[float, ...]]:
    """(axis or "", the targets' TCP names, the values in m) of the parameter the study varies."""
    if settings.vary == "NONE":
        return "", (), ()
    tcps = tuple(settings.tcps.replace(",", " ").split())
    if not tcps:
        raise UsageError("Targets: name the TCPs of the targets to move, e.g. hand_r hand_l")
    try:
        values = tuple(float(v) for v in re.split(r"[,\s;]+", settings.values.strip()) if v)
    except ValueError:
        raise UsageError(f"Values: expected offsets in m separated by commas, got {settings.values!r}") from None
    if not values or not all(math.isfinite(v) for v in values):
        raise UsageError(f"Values: expected finite offsets in m separated by commas, got {settings.values!r}")
    return settings.vary, tcps, values


def check_targets(arm: bpy.types.Object, scenario: dict, axis: str, tcps: tuple[str, ...]) -> None:
    """Refuse, with one UsageError line naming them, TCPs the study would move that have no target on ``arm``."""
    have = [str(t.get("tcp")) for t in scenario.get("targets", [])]
    missing = [tcp for tcp in tcps if tcp not in have]
    if missing:
        known = ", ".join(dict.fromkeys(have)) or "none"
        raise UsageError(f"Targets: {arm.name} has no target on {', '.join(missing)} to move by offset_{axis} "
                         f"(its targets: {known})")  # fmt: skip


def study_folder(settings, arm: bpy.types.Object, family: Path, inputs: list) -> Path:
    """``<output>/<manikin>_<family>_<hash of the inputs>``, in the output setting or in manikin_studies beside the
    .blend (or in the temp folder): the same study again goes on in its folder, another gets its own."""
    from ...solver.study.spec import digest

    name = bpy.path.clean_name(f"{arm.name}_{family.name}_{digest(inputs)[:8]}")
    return base_folder(settings.folder, "manikin_studies") / name


def start_study(scene: bpy.types.Scene, arm: bpy.types.Object) -> tuple[StudyJob, Path]:
    """Start a study of ``arm``'s targets with ``scene``'s study settings and watch it with :func:`poll_job`; (the
    job, its folder). ManikinError or OSError (one line) for bad input, before anything runs (a target the study
    would move that is not there: before anything is written)."""
    from ...solver.io.files import write_text
    from ...solver.io.scenario.write import write_scenario_files
    from ...solver.study import load_study
    from ...solver.study.plan import plan
    from ..scenario.write import scene_scenario
    from .job import StudyJob, study_text

    settings = scene.manikin_study
    family = family_folder(settings)
    axis, tcps, values = offsets(settings)
    scenario = scene_scenario(arm)
    check_targets(arm, scenario, axis, tcps)  # before anything is written
    text = study_text(family, "scenario.toml", f"{arm.name} x {family.name}", axis, tcps, values)
    folder = study_folder(settings, arm, family, [scenario, text])
    write_scenario_files(folder / "scenario.toml", scenario)
    study = Path(write_text(folder / "study.toml", text))
    run_ids = [run.run_id for run in plan(load_study(study))]
    job = StudyJob(study, folder / "out", run_ids, settings.workers)
    settings.rows.clear()
    settings.status, settings.study_file, settings.source = "", str(study), arm
    WATCH.start(job, scene)
    return job, folder


def load_row(context: bpy.types.Context, settings, run_id: str) -> tuple[bpy.types.Object, Result]:
    """Solve the row ``run_id`` of the settings' study and pose a manikin of its body with it: (armature, Result).
    The manikin is the scene's of that body, else a new one; it ends selected and active."""
    from ... import solver
    from ...solver.io.files import write_text
    from ...solver.study.export import row_scenario
    from ..scenario.read import body_source, rig_source
    from ..scene import armature, problem_io

    study = Path(settings.study_file)
    if not study.is_file():
        raise UsageError(f"{study}: the study file is gone; run the study again")
    path = write_text(study.parent / "rows" / f"{run_id}.toml", row_scenario(study, run_id))
    scenario = solver.load_scenario(path)
    result = list(solver.solve_motion(scenario))[-1][1]
    source = body_source(scenario.model)
    found = (ob for ob in context.scene.objects if is_manikin(ob) and rig_source(ob, resolved=True) == source)
    arm = next(found, None)
    if arm is None:
        preset, file = source.get("preset", ""), source.get("file", "")
        arm = armature.create_manikin(context, armature.load_model(preset, file), preset, file, at_cursor=False)
    where = settings.source  # a pointer: renaming the manikin keeps it
    if where is not None and where is not arm:
        arm.matrix_world = where.matrix_world.copy()  # the study's targets are in its manikin's frame
    context.view_layer.update()
    problem_io.write_result(arm, result)
    for ob in context.view_layer.objects.selected:
        ob.select_set(False)
    arm.select_set(True)
    context.view_layer.objects.active = arm
    return arm, result
