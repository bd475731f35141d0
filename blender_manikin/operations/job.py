"""A motion generated from operations in the background: ``python -m solver operate SCENARIO -o OUT`` in a
subprocess of the Python that runs Blender (:mod:`..scene.background`: the extension's solver with the wheels Blender
installed, as a population study and a reach envelope run), watched without ever waiting on it. Its progress is the
command's progress line on standard error (``OUT/operate.log``: "frames 120/300 ..."), its result ``OUT/result.json``
and ``OUT/summary.txt``. Cancel asks it to stop as Ctrl-C does and kills it after a grace time. No bpy here.
"""

from __future__ import annotations

import re
from pathlib import Path

from ..scene.background import CommandJob, solver_command

EXIT_DONE = (0, 3)  # every frame converged; some did not (a finished motion either way)
LOG = "operate.log"
RESULT, SUMMARY = "result.json", "summary.txt"  # what ``solver operate`` writes into its folder
PROGRESS = re.compile(r"frames (\d+)/(\d+)")  # solver.progress.progress_line
LABEL = re.compile(r"operations\[(\d+)\]")  # the solver's label of an operation: its index in the list


def numbered(text: str) -> str:
    """The solver's "operations[2] (place box)" as the panel's list numbers it: "operation 3 (place box)"."""
    return LABEL.sub(lambda m: f"operation {int(m.group(1)) + 1}", text)


class OperateJob(CommandJob):
    """One generation under way (``total`` frames): its subprocess and what became of it (:class:`CommandJob`).
    ``plan`` is whatever the caller keeps with it (the planned job, for keying the objects)."""

    PROGRESS = PROGRESS
    WORDS = dict(command="operate", verb="Generating", unit="frames", cancelled="nothing keyed", failed="Generate")

    def __init__(self, scenario: Path, output: Path, total: int, plan: object = None) -> None:
        self.scenario, self.output, self.plan = Path(scenario), Path(output), plan
        self.output.mkdir(parents=True, exist_ok=True)
        for old in (self.result, self.summary_path):  # an earlier run's: never mistaken for this one's
            old.unlink(missing_ok=True)
        command = solver_command("operate", str(self.scenario), "-o", str(self.output))
        self.begin(command, self.scenario.parent, self.output / LOG, total)

    @property
    def result(self) -> Path:
        return self.output / RESULT

    @property
    def summary_path(self) -> Path:
        return self.output / SUMMARY

    def ended_well(self, code: int) -> bool:
        return code in EXIT_DONE and self.result.is_file()

    def failure(self, code: int) -> str:
        return numbered(super().failure(code))

    def summary(self) -> list[str]:
        """The command's summary lines (per operation its frames and how many converged; the cycle time)."""
        try:
            text = self.summary_path.read_text(encoding="utf-8", errors="replace")
        except OSError:
            return []
        return [numbered(line) for line in text.splitlines() if line.strip()]
