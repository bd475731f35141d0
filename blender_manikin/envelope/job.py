"""A reach envelope computed in the background: ``python -m solver envelope BODY -o OUT ...`` in a subprocess of the
Python that runs Blender (:mod:`..scene.background`: the extension's solver with the wheels Blender installed, as
a population study runs), watched without ever waiting on it. Its progress is the command's own progress line (on
standard error, a line every few seconds, in ``OUT.log`` beside the output folder); its result the OBJ files it
writes (``<body>_<hand>.obj``). Cancel asks it to stop as Ctrl-C does and kills it after a grace time. No bpy here.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

from ..scene.background import CommandJob, solver_command

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


class EnvelopeJob(CommandJob):
    """One envelope under way (``directions`` per hand): its subprocess and what became of it (:class:`CommandJob`)."""

    PROGRESS = PROGRESS
    WORDS = dict(command="envelope", verb="Computing", unit="directions", cancelled="nothing imported",
                 failed="Envelope")  # fmt: skip

    def __init__(self, request: EnvelopeRequest, output: Path, directions: int) -> None:
        self.request, self.output = request, Path(output)
        self.output.parent.mkdir(parents=True, exist_ok=True)
        log = self.output.with_name(self.output.name + ".log")
        command = solver_command(*request.arguments(self.output))
        self.begin(command, self.output.parent, log, directions * len(request.hands()))

    def ended_well(self, code: int) -> bool:
        return code == EXIT_OK and finished(self.request, self.output)
