"""A solve: the comfort phase, then (if needed) the restoring phase, restarted from the other side of the limits."""

from __future__ import annotations

import time

import numpy as np

from ..body.state import State
from ..options import DEFAULT_OPTIONS, SolverOptions
from ..problem.priorities import ranked, soft_shortfall
from ..problem.problem import Problem
from .loop import PhaseEnd, run_phase
from .restarts import restart_pose
from .result import Result
from .stopping import StopReason
from .trial import Evaluator
from .tuning import TUNING, Tuning


def solve(
    problem: Problem,
    x0: np.ndarray | None = None,
    options: SolverOptions = DEFAULT_OPTIONS,
    tuning: Tuning = TUNING,
    warm: State | None = None,
) -> Result:
    """Find x meeting the constraints and maximising comfort, warm-started from ``x0`` (any earlier pose).

    Comfort is optimised while the constraints are met; if they are not met by the end of that phase (or the
    iterate keeps hovering just outside them), the last iterations restore them with comfort switched off
    (but still in its curvature metric, which keeps joints off their limits). A phase ends early when, far
    from the constraints, the error has stopped falling (unreachable targets: the best compromise, sooner).
    A solve that still fails starts again (up to ``options.restarts`` times) from :func:`restart_pose`. If
    every row cannot be met, the problem is solved again ranked (:mod:`solver.problem.priorities`), on from the best
    unranked end (and from the start if that does not hold priority 1): supports, loops and balance held, reach
    targets as close as they get. The result is the first that meets everything, else
    the one that holds the most of priority 1 and then comes closest to the rest, with the iterations and
    time of all attempts and the reason its last phase stopped (``Result.stop``). ``warm``: the state of the
    previous solve's end (the previous frame's ``Result.state``), whose values a start at the same point shares.
    """
    t0 = time.perf_counter()
    start = problem.start(x0)
    best, used = _with_restarts(problem, start, options, tuning, warm)
    was_ranked = False
    fallback = ranked(problem) if best.trial.worst > 1.0 else None
    # on from where reaching stopped (closer, fewer iterations); from the start again if that broke priority 1
    best_key = _ranking_key(fallback, best) if fallback is not None else None
    for origin in (best.trial.x, start) if fallback is not None else ():
        again, more = _with_restarts(fallback, origin, options, tuning)
        used += more
        key = _ranking_key(fallback, again)
        if key < best_key:
            best, best_key, was_ranked = again, key, True
        if best_key[0] <= 1.0:
            break
    result = Result.from_state(problem, best.trial.state, used, time.perf_counter() - t0)
    settled = best.reason in (StopReason.CONVERGED, StopReason.NO_PROGRESS) and best.trial.worst <= 1.0
    result.stop = StopReason.CLOSEST if (was_ranked and settled) else best.reason
    if was_ranked and result.shortfall:
        result.notes.append(result.verdict())
    return result


def _with_restarts(problem: Problem, start: np.ndarray, options: SolverOptions, tuning: Tuning,
                   warm: State | None = None):  # fmt: skip
    """(the best attempt, iterations of all) from ``start`` and up to ``options.restarts`` restart poses."""
    best = attempt(problem, start, options, tuning, warm)
    used = best.iterations
    for _ in range(options.restarts):
        if best.trial.worst <= 1.0:
            break
        again_from = restart_pose(problem, best.trial.state.x, tuning)
        if again_from is None:
            break
        again = attempt(problem, problem.start(again_from), options, tuning)
        used += again.iterations
        if again.trial.worst < best.trial.worst:
            best = again
    return best, used


def _ranking_key(ranked_problem: Problem, end: PhaseEnd) -> tuple[float, float]:
    """(how far priority 1 is off, beyond its tolerance; the soft targets' squared shortfall), at ``end``."""
    trial = Evaluator(ranked_problem, False)(end.trial.x)
    return max(trial.worst, 1.0), soft_shortfall(ranked_problem, trial.state)


def attempt(problem: Problem, x: np.ndarray, options: SolverOptions, tuning: Tuning = TUNING,
            warm: State | None = None) -> PhaseEnd:  # fmt: skip
    """One solve from solver variables x: the comfort phase, then the restoring phase if the constraints are not
    met; the end of the last phase that ran, with the iterations of both (``warm``: see :func:`solve`)."""
    budget = options.max_iterations
    end: PhaseEnd | None = None
    if options.optimize_comfort:
        polish = min(tuning.polish_iterations, budget // 3)
        end = run_phase(problem, x, options, tuning, True, budget - polish, warm=warm)
    used = end.iterations if end is not None else 0
    if (end is None or end.trial.worst > 1.0) and used < budget:
        x = end.trial.x if end is not None else x
        keep = options.optimize_comfort
        first = warm if end is None else None
        restored = run_phase(problem, x, options, tuning, False, budget - used, keep_off_limits=keep, warm=first)
        end = PhaseEnd(restored.trial, used + restored.iterations, restored.reason)
    if end is None:  # no iteration ran: the start itself
        end = PhaseEnd(Evaluator(problem, False)(x), 0, StopReason.NOT_RUN)
    return end
