"""What every job method gets and gives: :class:`JobInputs` (the job, the motion's frames, the per-frame ergonomics
report) and :class:`Method` (a name, a title, its published source, and :meth:`Method.evaluate`)."""

from __future__ import annotations

from dataclasses import dataclass

from ..io.result.frame import Frame
from .spec import Job


@dataclass(frozen=True)
class JobInputs:
    """The job, the frames of its motion (one work cycle's motion), and the ``ergo`` report of those frames
    (:func:`solver.ergonomics.evaluate`, its ``frames`` in the same order)."""

    job: Job
    frames: list[Frame]
    ergo: dict

    @property
    def frame_time(self) -> float:
        """s each frame stands for (1 / fps)."""
        return 1.0 / self.job.fps

    @property
    def motion_time(self) -> float:
        """s the motion lasts: its frames x the frame time."""
        return len(self.frames) * self.frame_time


def verdict(text: str, severity: int | None, frames: list[int] | None = None, task: str | None = None) -> dict:
    """A method's verdict on the job: one line, severity 0 (green) / 1 (yellow) / 2 (red) / None (no rating), the
    frames that drive it and, in a job of several tasks, the task those frames are of."""
    return dict(text=text, severity=severity, frames=frames or []) | ({"task": task} if task is not None else {})


@dataclass(frozen=True)
class TaskResult:
    """One task's result of a method, with how often the task is done: what :meth:`Method.combine` adds up."""

    name: str
    result: dict
    repetitions: int  # per shift
    per_cycle: float  # repetitions per work cycle (a per-shift task's: per shift / cycles per shift)
    motion_time: float  # s, one repetition

    @property
    def frames(self) -> list[int]:
        return self.result["verdict"]["frames"]


def worst(tasks: list[TaskResult]) -> TaskResult:
    """The task whose verdict is most severe (red before yellow before green before not rated); the first of ties."""
    return max(tasks, key=lambda t: -1 if t.result["verdict"]["severity"] is None else t.result["verdict"]["severity"])


# entries of a method's result that are not numbers for its detail table
RESERVED = ("verdict", "per_frame", "plot", "levers", "per_task")


def lever(frame: int, origin, end, length: float, label: str) -> dict:
    """A lever arm a method rates, for the driving frame's picture: from ``origin`` to ``end`` (world m) at frame
    number ``frame``, ``length`` m the horizontal distance the method uses."""
    return dict(frame=frame, origin=[float(v) for v in origin], end=[float(v) for v in end], length_m=length,
                label=label)  # fmt: skip


class Method:
    """One job method. ``evaluate`` returns a JSON-safe dict with at least ``verdict`` (:func:`verdict`); an entry
    ``per_frame`` (column name -> one value per frame) goes into the CSV; into the HTML go :meth:`detail`'s tables,
    ``plot`` (optional: ``kind`` "line" with ``y`` per-frame columns, ``label``, ``title`` and ``marks`` (frame
    indices to dot), or "levels" with ``order`` (column -> its levels in order)), and a picture of each verdict frame
    with the ``levers`` (:func:`lever`) of that frame."""

    name = ""
    title = ""
    source = ""

    def evaluate(self, inputs: JobInputs) -> dict:
        raise NotImplementedError

    def combine(self, job, tasks: list[TaskResult]) -> dict:
        """The job's result from its tasks' (one task: that task's result). By default the most severe task's
        verdict, named; a method whose published form adds tasks up overrides this."""
        if len(tasks) == 1:
            return tasks[0].result
        w = worst(tasks)
        v = w.result["verdict"]
        return dict(verdict=verdict(f"{w.name}: {v['text']}", v["severity"], v["frames"], w.name),
                    per_task=[dict(task=t.name, verdict=t.result["verdict"]["text"]) for t in tasks])  # fmt: skip

    def detail(self, result: dict) -> list[tuple[str, list[str], list[list]]]:
        """The HTML's tables of ``result``, each (heading, header, rows); by default one of its single numbers."""
        rows = [[k, v] for k, v in result.items() if k not in RESERVED and not isinstance(v, dict | list)]
        return [(self.title, ["quantity", "value"], rows)] if rows else []
