"""A job's tasks: each one motion (a scenario solved, a result file, or an operations scenario planned and solved)
with how often it is done (per cycle or per shift), the load it handles and the hand forces not from the solver.

::

    [[tasks]]
    name = "box lift"
    scenario = "../scenarios/box_lift_motion.toml"  # or result = "RESULT.json", or operations = "OPS.toml"
    repetitions_per_cycle = 1                        # or repetitions_per_shift = 400 (default: once per cycle)
    lifts_per_repetition = 1                         # handlings of the load in one repetition (default 1)
    [tasks.load]
    mass = 10.0                                      # kg
    hands = "both"                                   # both | right | left
    [[tasks.forces]]                                 # a force at a hand the solver does not know of
    hand = "right"                                   # right | left
    force = [0.0, 50.0, 0.0]                         # N on the hand, world (or magnitude = 50.0, direction = [0, 1, 0])
    frames = [10, 40]                                # first and last frame it acts (default: the whole task)
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..io.table_reader import TableReader

HANDS = {"both": ("hand_r", "hand_l"), "right": ("hand_r",), "left": ("hand_l",)}
FORCE_HANDS = {"right": "hand_r", "left": "hand_l"}
KINDS = ("scenario", "result", "operations")
MAX_REPETITIONS = 1e7  # a typo's bound, far beyond any real job
MAX_FORCE = 5000.0  # N at one hand: far beyond any person's
MAX_FPS = 1000.0


@dataclass(frozen=True)
class Force:
    """A force (N, world) acting ON the hand, as a scenario's [[loads]] (a hand pushing the work forward feels it
    push back); ``frames`` (first, last) frame numbers it acts at, None for the whole task."""

    hand: str  # the TCP: hand_r or hand_l
    force: tuple[float, float, float]  # N, world, acting on the hand
    frames: tuple[int, int] | None

    def acts_at(self, frame: int) -> bool:
        """Whether the force acts at frame number ``frame``."""
        return self.frames is None or self.frames[0] <= frame <= self.frames[1]

    def as_dict(self) -> dict:
        return dict(hand=self.hand, force_N=list(self.force), frames=list(self.frames) if self.frames else "all")


@dataclass(frozen=True)
class Task:
    """One motion of the job and what the methods need beyond it."""

    name: str
    kind: str  # scenario | result | operations
    source: Path
    fps: float | None  # frames per second; None: the operations scenario's own [operate] fps
    per_cycle: int | None  # repetitions per work cycle (exactly one of per_cycle, per_shift)
    per_shift: int | None  # repetitions per shift
    lifts_per_repetition: int
    load_mass: float  # kg
    hands: tuple[str, ...]  # the TCPs holding the load
    forces: tuple[Force, ...] = ()

    def repetitions(self, cycles: int) -> int:
        """Repetitions of the task per shift, with ``cycles`` work cycles per shift."""
        return self.per_shift if self.per_shift is not None else self.per_cycle * cycles

    def lifts(self, cycles: int) -> int:
        """Handlings of the load per shift (LiFFT's and The Shoulder Tool's repetitions)."""
        return self.repetitions(cycles) * self.lifts_per_repetition

    def as_dict(self, cycles: int) -> dict:
        """The task's inputs for the JSON report (s, kg, N)."""
        often = {"repetitions_per_cycle": self.per_cycle} if self.per_shift is None else \
            {"repetitions_per_shift_given": self.per_shift}  # fmt: skip
        return dict(name=self.name, motion={self.kind: str(self.source), "fps": self.fps}, **often,
                    repetitions_per_shift=self.repetitions(cycles), lifts_per_repetition=self.lifts_per_repetition,
                    lifts_per_shift=self.lifts(cycles), load_mass_kg=self.load_mass, hands=list(self.hands),
                    forces=[f.as_dict() for f in self.forces])  # fmt: skip


def read_load(load: TableReader) -> tuple[float, tuple[str, ...]]:
    """A [load] table: (mass kg, the TCPs holding it)."""
    load.known({"mass", "hands"})
    mass = load.number("mass", None, 0.0, 1000.0, "kg")
    hands = HANDS[load.choice("hands", HANDS, "which hands hold the load")] if "hands" in load.data else HANDS["both"]
    return mass, hands


def read_source(t: TableReader, here: Path, kinds: tuple[str, ...]) -> tuple[str, Path]:
    """(kind, path) of the one motion key of ``kinds`` in ``t``; the file must exist (relative to ``here``)."""
    given = [k for k in kinds if k in t.data]
    if len(given) != 1:
        expected = "exactly one of " + ", ".join(kinds) + " (a scenario TOML to solve, a result JSON, ...)"
        raise t.fail(given[0] if given else kinds[0], expected)
    which = given[0]
    source = here / t.string(which)
    if not source.is_file():
        raise t.fail(which, "an existing file (relative to the job file)", str(source))
    return which, source


def read_force(f: TableReader) -> Force:
    """One [[tasks.forces]] entry."""
    f.known({"hand", "force", "magnitude", "direction", "frames"})
    hand = FORCE_HANDS[f.choice("hand", FORCE_HANDS, "the hand the force acts at")]
    if f.exactly_one("force", "magnitude", "exactly one of force = [fx, fy, fz] (N) or magnitude = N with "
                     "direction = [x, y, z]") == "force":  # fmt: skip
        f.known({"hand", "force", "frames"})  # direction without magnitude: named
        vector = f.vector("force", 3, limit=MAX_FORCE, unit="N")
    else:
        size = f.number("magnitude", None, 0.0, MAX_FORCE, "N")
        direction = f.vector("direction", 3, limit=1e6)
        norm = float(np.linalg.norm(direction))
        if norm < 1e-9:
            raise f.fail("direction", "a direction (not all zero)", direction.tolist())
        vector = direction / norm * size
    frames = None
    if "frames" in f.data:
        value = f.data["frames"]
        if not (isinstance(value, list) and len(value) == 2 and all(type(v) is int for v in value)
                and 0 <= value[0] <= value[1] <= 10**7):  # fmt: skip
            raise f.fail("frames", "[first, last] frame numbers, first <= last", value)
        frames = (value[0], value[1])
    return Force(hand, tuple(float(v) for v in vector), frames)


def read_task(t: TableReader, here: Path, index: int) -> Task:
    """One [[tasks]] entry; ``here`` the job file's folder."""
    t.known({"name", *KINDS, "fps", "repetitions_per_cycle", "repetitions_per_shift", "lifts_per_repetition", "load",
             "forces"})  # fmt: skip
    kind, source = read_source(t, here, KINDS)
    if "repetitions_per_cycle" in t.data and "repetitions_per_shift" in t.data:
        raise t.fail("repetitions_per_shift", "one of repetitions_per_cycle or repetitions_per_shift, not both")
    per_shift = t.integer("repetitions_per_shift", None, 0, MAX_REPETITIONS, "a whole number of repetitions per "
                          "shift") if "repetitions_per_shift" in t.data else None  # fmt: skip
    per_cycle = None if per_shift is not None else t.integer("repetitions_per_cycle", 1, 0, 1000,
                                                             "a whole number of repetitions per cycle")  # fmt: skip
    if kind == "operations" and "fps" in t.data:
        raise t.fail("fps", "no fps for an operations scenario (its [operate] fps is used)", t.data["fps"])
    fps = None if kind == "operations" else (t.positive("fps", MAX_FPS, "frames per second") if "fps" in t.data
                                             else 24.0)  # fmt: skip
    t.required("load")
    mass, hands = read_load(t.table("load"))
    return Task(
        name=t.string("name", f"task {index + 1}"), kind=kind, source=source, fps=fps, per_cycle=per_cycle,
        per_shift=per_shift, lifts_per_repetition=t.integer("lifts_per_repetition", 1, 0, 1000, "a whole number of "
                                                            "lifts per repetition"),
        load_mass=mass, hands=hands, forces=tuple(read_force(f) for f in t.table_list("forces")),
    )  # fmt: skip
