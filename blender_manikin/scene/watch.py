"""One background job of a feature watched from Blender (bpy): a population study, a reach envelope computed from
the sidebar. A ``bpy.app.timers`` timer reads the job's progress twice a second, redraws the 3D views and, when the
job has ended, hands it to the feature (fill the table, import the envelope); nothing waits on the subprocess.

A job is anything with ``poll()`` (True while it runs), ``state`` ("running", "cancelling", ...) and ``cancel()``.
"""

from __future__ import annotations

import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

import bpy

POLL_S = 0.5  # s between two looks at a job's progress


def redraw_views() -> None:
    """Redraw every 3D view (their sidebars show the progress); none in background mode."""
    for window in bpy.context.window_manager.windows:
        for area in window.screen.areas:
            if area.type == "VIEW_3D":
                area.tag_redraw()


def base_folder(setting: str, default: str) -> Path:
    """Where a feature's runs go: the folder ``setting`` if given, else the folder ``default`` beside the .blend, else
    ``default`` in the temporary folder (a file never saved)."""
    if setting.strip():
        return Path(bpy.path.abspath(setting))
    if bpy.data.filepath:
        return Path(bpy.data.filepath).parent / default
    return Path(tempfile.gettempdir()) / default


class Watch:
    """The job a feature started last in this session, and the timer that watches it.

    ``ended(scene, job)`` is called once when the job has ended (``scene``: the one it was started from, or None if
    that scene is gone). :attr:`timer` is the one callable registered with ``bpy.app.timers`` (and asked about)."""

    def __init__(self, ended: Callable[[bpy.types.Scene | None, Any], None]) -> None:
        self.job: Any = None
        self.scene_name = ""
        self._ended = ended
        self.timer = self._poll  # one bound method, so registering and is_registered see the same object

    def running(self) -> bool:
        """Whether the job is running or stopping."""
        return self.job is not None and self.job.state in ("running", "cancelling")

    def cancellable(self) -> bool:
        """Whether there is a running job to cancel."""
        return self.job is not None and self.job.state == "running"

    def start(self, job: Any, scene: bpy.types.Scene) -> None:
        """Watch ``job``, started from ``scene``."""
        self.job, self.scene_name = job, scene.name
        if not bpy.app.timers.is_registered(self.timer):
            bpy.app.timers.register(self.timer, first_interval=POLL_S, persistent=True)

    def stop(self) -> None:
        """Cancel a running job and stop watching it (add-on disabled)."""
        if bpy.app.timers.is_registered(self.timer):
            bpy.app.timers.unregister(self.timer)
        if self.cancellable():
            self.job.cancel()
        self.job = None

    def _poll(self) -> float | None:
        """Timer: read the progress; when the job has ended, hand it over and stop (None)."""
        if self.job is None:
            return None
        running = self.job.poll()
        if not running:
            self._ended(bpy.data.scenes.get(self.scene_name), self.job)
        redraw_views()
        return POLL_S if running else None


class CancelJob:
    """What a feature's Cancel operator does (a mixin before ``bpy.types.Operator``): polls its :attr:`watch`, asks the
    job to stop, reports :attr:`stopping` (formatted with ``job``)."""

    watch: Watch
    stopping = "Stopping: {job.done} of {job.total} done"

    @classmethod
    def poll(cls, context: bpy.types.Context) -> bool:
        return cls.watch.cancellable()

    def execute(self, context: bpy.types.Context) -> set[str]:
        job = self.watch.job
        job.cancel()
        self.report({"INFO"}, self.stopping.format(job=job))
        return {"FINISHED"}
