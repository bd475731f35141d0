"""Result files written frame by frame, so memory stays flat however long the motion: each frame is turned into
text and appended as it is solved, into ``NAME.tmp`` beside the file, which is renamed onto it at the end.

The result JSON is written as ``{"scenario": ..., "frames": [`` then one frame per line, then ``]}``; the compact
format (JSON Lines) as a header line and one line per frame. A run that stops early (Ctrl-C, an error) still
ends with a valid file holding the frames solved so far and says so: ``"interrupted": {"at_frame", "solved",
"reason"}`` (a last key of the JSON, a last line of the compact file). Ctrl-C is held while a frame is written
(:func:`interrupts_held`), so a frame is in the file whole or not at all.
"""

from __future__ import annotations

import json
from collections.abc import Iterable
from pathlib import Path
from types import TracebackType
from typing import TYPE_CHECKING

from ...errors import ManikinError, UsageError
from ...iteration.result import Result
from ..files import OutputFile
from ..interrupts import interrupts_held
from .document import compact_header
from .frame_text import PoseText
from .line_text import CompactText

if TYPE_CHECKING:
    from ...body.state import State

COMPACT_SUFFIXES = (".jsonl", ".ndjson")


def is_compact_path(path: str | Path) -> bool:
    """Whether a file of this name is written in the compact format by default (``.jsonl``)."""
    return Path(path).suffix.lower() in COMPACT_SUFFIXES


class ResultWriter:
    """Appends (frame, Result) pairs to the result file ``path``; :meth:`close` puts it in place.

    ``compact``: the JSON Lines format (default: for a ``.jsonl`` path). Use as a context manager: leaving the
    block by an exception keeps the frames written so far (marked interrupted) and re-raises.
    """

    def __init__(self, path: str | Path, scenario: str | Path | None = None, compact: bool | None = None) -> None:
        self.path = Path(path)
        self.compact = is_compact_path(self.path) if compact is None else compact
        self.scenario = None if scenario is None else str(scenario)
        self.count = 0  # frames written
        self.last_frame: int | None = None
        self._out = OutputFile(path)  # a temporary file renamed into place by close(); "-" standard output
        self._file = self._out.stream
        self.closed = False
        self.written: Path | None = None  # the file once closed with frames in it
        self._pose = PoseText()  # the result JSON's frames as text, the parts the frames share encoded once
        self._compact = CompactText()  # the compact file's lines, joint values unchanged since the last keeping theirs
        if not self.compact:
            head = {} if self.scenario is None else {"scenario": self.scenario}
            self._file.write(json.dumps(head)[:-1] + (", " if head else "") + '"frames": [')

    def add(self, frame: int, result: Result, state: State | None = None) -> None:
        """Append one frame (its text is built first, then written whole with Ctrl-C held); ``state``: the result's
        state if the caller has it."""
        if self.compact:
            head = "" if self.count else json.dumps(compact_header(result.problem.model, self.scenario)) + "\n"
            text = head + self._compact(result, frame, state) + "\n"
        else:
            text = ("\n" if self.count == 0 else ",\n") + self._pose.result_frame(result, frame, state)
        with interrupts_held():
            try:
                self._file.write(text)
                self._file.flush()
            except OSError as exc:
                raise ManikinError(f"{self.path}: cannot write ({exc.strerror or exc})") from None
            self.count += 1
            self.last_frame = frame

    def close(self, interrupted_at: int | None = None, reason: str = "interrupted") -> Path | None:
        """Finish the file and rename it into place; returns its path. ``interrupted_at``: the frame at which the
        run stopped (the file then says so). With no frame written, nothing replaces ``path`` (returns None)."""
        if self.closed:
            return self.written
        self.closed = True
        with interrupts_held():
            stop = None if interrupted_at is None else dict(at_frame=interrupted_at, solved=self.count, reason=reason)
            if self.compact:
                self._file.write("" if stop is None else json.dumps({"interrupted": stop}) + "\n")
            else:
                self._file.write("\n]" + ("" if stop is None else ',\n"interrupted": ' + json.dumps(stop)) + "}\n")
            if self.count == 0:
                self._out.discard()
                return None
            self._out.commit()
        self.written = self.path
        return self.path

    def __enter__(self) -> ResultWriter:
        return self

    def __exit__(self, kind: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None) -> None:
        if not self.closed:
            if kind is None:
                self.close()
            else:
                after = None if self.last_frame is None else self.last_frame + 1
                self.close(interrupted_at=after, reason="interrupted" if kind is KeyboardInterrupt else kind.__name__)


def write_result(
    path: str | Path,
    results: Result | Iterable[tuple[int, Result]],
    scenario: str | Path | None = None,
    compact: bool | None = None,
) -> Path:
    """Write a result file: one Result (frame 1) or (frame, Result) pairs as :func:`solver.solve_motion` yields them
    (an iterator is written as it goes, holding one frame at a time); ``scenario`` names the scenario file (the
    ergonomics finds the manikin there). ``compact``: the JSON Lines format (default: for a ``.jsonl`` path).
    Atomic; returns the path."""
    pairs = [(1, results)] if isinstance(results, Result) else results
    with ResultWriter(path, scenario, compact) as writer:
        for number, result in pairs:
            writer.add(number, result)
    if writer.written is None:
        raise UsageError(f"{path}: no frames to write (nothing written)")
    return writer.written
