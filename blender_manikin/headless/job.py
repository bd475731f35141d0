"""The headless motion pipeline behind ``batch.py`` and the demo (bpy): scene in, bake, files out.

The scene comes from a scenario file (a new manikin with keyed target empties) and/or an open .blend; the
frame range is baked as Bake Motion does, then the requested files are written: the .blend, exports (FBX,
BVH, glTF), a JSON report (per frame: converged, iterations, times, residuals, and the ergonomics of
``solver.ergonomics``), the result JSON of ``python -m solver solve`` and a picture of key poses. Bad input
raises ManikinError with one line; a frame that does not converge makes :func:`run` return 3. Blender's operators
run through :func:`.quiet.quietly`, so only our own lines (what was baked and written) reach the console.
"""

from __future__ import annotations

import os
import sys
import time
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import bpy

from ... import solver
from ...solver import ManikinError
from ...solver.ergonomics.report import plot_paths
from ...solver.io.output_paths import check_distinct, check_output
from ...solver.options import MAX_FRAME, MAX_FRAMES
from ..scene import exports, keyframes, motion_keys
from ..scene.bake import Baker
from ..scene.schema import FILE_KEY, PRESET_KEY, is_manikin, members, rig_of
from .quiet import quietly
from .report import captions, choose_frames, evaluate_motion, motion_report, summary_lines, write_json

EXIT_OK, EXIT_NOT_CONVERGED = 0, 3


@dataclass
class Job:
    """What to do; paths as given by the user."""

    scenario: Path | None = None
    blend: Path | None = None
    manikin: str | None = None
    frames: tuple[int, int] | None = None
    out: Path | None = None
    exports: list[Path] = field(default_factory=list)
    report: Path | None = None
    result: Path | None = None
    picture: Path | None = None
    plots: Path | None = None
    quiet: bool = False


def _say(job: Job, text: str) -> None:
    if not job.quiet:
        print(text, flush=True)


def open_scene(job: Job) -> bpy.types.Object:
    """Open the .blend and/or import the scenario (the scene's range becomes its frames); the manikin to bake."""
    if job.blend is not None:
        if not job.blend.is_file():
            raise ManikinError(f"{job.blend}: file not found")
        try:
            quietly(bpy.ops.wm.open_mainfile, filepath=str(job.blend.resolve()), load_ui=False)
        except RuntimeError as exc:
            raise ManikinError(f"{job.blend}: cannot open ({str(exc).strip()})") from None
    if job.scenario is None:
        return find_manikin(job.manikin)
    frames = solver.load_scenario(job.scenario).frames  # validates first: a bad file is one ScenarioError line
    for ob in bpy.context.view_layer.objects:
        ob.select_set(False)
    bpy.context.view_layer.objects.active = None  # so the scenario goes onto a new manikin
    if job.blend is None:  # a fresh session's default cube, camera and light would only be in the way
        for ob in list(bpy.data.objects):
            bpy.data.objects.remove(ob, do_unlink=True)
    try:
        quietly(bpy.ops.manikin.import_scenario, filepath=str(job.scenario.resolve()))
    except RuntimeError as exc:
        raise ManikinError(str(exc).strip().removeprefix("Error: ")) from None
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = frames[0], frames[-1]  # the scenario's frames (one for a single pose)
    scene.frame_set(frames[0])
    return bpy.context.view_layer.objects.active


def find_manikin(name: str | None) -> bpy.types.Object:
    """The named manikin armature, or the scene's only one."""
    found = [ob for ob in bpy.context.scene.objects if is_manikin(ob)]
    if name is not None:
        for ob in found:
            if ob.name == name:
                return ob
        raise ManikinError(f"no manikin named {name!r} in the scene (manikins: {', '.join(o.name for o in found)})")
    if not found:
        raise ManikinError("no manikin in the scene: open a .blend with one or pass --scenario FILE.toml")
    if len(found) > 1:
        raise ManikinError(f"several manikins ({', '.join(o.name for o in found)}); choose one with --manikin NAME")
    return found[0]


def bake(job: Job, arm: bpy.types.Object) -> Baker:
    """Solve the frame range with progress lines, then key it."""
    scene = bpy.context.scene
    start, end = job.frames or (scene.frame_start, scene.frame_end)
    keep = any(p is not None for p in (job.report, job.result, job.picture, job.plots))
    baker = Baker(scene, arm, start, end, keep_results=keep)
    n = len(baker.frames)
    _say(job, f"baking {arm.name}: frames {start}-{end} ({n})")
    shown = 0
    while not baker.step(0.25):
        if baker.done - shown >= max(10, n // 10):
            shown = baker.done
            _say(job, f"  frame {baker.records[-1].frame} ({baker.done}/{n})")
    keyed = baker.write()
    for record in baker.records:
        if not record.converged:
            detail = "; ".join(record.notes) or "unmet: " + ", ".join(record.unmet)
            _say(job, f"  frame {record.frame} NOT converged: {detail}")
    solve_s = sum(r.wall_s for r in baker.records)
    failed = baker.not_converged()
    state = f"{len(failed)} not converged: {failed}" if failed else "all converged"
    _say(job, f"baked {n} frames in {solve_s + keyed:.2f} s ({n / (solve_s + keyed):.0f} frames/s), {state}")
    return baker


def write_outputs(job: Job, arm: bpy.types.Object, baker: Baker) -> None:
    """Every requested file; each written path is printed."""
    start, end = baker.frames[0], baker.frames[-1]
    for path in job.exports:
        _say(job, f"wrote {quietly(exports.export, arm, path, start, end)}")
    source = dict(scenario=str(job.scenario) if job.scenario else None, blend=str(job.blend) if job.blend else None)
    body = arm.get(PRESET_KEY) or arm.get(FILE_KEY, "")
    report = None
    if job.report is not None or job.picture is not None or job.plots is not None:
        ergo = evaluate_motion(baker, body)
        report = motion_report(baker, source, body, ergo)
    if job.plots is not None:
        from ...solver.ergonomics.plots import write_plots

        for path in write_plots(ergo, job.plots.resolve()):
            _say(job, f"wrote {path}")
    if job.report is not None:
        _say(job, f"wrote {write_json(report, job.report)}")
        for line in summary_lines(report):
            _say(job, "  " + line)
    if job.result is not None:
        _say(job, f"wrote {solver.write_result(job.result, baker.results, scenario=source['scenario'])}")
    if job.out is not None:
        path = job.out.resolve()
        path.parent.mkdir(parents=True, exist_ok=True)
        quietly(bpy.ops.wm.save_as_mainfile, filepath=str(path), copy=True)
        _say(job, f"wrote {path}")
    if job.picture is not None:
        from .picture import render_key_poses

        keys = {round(f) for ob in motion_keys.target_empties(arm) for f in keyframes.key_frames(ob)}
        frames = choose_frames(baker.frames, baker.thetas, sorted(keys))
        title = f"{_title(job, arm)}: {body}{_carried(arm)}, frames {start}-{end}, " + (
            f"{len(baker.not_converged())} not converged" if baker.not_converged() else "all converged"
        )
        _say(job, f"rendering frames {', '.join(map(str, frames))} (Cycles, CPU) ...")
        _say(job, f"wrote {quietly(render_key_poses, arm, frames, job.picture, captions(report), title)}")


def _title(job: Job, arm: bpy.types.Object) -> str:
    """The scenario's name, else the file's or the armature's."""
    if job.scenario is not None:
        try:
            name = tomllib.loads(job.scenario.read_text(encoding="utf-8")).get("name")
        except (OSError, tomllib.TOMLDecodeError):
            name = None
        if isinstance(name, str) and name:
            return name
    return (job.scenario or job.blend or Path(arm.name)).stem


def _carried(arm: bpy.types.Object) -> str:
    """The carried mass as ", 10 kg carried" (from the load empties' downward forces), or an empty string."""
    kg = sum(-ob.manikin_target.force[2] / 9.81 for ob in members(arm) if ob.manikin_target.role == "LOAD")
    return f", {kg:.0f} kg carried" if kg >= 0.5 else ""


def check_job(job: Job) -> None:
    """The frame range and every output path, before the scene is opened: a bad path never costs a bake."""
    if job.frames is not None:
        first, last = job.frames
        if last < first:
            raise ManikinError(f"--frames {first} {last}: the end comes before the start")
        if not -MAX_FRAME <= first <= last <= MAX_FRAME or last - first >= MAX_FRAMES:
            raise ManikinError(f"--frames {first} {last}: expected frames in [{-MAX_FRAME}, {MAX_FRAME}], "
                               f"at most {MAX_FRAMES} of them")  # fmt: skip
    for path in job.exports:
        exports.check_path(path)
    plots = plot_paths(Path(os.path.abspath(job.plots))) if job.plots is not None else []
    outputs = [("--out", job.out), *(("--export", p) for p in job.exports), ("--report", job.report),
               ("--result", job.result), ("--picture", job.picture), *(("--plots", p) for p in plots)]  # fmt: skip
    for flag, path in outputs:
        if path is not None:
            check_output(path, flag)
    check_distinct(outputs, [("--scenario", job.scenario), ("--blend", job.blend)])


def run(job: Job) -> int:
    """Do the job; 0 when every frame converged, 3 when some did not (the files are written either way)."""
    check_job(job)
    t0 = time.perf_counter()
    arm = open_scene(job)
    if arm is None or rig_of(arm) is None:
        raise ManikinError("the scenario did not create a manikin")
    baker = bake(job, arm)
    write_outputs(job, arm, baker)
    _say(job, f"done in {time.perf_counter() - t0:.1f} s")
    sys.stdout.flush()
    return EXIT_NOT_CONVERGED if baker.not_converged() else EXIT_OK
