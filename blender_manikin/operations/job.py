"""A motion generated from operations in the background: ``python -m solver operate SCENARIO -o OUT`` in a
subprocess of the Python that runs Blender (:mod:`..scene.background`: the extension's solver with the wheels Blender
installed, as a population study and a reach envelope run), watched without ever waiting on it. Its progress is the
command's progress line on standard error (``OUT/operate.log``: "frames 120/300 ..."), its result ``OUT/result.json``
and ``OUT/summary.txt``. Cancel asks it to stop as Ctrl-C does and kills it after ``GRACE_S``. No bpy here.
"""

from __future__ import annotations

import re
import time
from pathlib import Path

from ..scene.background import interrupt, kill, last_line, solver_command, start

GRACE_S = 5.0  # s a cancelled run has to stop by itself before it is killed
EXIT_DONE = (0, 3)  # every frame converged; some did not (a finished motion either way)
LOG = "operate.log"
RESULT, SUMMARY = "result.json", "summary.txt"  # what ``solver operate`` writes into its folder
PROGRESS = re.compile(r"frames (\d+)/(\d+)")  # solver.progress.progress_line
LABEL = re.compile(r"operations\[(\d+)\]")  # the solver's label of an operation: its index in the list


def numbered(text: str) -> str:
    """The solver's "operations[2] (place box)" as the panel's list numbers it: "operation 3 (place box)"."""
    return LABEL.sub(lambda m: f"operation {int(m.group(1)) + 1}", text)


class OperateJob:
    """One generation under way (``total`` frames): its subprocess and what became of it (``state``: running,
    cancelling, done, cancelled or failed; ``error`` the command's one line when it failed). ``plan`` is whatever
    the caller keeps with it (the planned job, for keying the objects)."""

    def __init__(self, scenario: Path, output: Path, total: int, plan: object = None) -> None:
        self.scenario, self.output, self.total, self.plan = Path(scenario), Path(output), total, plan
        self.state, self.error, self.done = "running", "", 0
        self._cancelled_at: float | None = None
        self.output.mkdir(parents=True, exist_ok=True)
        for old in (self.result, self.summary_path):  # an earlier run's: never mistaken for this one's
            old.unlink(missing_ok=True)
        self.started = time.monotonic()
        command = solver_command("operate", str(self.scenario), "-o", str(self.output))
        self.process = start(command, self.scenario.parent, self.output / LOG)

    @property
    def result(self) -> Path:
        return self.output / RESULT

    @property
    def summary_path(self) -> Path:
        return self.output / SUMMARY

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
        elif code in EXIT_DONE and self.result.is_file():
            self.state, self.done = "done", self.total
        else:
            self.state = "failed"
            why = last_line(self.output / LOG).removeprefix("error: ")
            self.error = numbered(why) or f"the operate command exited with {code}"
        return False

    def cancel(self) -> None:
        """Ask the command to stop; :meth:`poll` says when it has."""
        if self.process.poll() is not None or self._cancelled_at is not None:
            return
        self._cancelled_at = time.monotonic()
        self.state = "cancelling"
        interrupt(self.process)

    def summary(self) -> list[str]:
        """The command's summary lines (per operation its frames and how many converged; the cycle time)."""
        try:
            text = self.summary_path.read_text(encoding="utf-8", errors="replace")
        except OSError:
            return []
        return [numbered(line) for line in text.splitlines() if line.strip()]

    def _read_progress(self) -> None:
        found = PROGRESS.findall(last_line(self.output / LOG))
        if found:
            self.done = int(found[-1][0])

    def line(self) -> str:
        """The status line the panel shows while it runs, or how it ended."""
        seconds = time.monotonic() - self.started
        if self.state in ("running", "cancelling"):
            what = "Stopping" if self.state == "cancelling" else "Generating"
            return f"{what}: {self.done} of {self.total} frames solved, {seconds:.0f} s"
        if self.state == "failed":
            return f"Generate failed: {self.error}"
        if self.state == "cancelled":
            return f"Cancelled after {seconds:.0f} s: nothing keyed"
        return f"Solved {self.total} frames in {seconds:.0f} s"
