"""A population study run in the background: ``python -m solver study STUDY.toml -o OUT -q`` in a subprocess of
the Python that runs Blender, watched through the study's journal (``OUT/runs.jsonl``) without ever waiting on it.

The subprocess and its environment (the extension's ``solver``, the wheels Blender installed, the same numpy)
are :mod:`..scene.background`'s, shared with a reach envelope computed from the sidebar.

Cancel asks the study to stop as Ctrl-C does (SIGINT: it keeps the finished rows, writes its tables and exits 130);
if it has not stopped after ``GRACE_S``, its whole process group (the study and its worker processes) is killed.
Either way the journal keeps every finished row, and running the same study again goes on from there.
"""

from __future__ import annotations

import json
import os
import time
from pathlib import Path

from ..scene.background import child_env, interrupt, kill, last_line, python_path, solver_command, start

__all__ = ["StudyJob", "child_env", "last_line", "python_path", "study_command", "study_text"]

JOURNAL = "runs.jsonl"  # solver.study.outputs.JOURNAL (not imported: this module stays light)
LOG = "study.log"  # the subprocess's standard error, in the output folder
GRACE_S = 5.0  # s a cancelled study has to stop by itself before it is killed
EXIT_DONE = (0, 3)  # every run converged; some did not (a finished study either way)
EXIT_INTERRUPTED = 130


def study_command(study: Path, output: Path, workers: int) -> list[str]:
    """The command the study runs as (``workers`` 0: all cores but one, which Blender keeps)."""
    count = workers or max(1, (os.cpu_count() or 2) - 1)
    return solver_command("study", str(study), "-o", str(output), "-q", "--workers", str(count))


class StudyJob:
    """One study under way: its subprocess, the rows of its runs (``run_ids``, in the study's order) found in the
    journal so far, and what became of it (``state``: running, cancelling, done, cancelled or failed)."""

    def __init__(self, study: Path, output: Path, run_ids: list[str], workers: int = 0) -> None:
        self.study, self.output, self.run_ids = Path(study), Path(output), list(run_ids)
        self.wanted = set(self.run_ids)
        self.rows: dict[str, dict] = {}
        self.state = "running"
        self.error = ""
        self._offset, self._rest = 0, b""
        self._cancelled_at: float | None = None
        self.output.mkdir(parents=True, exist_ok=True)
        self._read_journal()
        self.kept = len(self.rows)  # finished before this start (a resumed study)
        self.started = time.monotonic()
        self.process = start(study_command(self.study, self.output, workers), self.study.parent, self.output / LOG)

    @property
    def done(self) -> int:
        return len(self.rows)

    @property
    def total(self) -> int:
        return len(self.run_ids)

    def rate(self) -> float:
        """Runs per second finished by this start (0 before the first)."""
        seconds = time.monotonic() - self.started
        return (self.done - self.kept) / seconds if seconds > 0 else 0.0

    def poll(self) -> bool:
        """Read the rows finished since the last poll and see whether the study ended; True while it runs."""
        self._read_journal()
        code = self.process.poll()
        if code is None:
            if self._cancelled_at is not None and time.monotonic() - self._cancelled_at > GRACE_S:
                self._kill()
            return True
        self._read_journal()
        if self._cancelled_at is not None:
            self.state = "cancelled"
        elif code in EXIT_DONE:
            self.state = "done"
        else:
            self.state = "failed"
            self.error = last_line(self.output / LOG).removeprefix("error: ") or f"the study exited with {code}"
        return False

    def cancel(self) -> None:
        """Ask the study to stop (see the module docstring); :meth:`poll` says when it has."""
        if self.process.poll() is not None or self._cancelled_at is not None:
            return
        self._cancelled_at = time.monotonic()
        self.state = "cancelling"
        interrupt(self.process)

    def _kill(self) -> None:
        kill(self.process)  # the study and its workers (one session)

    def _read_journal(self) -> None:
        """Add the journal's complete lines since the last read; rows of other studies in the folder are skipped."""
        try:
            with open(self.output / JOURNAL, "rb") as fh:
                fh.seek(self._offset)
                chunk = fh.read()
        except OSError:
            return
        self._offset += len(chunk)
        *lines, self._rest = (self._rest + chunk).split(b"\n")
        for line in lines:
            try:
                row = json.loads(line)
            except ValueError:
                continue  # a line a killed study cut short
            if isinstance(row, dict) and row.get("run_id") in self.wanted:
                self.rows[row["run_id"]] = row

    def ordered_rows(self) -> list[dict]:
        """The rows found, in the study's order."""
        return [self.rows[i] for i in self.run_ids if i in self.rows]

    def line(self) -> str:
        """The status line the panel shows."""
        counts = f"{self.done} of {self.total} runs"
        if self.state in ("running", "cancelling"):
            rate = self.rate()
            left = f", about {(self.total - self.done) / rate:.0f} s left" if rate > 0 else ""
            what = "Stopping" if self.state == "cancelling" else "Running"
            return f"{what}: {counts} ({rate:.1f} runs/s{left})"
        if self.state == "failed":
            return f"Study failed: {self.error}"
        ok = sum(bool(r.get("converged")) for r in self.rows.values())
        if self.state == "cancelled":
            return f"Cancelled: {counts} kept, {ok} converged (Run Study again to go on)"
        return f"Done: {counts}, {ok} converged"


AXES = "xyz"


def study_text(family: Path, scenario: str, name: str, axis: str = "", tcps: tuple[str, ...] = (),
               values: tuple[float, ...] = ()) -> str:  # fmt: skip
    """The study file: every member of the family folder ``family`` on the scenario file ``scenario`` (beside the
    study file), and, with an ``axis`` ("x", "y" or "z"), the parameter ``offset_<axis>``: each of ``values`` (m)
    added to that coordinate of the targets of ``tcps``."""
    from ...solver.errors import ScenarioError
    from ...solver.io.toml_write import dumps_toml

    scene: dict = {"file": scenario, "name": "scene"}
    if axis:
        paths = [f"targets.{tcp}.position[{AXES.index(axis)}]" for tcp in tcps]
        scene["parameters"] = {f"offset_{axis}": {"values": [float(v) for v in values], "add": paths}}
    data = {"manikins": [{"family": str(family), "name": family.name}], "study": {"name": name}, "scenarios": [scene]}
    head = "# A study the Blender sidebar wrote (Manikin > Population Study): python -m solver study this -o out/\n"
    return head + dumps_toml(data, ScenarioError)
