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
from pathlib import Path
from typing import TYPE_CHECKING

import bpy

from ...solver.errors import UsageError
from ...solver.presets import MANIKINS_DIR
from ..scene.schema import FILE_KEY, PRESET_KEY
from ..scene.watch import Watch, base_folder

if TYPE_CHECKING:
    from .job import EnvelopeJob, EnvelopeRequest


def _ended(scene: bpy.types.Scene | None, job: EnvelopeJob) -> None:
    """The envelope ended: import it (if done) onto the manikin it was started for; the status says how it went."""
    arm = scene.manikin_envelope.source if scene is not None else None  # a pointer: a renamed manikin still gets it
    status = job.line()
    if job.state == "done":
        status = import_result(job.request, job.output, arm, status)
    if scene is not None:
        scene.manikin_envelope.status = status


WATCH = Watch(_ended)
poll_job = WATCH.timer  # the timer (:mod:`..scene.watch`)
is_running, stop_job = WATCH.running, WATCH.stop


def current_job() -> EnvelopeJob | None:
    """The envelope started last in this session (running or ended), or None."""
    return WATCH.job


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


def start_envelope(scene: bpy.types.Scene, arm: bpy.types.Object) -> tuple[EnvelopeJob | None, Path]:
    """Compute ``arm``'s envelope with ``scene``'s envelope settings in the background and watch it with
    :func:`poll_job`: (the job, its folder). A finished folder of the same body and settings is imported at once
    instead: (None, that folder), the status says so. UsageError or OSError (one line) for bad input."""
    from ...solver.envelope.directions import direction_sphere
    from .job import EnvelopeJob, finished, free_folder

    settings = scene.manikin_envelope
    request, digest = request_of(settings, arm)
    name = bpy.path.clean_name(f"{arm.name}_{request.hand}_{request.feet}_{digest}")
    base = base_folder(settings.folder, "manikin_envelopes") / name
    if finished(request, base):
        settings.status = import_result(request, base, arm, "Computed before with these settings")
        return None, base
    directions = len(direction_sphere(request.frequency, request.hemisphere).directions)
    job = EnvelopeJob(request, free_folder(base), directions)
    settings.status, settings.source = "", arm
    WATCH.start(job, scene)
    return job, job.output
