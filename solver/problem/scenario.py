"""A scenario: the model, the problem at its first frame, solver options, start pose and, for a motion, keyed frames.

Files are read by :func:`solver.load_scenario` (``solver/io/scenario/read.py``) and written by
``solver/io/scenario/write.py``. Units: m, rad, N, kg.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..body.model import Model
from ..collision.carried import Carried
from ..options import MotionLimits, SolverOptions
from .problem import Problem
from .tracks import Track, targets_at


@dataclass
class Scenario:
    """A parsed scenario: the model, the problem (at the first frame), solver options, start pose, frames.

    ``tracks`` hold the keyed targets of a motion; :meth:`problem_at` gives the problem at any frame.
    """

    path: Path
    model: Model
    problem: Problem
    options: SolverOptions
    start: np.ndarray
    frames: list[int]
    tracks: list[Track]
    limits: MotionLimits | None
    carried: Carried | None = None  # a box held between two TCPs ([carried]): the problem keeps the body out

    @property
    def frame(self) -> int:
        return self.frames[0]

    @property
    def is_motion(self) -> bool:
        """Whether the scenario has keyed targets or more than one frame to solve."""
        return bool(self.tracks) or len(self.frames) > 1

    def problem_at(self, frame: int) -> Problem:
        """The problem with every keyed target at its pose for ``frame``."""
        if not self.tracks:
            return self.problem
        return self.problem.with_targets(targets_at(self.problem.all_targets, self.tracks, frame))
