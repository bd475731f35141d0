"""A reach envelope computed in the background: ``python -m solver envelope BODY -o OUT ...`` in a subprocess of the
Python that runs Blender (:mod:`..scene.background`: the extension's solver with the wheels Blender installed, as
a population study runs), watched without ever waiting on it. Its progress is the command's own progress line (on
standard error, a line every few seconds, in ``OUT.log`` beside the output folder); its result the OBJ files it
writes (``<body>_<hand>.obj``). Cancel asks it to stop as Ctrl-C does and kills it after ``GRACE_S``. No bpy here.
"""

from __future__ import annotations

import re
import time
from dataclasses import dataclass
from pathlib import Path

from ..scene.background import interrupt, kill, last_line, solver_command, start

GRACE_S = 5.0  # s a cancelled envelope has to stop by itself before it is killed
EXIT_OK = 0
PROGRESS = re.compile(r"directions (\d+)/(\d+)")  # solver.progress.progress_line, what="directions"
SUMMARY = "envelopes.csv"  # solver.envelope.outputs.SUMMARY: written once an envelope is done


@dataclass(frozen=True)
class EnvelopeRequest:
    """What to compute: the body (a preset name or a body file's absolute path, named ``name`` in the files), the
    hand ("right", "left" or "both"), feet ("planted" or "step"), load (kg), directions (geodesic ``frequency`` and
    ``hemisphere``), ``tolerance`` (m) and ``sole_scale``: the options of ``python -m solver envelope``."""

    body: str
    name: str
    hand: str = "right"
    feet: str = "planted"
    load_kg: float = 0.0
    frequency: int = 3
    hemisphere: str = "all"
    tolerance: float = 0.02
    sole_scale: float = 1.0

    def hands(self) -> tuple[str, ...]:
        return ("right", "left") if self.hand == "both" else (self.hand,)

    def arguments(self, output: Path) -> list[str]:
        """The command line's arguments."""
        return ["envelope", self.body, "-o", str(output), "--hand", self.hand, "--feet", self.feet,
                "--load", repr(float(self.load_kg)), "--frequency", str(self.frequency), "--hemisphere",
                self.hemisphere, "--tolerance", repr(float(self.tolerance)), "--sole-scale",
                repr(float(self.sole_scale)), "--processes", str(len(self.hands()))]  # fmt: skip

    def files(self, output: Path) -> list[Path]:
        """The OBJ files the command writes into ``output``, one per hand."""
        return [output / f"{self.name}_{hand}.obj" for hand in self.hands()]


def finished(request: EnvelopeRequest, output: Path) -> bool:
    """Whether ``output`` holds a finished run of ``request`` (every envelope's OBJ and the summary)."""
    return (output / SUMMARY).is_file() and all(path.is_file() for path in request.files(output))


def free_folder(base: Path) -> Path:
    """``base`` when it is new or empty, else ``base-2``, ``base-3``, ... (the command writes only into a new or
    empty folder; a cancelled run of two hands may have left one)."""
    folder, k = base, 1
    while folder.exists() and (not folder.is_dir() or any(folder.iterdir())):
        k += 1
        folder = base.with_name(f"{base.name}-{k}")
    return folder


class EnvelopeJob:
    """One envelope under way (``directions`` per hand): its subprocess and what became of it (``state``: running,
    cancelling, done, cancelled or failed; ``error`` the command's one line when it failed)."""

    def __init__(self, request: EnvelopeRequest, output: Path, directions: int) -> None:
        self.request, self.output = request, Path(output)
        self.log = self.output.with_name(self.output.name + ".log")
        self.state, self.error = "running", ""
        self.done, self.total = 0, directions * len(request.hands())
        self._cancelled_at: float | None = None
        self.output.parent.mkdir(parents=True, exist_ok=True)
        self.started = time.monotonic()
        self.process = start(solver_command(*request.arguments(self.output)), self.output.parent, self.log)

    def poll(self) -> bool:
        """Read the progress so far and see whether the command ended; True while it runs."""
        self._read_progress()
        code = self.process.poll()
        if code is None:
            if self._cancelled_at is not None and time.monotonic() - self._cancelled_at > GRACE_S:
                kill(self.process)
            return True
        if self._cancelled_at is not None:
            self.state = "cancelled"
        elif code == EXIT_OK and finished(self.request, self.output):
            self.state, self.done = "done", self.total
        else:
            self.state = "failed"
            self.error = last_line(self.log).removeprefix("error: ") or f"the envelope command exited with {code}"
        return False

    def cancel(self) -> None:
        """Ask the command to stop; :meth:`poll` says when it has."""
        if self.process.poll() is not None or self._cancelled_at is not None:
            return
        self._cancelled_at = time.monotonic()
        self.state = "cancelling"
        interrupt(self.process)

    def _read_progress(self) -> None:
        """The count of the command's last progress line."""
        try:
            text = self.log.read_text(encoding="utf-8", errors="replace")
        except OSError:
            return
        found = PROGRESS.findall(text)
        if found:
            self.done = int(found[-1][0])

    def line(self) -> str:
        """The status line the panel shows."""
        seconds = time.monotonic() - self.started
        if self.state in ("running", "cancelling"):
            what = "Stopping" if self.state == "cancelling" else "Computing"
            return f"{what}: {self.done} of {self.total} directions, {seconds:.0f} s"
        if self.state == "failed":
            return f"Envelope failed: {self.error}"
        if self.state == "cancelled":
            return f"Cancelled after {seconds:.0f} s: nothing imported"
        return f"Done: {self.total} directions in {seconds:.0f} s"
