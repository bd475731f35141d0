"""Why a solve stopped (recorded on ``Result.stop``) and the watch that ends a phase when the error stops falling."""

from __future__ import annotations

from enum import Enum

from .tuning import Tuning


class StopReason(Enum):
    """Why the iteration ended; the value is what reports print."""

    CONVERGED = "converged"  # constraints met and the next comfort step would gain less than the tolerance
    HOVERING = "hovering"  # comfort kept the iterate just outside the constraints: the restoring phase takes over
    NO_PROGRESS = "no progress"  # every step length was rejected several iterations in a row
    STAGNATED = "stagnated"  # far from the constraints the error stopped falling: targets out of reach
    ITERATION_LIMIT = "iteration limit"  # the iteration budget was used up
    NOT_RUN = "not run"  # no iteration ran (no budget): the start itself
    CLOSEST = "closest"  # not everything could be met: priority 1 met, the reach targets as close as they get

    def describe(self) -> str:
        """One sentence for a person."""
        return {
            StopReason.CONVERGED: "constraints met, comfort at its optimum within the tolerance",
            StopReason.HOVERING: "comfort held the pose just outside the constraints",
            StopReason.NO_PROGRESS: "no step lowered the error any more",
            StopReason.STAGNATED: "the error stopped falling far from the constraints: a target is out of reach",
            StopReason.ITERATION_LIMIT: "the iteration budget ran out",
            StopReason.NOT_RUN: "no iteration ran",
            StopReason.CLOSEST: "supports, loops and balance met, the other targets as close as they can get",
        }[self]


class StagnationWatch:
    """Remembers (merit, worst) after each iteration and tells when, far from the constraints, neither falls.

    Over ``window`` iterations the sum of squares must fall by ``stagnation_gain`` (a shorter window without
    comfort, where every accepted step lowers it), and over the long window the worst row must too: a flat
    worst row under a slowly falling sum is a stall as well.
    """

    def __init__(self, tuning: Tuning, comfort_on: bool) -> None:
        self.gain = tuning.stagnation_gain
        self.long_window = tuning.stagnation_window
        self.window = tuning.stagnation_window if comfort_on else tuning.restore_stagnation_window
        self.above = tuning.comfort_slack if comfort_on else 1.0  # errors below this are never a stall
        self.history: list[tuple[float, float]] = []

    def stalled(self, merit: float, worst: float) -> bool:
        """Record one iteration's end; True when the phase should give up."""
        history = self.history
        history.append((merit, worst))
        if worst <= self.above or len(history) <= self.window:
            return False
        stalled = merit > (1.0 - self.gain) * history[-1 - self.window][0]
        if len(history) > self.long_window:
            stalled |= worst > (1.0 - self.gain) * history[-1 - self.long_window][1]
        return stalled
