"""The headless motion pipeline behind ``batch.py`` and the demo (bpy): scene in, bake, files out.

The scene comes from a scenario file (a new manikin with keyed target empties) and/or an open .blend; the
frame range is baked as Bake Motion does, then the requested files are written: the .blend, exports (FBX,
BVH, glTF), a JSON report (per frame: converged, iterations, times, residuals, and the ergonomics of
``solver.ergonomics``), the result JSON of ``python -m solver solve`` and a picture of key poses. Bad input
raises ManikinError with one line; a frame that does not converge makes :func:`run` return 3. The scenario is read
into the scene by the function Import Scenario calls (:func:`..scenario.read.apply_scenario`), never through an
operator of ours. Blender's operators and what prints run through :func:`.quiet.quietly`, so only our own lines
(what was baked and written) reach the console.
"""

from __future__ import annotations

import signal
import sys
import time
import tomllib
from pathlib import Path

import bpy

from ... import solver
from ...solver import ManikinError
from ...solver.io.result.write import ResultWriter
from ...solver.progress import Progress
from ..scenario.keys import target_empties
from ..scenario.read import apply_scenario
from ..scene import display, keyframes
from ..scene.schema import FILE_KEY, PRESET_KEY, is_manikin, members, rig_of
from . import exports
from .bake import Baker, FrameRecord
from .frame_store import STORE_MAX
from .job_input import Job, check_blend, check_job
from .quiet import captured_output, quietly
from .report import MotionReport, captions, choose_frames, summary_lines
from .written import written_by_path

EXIT_OK, EXIT_NOT_CONVERGED, EXIT_INTERRUPTED = 0, 3, 130


def _say(job: Job, text: str) -> None:
    if not job.quiet:
        print(text, flush=True)


def open_scene(job: Job) -> bpy.types.Object:
    """Open the .blend and/or import the scenario (the scene's range becomes its frames); the manikin to bake."""
    if job.blend is not None:
        check_blend(job.blend)
        try:
            quietly(bpy.ops.wm.open_mainfile, filepath=str(job.blend.resolve()), load_ui=False)
        except RuntimeError as exc:
            raise ManikinError(f"{job.blend}: cannot open ({str(exc).strip()})") from None
    if job.scenario is None:
        return find_manikin(job.manikin)
    scenario = solver.load_scenario(job.scenario)  # read first: a bad file is one ScenarioError line, nothing changed
    if job.blend is None:  # a fresh session's default cube, camera and light would only be in the way
        for ob in list(bpy.data.objects):
            bpy.data.objects.remove(ob, do_unlink=True)
        bpy.data.orphans_purge(do_recursive=True)  # and an earlier job's data (the demo's second one): its names
    done = quietly(apply_scenario, bpy.context, scenario, job.scenario.name)  # onto a new manikin
    for warning in done.warnings:
        _say(job, f"warning: {warning}")
    scene, frames = bpy.context.scene, scenario.frames
    scene.frame_start, scene.frame_end = frames[0], frames[-1]  # the scenario's frames (one for a single pose)
    scene.frame_set(frames[0])
    return done.arm


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


class Sinks:
    """Where each baked frame goes as it is solved: the result file (frame by frame) and the report (its
    ergonomics). Nothing is kept per frame but what the plots, captions and summary lines show."""

    def __init__(self, job: Job, arm: bpy.types.Object, model: solver.Model, store: bool = False) -> None:
        self.source = dict(scenario=str(job.scenario) if job.scenario else None,
                           blend=str(job.blend) if job.blend else None)  # fmt: skip
        if job.operations is not None:
            self.source = dict(operations=str(job.operations))
        self.body = arm.get(PRESET_KEY) or arm.get(FILE_KEY, "")
        read = str(job.operations or job.scenario) if job.operations or job.scenario else None  # the result's source
        self.result = ResultWriter(job.result.resolve(), read) if job.result is not None else None
        wanted = job.report is not None or job.picture is not None or job.plots is not None
        plots = job.plots is not None  # store: each frame's sidebar entry too, for the .blend's panels
        self.report = MotionReport(model, self.body, job.report, plots, store) if wanted else None

    def __call__(self, record: FrameRecord, result: solver.Result) -> None:
        state = result.state  # the pose's kinematics and statics, computed once for both
        if self.result is not None:
            self.result.add(record.frame, result, state)
        if self.report is not None:
            self.report.add(record, result, state)

    def discard(self, baker: Baker, reason: str) -> None:
        """After an error: the frames solved so far stay in the result file, which says where and why it stopped."""
        if self.result is not None:
            at = baker.frames[min(baker.done, len(baker.frames) - 1)]
            self.result.close(interrupted_at=at, reason=reason)
        if self.report is not None:
            self.report.discard()


def bake(job: Job, baker: Baker) -> tuple[int | None, float]:
    """Solve the frame range with a progress line; (None, or the frame at which Ctrl-C stopped it, seconds)."""
    n = len(baker.frames)
    _say(job, f"baking {baker.arm.name}: frames {baker.frames[0]}-{baker.frames[-1]} ({n})")
    progress = Progress(n, enabled=not job.quiet, stream=sys.stdout)
    try:
        while not baker.step(0.25):
            progress.update(baker.done, baker.failed)
    except KeyboardInterrupt:
        signal.signal(signal.SIGINT, signal.SIG_IGN)  # the frames solved are being saved: a second Ctrl-C waits
        progress.clear()
        return baker.frames[baker.done], progress.elapsed()
    progress.clear()
    return None, progress.elapsed()


def report_bake(job: Job, baker: Baker, seconds: float) -> None:
    """The lines after a bake (``seconds``: solving, writing each frame out and keying): frames that did not
    converge (the first ten) and the totals."""
    failed = [r for r in baker.records if not r.converged]
    for record in failed[:10]:
        _say(job, f"  NOT converged: {record.why()}")
    if len(failed) > 10:
        _say(job, f"  ... and {len(failed) - 10} more frames not converged")
    n = baker.done
    state = f"{len(failed)} not converged" if failed else "all converged"
    _say(job, f"baked {n} frames in {seconds:.2f} s ({n / max(seconds, 1e-9):.0f} frames/s), {state}")


def write_outputs(job: Job, arm: bpy.types.Object, baker: Baker, sinks: Sinks, stopped: int | None,
                  exported: bpy.types.Object | None = None, posed: list[int] | None = None) -> list[Path]:  # fmt: skip
    """Every requested file, each written path printed; after Ctrl-C (``stopped``: the frame it stopped at) only
    the result, the report and the .blend, which hold the frames solved. Exports write ``exported`` (the retarget
    target), else the manikin. The picture shows the frames ``posed`` (default: the ends, the target empties' keys
    and the middles of the stretches that change most). Returns the paths written."""
    written: list[Path] = []

    def wrote(path: Path | None) -> None:
        if path is not None:
            written.append(path)
            _say(job, f"wrote {path}")

    start, end = baker.frames[0], baker.frames[-1]
    stop = None if stopped is None else dict(at_frame=stopped, solved=baker.done, reason="interrupted (Ctrl-C)")
    if sinks.result is not None:
        wrote(sinks.result.close(interrupted_at=stopped, reason="interrupted (Ctrl-C)"))
    report = sinks.report
    if report is not None and job.report is not None and baker.done:
        wrote(report.write(baker, sinks.source, stop))
        for line in summary_lines(report.summary()):
            _say(job, "  " + line)
    elif report is not None:
        report.discard()
    if job.out is not None:
        wrote(save_blend(job.out.resolve()))
    if stopped is not None:
        return written
    for path in job.exports:
        _say(job, f"exporting {path} ({end - start + 1} frames) ...")
        wrote(quietly(exports.export, exported or arm, path, start, end))
    if job.plots is not None:
        for path in report.plots(job.plots.resolve()):
            wrote(path)
    if job.picture is not None:
        from .picture import render_key_poses

        keys = {round(f) for ob in target_empties(arm) for f in keyframes.key_frames(ob)}
        frames = posed or choose_frames(baker.frames, baker.thetas, sorted(keys))
        shown = f"frame {start}" if start == end else f"frames {start}-{end}"
        title = f"{_title(job, arm)}: {sinks.body}{_carried(arm)}, {shown}, " + (
            f"{len(baker.not_converged())} not converged" if baker.not_converged() else "all converged"
        )
        _say(job, f"rendering frames {', '.join(map(str, frames))} (Cycles, CPU) ...")
        wrote(quietly(render_key_poses, arm, frames, job.picture, captions(report.summary()), title))
    return written


def save_blend(path: Path) -> Path:
    """Save a copy of the scene as ``path`` (a temporary file beside it, checked, then renamed: a full disk leaves
    the old file and says so in one line); its path."""
    with written_by_path(path) as work, captured_output():  # Blender's lines kept out, its error is the reason
        bpy.ops.wm.save_as_mainfile(filepath=str(work), copy=True)
    return path


def _title(job: Job, arm: bpy.types.Object) -> str:
    """The scenario's (or operations file's) name, else the file's or the armature's."""
    source = job.operations or job.scenario
    if source is not None:
        try:
            name = tomllib.loads(source.read_text(encoding="utf-8")).get("name")
        except (OSError, tomllib.TOMLDecodeError):
            name = None
        if isinstance(name, str) and name:
            return name
    return (source or job.blend or Path(arm.name)).stem


def _carried(arm: bpy.types.Object) -> str:
    """The carried mass as ", 10 kg carried" (from the load empties' downward forces), or an empty string."""
    kg = sum(-ob.manikin_target.force[2] / 9.81 for ob in members(arm) if ob.manikin_target.role == "LOAD")
    return f", {kg:.0f} kg carried" if kg >= 0.5 else ""


def retarget_step(job: Job, arm: bpy.types.Object, baker: Baker) -> bpy.types.Object:
    """Key the baked frames onto ``--retarget``'s armature (a shipped rig is built beside the manikin)."""
    from ..retarget.headless import retarget_named

    target, done = retarget_named(job.retarget, arm, (baker.frames[0], baker.frames[-1]))
    _say(job, f"retargeted frames {done.frame_start}-{done.frame_end} onto {target.name}: {done.bones} bones keyed, "
              f"leg-length ratio {done.ratio:.3f}")  # fmt: skip
    return target


def run(job: Job) -> int:
    """Do the job; 0 when every frame converged, 3 when some did not (the files are written either way), 130 when
    Ctrl-C stopped the bake (the frames solved are keyed and kept in the result, the report and the .blend)."""
    check_job(job)
    t0 = time.perf_counter()
    arm = open_scene(job)
    if arm is None or rig_of(arm) is None:
        raise ManikinError("the scenario did not create a manikin")
    display.forget_skins()  # the human is in the scene now: its fitting data would stay through the whole bake
    scene = bpy.context.scene
    start, end = job.frames or (scene.frame_start, scene.frame_end)
    if job.retarget is not None:
        from ..retarget.headless import check_name

        check_name(job.retarget, arm)
    baker = Baker(scene, arm, start, end)
    sinks = baker.on_frame = Sinks(job, arm, baker.model, len(baker.frames) <= STORE_MAX)
    try:
        stopped, seconds = bake(job, baker)
        keyed = baker.write(thin=True, ergo=sinks.report, release=job.picture is None)  # a picture needs them
        report_bake(job, baker, seconds + keyed)
        target = retarget_step(job, arm, baker) if job.retarget is not None and stopped is None else None
        written = write_outputs(job, arm, baker, sinks, stopped, target)
    except BaseException as exc:
        sinks.discard(baker, " ".join(str(exc).split()) or type(exc).__name__)
        raise
    if stopped is not None:
        kept = ", ".join(str(p) for p in written) or "no file (none requested)"
        print(f"interrupted at frame {stopped}; kept {baker.done} solved frames in {kept}", file=sys.stderr)
        return EXIT_INTERRUPTED
    _say(job, f"done in {time.perf_counter() - t0:.1f} s")
    sys.stdout.flush()
    return EXIT_NOT_CONVERGED if baker.not_converged() else EXIT_OK
