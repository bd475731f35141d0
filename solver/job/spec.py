"""The job file (``presets/jobs/*.toml``): the motion of one work cycle and what the job methods need beyond it.

::

    name = "box lift"
    [motion]
    scenario = "../scenarios/box_lift_motion.toml"  # solved when the job runs; or result = "RESULT.json"
    fps = 24                                         # frames per second of the motion
    [work]
    cycle_time = 30.0                                # s, one work cycle (the motion and any time between)
    repetitions = 800                                # cycles per shift
    shift = 8.0                                      # h
    lifts_per_cycle = 1                              # lifts of the load in one cycle (LiFFT repetitions)
    [load]
    mass = 10.0                                      # kg, the load lifted
    hands = "both"                                   # both | right | left: which hands hold it

Or several motions, each a ``[[tasks]]`` entry (:mod:`.tasks`) instead of ``[motion]`` and ``[load]``; the
single form is one task (done once per cycle, its lifts ``lifts_per_cycle``). A path is relative to the job file.
Bad input is one line naming the file and the key (exit 2).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path

from ..errors import UsageError
from ..io.files import read_toml
from ..io.table_reader import TableReader
from .tasks import HANDS, MAX_REPETITIONS, Task, read_load, read_source, read_task

MAX_SHIFT_H = 24.0
__all__ = ["HANDS", "Job", "Task", "read_job"]


@dataclass(frozen=True)
class Job:
    """A job as read from its file: its tasks and the work around them. The single form's motion (``scenario`` or
    ``result``), fps, load and hands are also its fields (the first task's in a ``[[tasks]]`` job); a method
    rating one task gets :meth:`for_task`, whose fields are that task's."""

    path: Path
    name: str
    scenario: Path | None
    result: Path | None
    fps: float  # frames per second of the motion
    cycle_time: float  # s
    repetitions: int  # cycles per shift
    shift: float  # h
    lifts_per_cycle: int
    load_mass: float  # kg
    hands: tuple[str, ...]  # the TCPs holding the load
    tasks: tuple[Task, ...] = ()  # () only for a Job built by hand: then it is the single form's one task
    single: bool = True  # the single [motion]/[load] form

    @property
    def lifts(self) -> int:
        """Lifts per shift: of the one task (cycles x lifts per cycle in the single form), or of all tasks."""
        if not self.tasks:
            return self.repetitions * self.lifts_per_cycle
        return sum(t.lifts(self.repetitions) for t in self.tasks)

    def for_task(self, task: Task, fps: float) -> Job:
        """This job seen by a method rating ``task`` alone (its motion at ``fps``): the task's load, hands, lifts."""
        return replace(self, name=task.name, fps=fps, load_mass=task.load_mass, hands=task.hands, tasks=(task,),
                       lifts_per_cycle=task.lifts_per_repetition * (task.per_cycle or 0))  # fmt: skip

    def as_dict(self) -> dict:
        """The job's inputs for the JSON report (units in the key names' docs: s, h, kg)."""
        work = dict(file=str(self.path), name=self.name, cycle_time_s=self.cycle_time,
                    repetitions_per_shift=self.repetitions, shift_h=self.shift)  # fmt: skip
        if not self.single:
            return work | dict(lifts_per_shift=self.lifts, tasks=[t.as_dict(self.repetitions) for t in self.tasks])
        motion = {"scenario": str(self.scenario)} if self.scenario else {"result": str(self.result)}
        return dict(
            file=str(self.path), name=self.name, motion=motion | {"fps": self.fps}, cycle_time_s=self.cycle_time,
            repetitions_per_shift=self.repetitions, shift_h=self.shift, lifts_per_cycle=self.lifts_per_cycle,
            lifts_per_shift=self.lifts, load_mass_kg=self.load_mass, hands=list(self.hands),
        )  # fmt: skip


def read_job(path: str | Path) -> Job:
    """The job in the TOML file ``path``; any bad or missing value is one UsageError line naming file and key."""
    path = Path(path)
    root = TableReader(path, read_toml(path, UsageError), error=UsageError)
    root.known({"name", "motion", "work", "load", "tasks"})
    if "tasks" in root.data:
        for key in ("motion", "load"):
            if key in root.data:
                raise root.fail(key, "no [motion] or [load] beside [[tasks]] (each task has its own)")
        root.required("work")
    else:
        root.required("motion", "work", "load")
    work = root.table("work")
    work.known({"cycle_time", "repetitions", "shift"} | (set() if "tasks" in root.data else {"lifts_per_cycle"}))
    shift = work.positive("shift", MAX_SHIFT_H, "h")
    cycle_time = work.positive("cycle_time", shift * 3600.0, "s")
    repetitions = work.integer("repetitions", None, 0, MAX_REPETITIONS, "a whole number of cycles per shift")
    if repetitions * cycle_time > shift * 3600.0 * (1 + 1e-9):
        raise work.fail("repetitions", f"at most {shift * 3600.0 / cycle_time:.0f} cycles of {cycle_time:g} s in a "
                        f"{shift:g} h shift", repetitions)  # fmt: skip
    name = root.string("name", path.stem)
    if "tasks" in root.data:
        readers = root.table_list("tasks", non_empty=True)
        tasks = tuple(read_task(t, path.parent, i) for i, t in enumerate(readers))
        for i, task in enumerate(tasks):  # the report's sections and the CSV's task column go by name
            if task.name in (t.name for t in tasks[:i]):
                raise readers[i].fail("name", "a name no other task has", task.name)
        first = tasks[0]
        return Job(path=path, name=name, scenario=first.source if first.kind != "result" else None,
                   result=first.source if first.kind == "result" else None, fps=first.fps or 24.0,
                   cycle_time=cycle_time, repetitions=repetitions, shift=shift, lifts_per_cycle=0,
                   load_mass=first.load_mass, hands=first.hands, tasks=tasks, single=False)  # fmt: skip
    motion = root.table("motion")
    motion.known({"scenario", "result", "fps"})
    which, source = read_source(motion, path.parent, ("scenario", "result"))
    fps = motion.positive("fps", 1000.0, "frames per second") if "fps" in motion.data else 24.0
    lifts_per_cycle = work.integer("lifts_per_cycle", 1, 0, 1000, "a whole number of lifts per cycle")
    mass, hands = read_load(root.table("load"))
    task = Task(name, which, source, fps, 1, None, lifts_per_cycle, mass, hands)
    return Job(path=path, name=name, scenario=source if which == "scenario" else None,
               result=source if which == "result" else None, fps=fps, cycle_time=cycle_time, repetitions=repetitions,
               shift=shift, lifts_per_cycle=lifts_per_cycle, load_mass=mass, hands=hands, tasks=(task,))  # fmt: skip
