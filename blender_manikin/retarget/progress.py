"""Progress of a long retarget (bpy): the window manager's progress (the cursor's counter) while it runs in the UI,
a printed line per :data:`EVERY` frames in background mode (the batch script, ``blender -b``)."""

from __future__ import annotations

import bpy

EVERY = 100  # frames between two printed lines in background mode


class Progress:
    """Counts the frames sampled, then solved: ``2 * frames`` steps."""

    def __init__(self, label: str, frames: int, window_manager: object | None = None,
                 background: bool | None = None) -> None:  # fmt: skip
        self.label, self.frames = label, frames
        self.background = bpy.app.background if background is None else background
        self.wm = None if self.background else window_manager
        self.lines: list[str] = []

    def __enter__(self) -> Progress:
        if self.wm is not None:
            self.wm.progress_begin(0, 2 * self.frames)
        return self

    def __exit__(self, *_exc) -> None:
        if self.wm is not None:
            self.wm.progress_end()

    def step(self, stage: str, done: int) -> None:
        """``done`` frames of ``stage`` (``sampled`` from the scene, ``solved``) are finished."""
        if self.wm is not None:
            self.wm.progress_update(done + (self.frames if stage == "solved" else 0))
        elif self.background and (done % EVERY == 0 or done == self.frames):
            line = f"{self.label}: {stage} {done}/{self.frames} frames"
            self.lines.append(line)
            print(line, flush=True)
