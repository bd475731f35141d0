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

A path is relative to the job file. Bad input is one line naming the file and the key (exit 2).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from ..errors import UsageError
from ..io.files import read_toml
from ..io.table_reader import TableReader

HANDS = {"both": ("hand_r", "hand_l"), "right": ("hand_r",), "left": ("hand_l",)}
MAX_REPETITIONS = 1e7  # cycles per shift: a typo's bound, far beyond any real job
MAX_SHIFT_H = 24.0


@dataclass(frozen=True)
class Job:
    """A job as read from its file: the motion (exactly one of ``scenario``/``result``) and the work around it."""

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

    @property
    def lifts(self) -> int:
        """Lifts per shift: cycles x lifts per cycle."""
        return self.repetitions * self.lifts_per_cycle

    def as_dict(self) -> dict:
        """The job's inputs for the JSON report (units in the key names' docs: s, h, kg)."""
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
    root.known({"name", "motion", "work", "load"})
    root.required("motion", "work", "load")
    motion, work, load = root.table("motion"), root.table("work"), root.table("load")
    motion.known({"scenario", "result", "fps"})
    which = motion.exactly_one("scenario", "result", "exactly one of scenario (a TOML to solve) or result (a JSON)")
    source = path.parent / motion.string(which)
    if not source.is_file():
        raise motion.fail(which, "an existing file (relative to the job file)", str(source))
    work.known({"cycle_time", "repetitions", "shift", "lifts_per_cycle"})
    shift = work.positive("shift", MAX_SHIFT_H, "h")
    cycle_time = work.positive("cycle_time", shift * 3600.0, "s")
    repetitions = work.integer("repetitions", None, 0, MAX_REPETITIONS, "a whole number of cycles per shift")
    if repetitions * cycle_time > shift * 3600.0 * (1 + 1e-9):
        raise work.fail("repetitions", f"at most {shift * 3600.0 / cycle_time:.0f} cycles of {cycle_time:g} s in a "
                        f"{shift:g} h shift", repetitions)  # fmt: skip
    load.known({"mass", "hands"})
    return Job(
        path=path,
        name=root.string("name", path.stem),
        scenario=source if which == "scenario" else None,
        result=source if which == "result" else None,
        fps=motion.positive("fps", 1000.0, "frames per second") if "fps" in motion.data else 24.0,
        cycle_time=cycle_time,
        repetitions=repetitions,
        shift=shift,
        lifts_per_cycle=work.integer("lifts_per_cycle", 1, 0, 1000, "a whole number of lifts per cycle"),
        load_mass=load.number("mass", None, 0.0, 1000.0, "kg"),
        hands=HANDS[load.choice("hands", HANDS, "which hands hold the load")]
        if "hands" in load.data
        else HANDS["both"],
    )
