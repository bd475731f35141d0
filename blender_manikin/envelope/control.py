"""A reach envelope of the scene's manikin computed from the sidebar (bpy): start it in the background, watch it,
stop it, and import its result onto the manikin. What the operators of the "Reach Envelope" panel call.

:func:`start_envelope` names the run's folder ``<output>/<manikin>_<hand>_<feet>_<hash of body and settings>`` (in
the panel's output folder, else manikin_envelopes beside the .blend, else the temp folder) and starts a
:class:`.job.EnvelopeJob`; the same body and settings again find their finished folder and import it at once. A
``bpy.app.timers`` timer (:func:`poll_job`) reads its progress twice a second and, when it ends, imports its OBJ
files as Import Reach Envelope does (:func:`.objects.import_envelope`); nothing waits on the subprocess.
"""

from __future__ import annotations

import hashlib
import json
import tempfile
from pathlib import Path
from typing import TYPE_CHECKING

import bpy

from ...solver.errors import UsageError
from ...solver.presets import MANIKINS_DIR
from ..scene.schema import FILE_KEY, PRESET_KEY

if TYPE_CHECKING:
    from .job import EnvelopeJob, EnvelopeRequest

POLL_S = 0.5  # s between two looks at the progress
_job: EnvelopeJob | None = None
_where = ("", "")  # (scene, armature) names the running envelope imports into


def current_job() -> EnvelopeJob | None:
    """The envelope started last in this session (running or ended), or None."""
    return _job


def is_running() -> bool:
    """Whether an envelope is being computed or stopped."""
    return _job is not None and _job.state in ("running", "cancelling")


def stop_job() -> None:
    """Cancel a running envelope and stop watching it (add-on disabled)."""
    global _job
    if bpy.app.timers.is_registered(poll_job):
        bpy.app.timers.unregister(poll_job)
    if _job is not None and _job.state == "running":
        _job.cancel()
    _job = None


def _redraw() -> None:
    for window in bpy.context.window_manager.windows:  # none in background mode
        for area in window.screen.areas:
            if area.type == "VIEW_3D":
                area.tag_redraw()


def poll_job() -> float | None:
    """Timer: read the progress; when the envelope has ended, import it (if done), set the status and stop (None)."""
    if _job is None:
        return None
    running = _job.poll()
    if not running:
        scene = bpy.data.scenes.get(_where[0])
        status = _job.line()
        if _job.state == "done":
            status = import_result(_job.request, _job.output, bpy.data.objects.get(_where[1]), status)
        if scene is not None:
            scene.manikin_envelope.status = status
    _redraw()
    return POLL_S if running else None


def import_result(request: EnvelopeRequest, output: Path, arm: bpy.types.Object | None, status: str) -> str:
    """Import the run's OBJ files onto ``arm`` (gone: into the world); the status line, what was imported added."""
    from ...solver.errors import ManikinError
    from .objects import import_envelope

    names = []
    try:
        for path in request.files(output):
            made, _ = import_envelope(bpy.context, str(path), arm)
            names += [ob.name for ob in made]
    except ManikinError as exc:
        return f"Envelope failed: {' '.join(str(exc).split())}"
    return f"{status}; imported {', '.join(names)} from {output}"


def body_of(arm: bpy.types.Object) -> tuple[str, str, str]:
    """(the body as the envelope command takes it: a preset name or a body file's absolute path, its name in the
    files, the text that identifies it: the preset's name and file, or the body file's contents). UsageError if the body
    file is gone."""
    preset = arm.get(PRESET_KEY, "")
    if preset:
        path = MANIKINS_DIR / f"{preset}.toml"  # its contents too: a preset changed by an update is another body
        return preset, preset, preset + (path.read_text(encoding="utf-8") if path.is_file() else "")
    path = Path(bpy.path.abspath(arm.get(FILE_KEY, "")))
    if not path.is_file():
        raise UsageError(f"{arm.name}: its body file {path} is gone; an envelope needs the body")
    return str(path.resolve()), path.stem, path.read_text(encoding="utf-8", errors="replace")


def request_of(settings, arm: bpy.types.Object) -> tuple[EnvelopeRequest, str]:
    """The request of the panel's ``settings`` for ``arm``, and a digest of it and the body's text."""
    from .job import EnvelopeRequest

    body, name, text = body_of(arm)
    s = settings
    request = EnvelopeRequest(body, name, s.hand, s.feet, round(s.load_kg, 6), s.frequency, s.hemisphere,
                              round(s.tolerance, 6), round(s.sole_scale, 6))  # fmt: skip
    key = json.dumps([text, request.hand, request.feet, request.load_kg, request.frequency, request.hemisphere,
                      request.tolerance, request.sole_scale])  # fmt: skip
    return request, hashlib.sha256(key.encode("utf-8")).hexdigest()[:8]


def base_folder(settings) -> Path:
    """Where envelopes go: the output setting, else manikin_envelopes beside the .blend, else in the temp folder."""
    if settings.folder.strip():
        return Path(bpy.path.abspath(settings.folder))
    if bpy.data.filepath:
        return Path(bpy.data.filepath).parent / "manikin_envelopes"
    return Path(tempfile.gettempdir()) / "manikin_envelopes"


def start_envelope(scene: bpy.types.Scene, arm: bpy.types.Object) -> tuple[EnvelopeJob | None, Path]:
    """Compute ``arm``'s envelope with ``scene``'s envelope settings in the background and watch it with
    :func:`poll_job`: (the job, its folder). A finished folder of the same body and settings is imported at once
    instead: (None, that folder), the status says so. UsageError or OSError (one line) for bad input."""
    global _job, _where
    from ...solver.envelope.directions import direction_sphere
    from .job import EnvelopeJob, finished, free_folder

    settings = scene.manikin_envelope
    request, digest = request_of(settings, arm)
    base = base_folder(settings) / bpy.path.clean_name(f"{arm.name}_{request.hand}_{request.feet}_{digest}")
    if finished(request, base):
        settings.status = import_result(request, base, arm, "Computed before with these settings")
        return None, base
    directions = len(direction_sphere(request.frequency, request.hemisphere).directions)
    job = EnvelopeJob(request, free_folder(base), directions)
    _job, _where = job, (scene.name, arm.name)
    settings.status = ""
    if not bpy.app.timers.is_registered(poll_job):
        bpy.app.timers.register(poll_job, first_interval=POLL_S, persistent=True)
    return job, job.output
