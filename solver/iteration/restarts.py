"""Where a failed solve starts again: the joints it left at a limit, moved to the other side of their range."""

from __future__ import annotations

import numpy as np

from ..problem.problem import Problem
from .tuning import TUNING, Tuning


def restart_pose(problem: Problem, x: np.ndarray, tuning: Tuning = TUNING) -> np.ndarray | None:
    """The pose x (joints + forces) with every joint that ended within ``restart_near`` of its range from a limit
    moved to ``restart_at`` of its range from the opposite limit; None when no joint ended at a limit.

    A local solver fails mostly in a local minimum: an arm twisted the wrong way round to a hand orientation, its
    forearm or shoulder rotation stopped at a limit. Starting those joints from the other side lets the iteration
    take the other way round.
    """
    model = problem.model
    n = model.n
    theta = x[:n]
    span = model.upper - model.lower
    finite = np.isfinite(span) & (span > 0)
    at_upper = finite & (model.upper - theta < tuning.restart_near * span)
    at_lower = finite & (theta - model.lower < tuning.restart_near * span) & ~at_upper
    if not (at_upper.any() or at_lower.any()):
        return None
    out = np.array(x, dtype=float)
    out[:n][at_upper] = (model.lower + tuning.restart_at * span)[at_upper]
    out[:n][at_lower] = (model.upper - tuning.restart_at * span)[at_lower]
    return out
