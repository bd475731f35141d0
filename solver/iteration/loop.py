"""One phase of the iteration: linearise, step, search, adapt, until a stopping rule fires."""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..body.state import State
from ..options import SolverOptions
from ..problem.problem import Problem
from .curvature_memory import CurvatureMemory
from .line_search import LineSearch, Outcome
from .step import Linearization, Step, compute_step
from .stopping import StagnationWatch, StopReason
from .trial import Evaluator, Trial
from .tuning import Tuning


@dataclass(frozen=True)
class PhaseEnd:
    """Where a phase ended, after how many iterations, and why."""

    trial: Trial
    iterations: int
    reason: StopReason


@dataclass
class _Controls:
    """What the phase adapts between iterations."""

    mu: float  # comfort metric damping (x mean curvature): Levenberg-Marquardt on the comfort model
    radius: float  # trust region of the task step
    rejected: int = 0  # iterations in a row without an accepted step
    hovering: int = 0  # iterations in a row just outside the constraints
    quiet: int = 0  # feasible iterations in a row that gained negligible comfort
    gained: float = 0.0  # what the last accepted step gained in f
    comfort_cap: float = 0.0  # largest entry of the next comfort part (Tuning.comfort_shrink; 0: max_comfort_step)
    dropped: bool = False  # the last line search gave the comfort part up (Tuning.task_first)


def run_phase(
    problem: Problem,
    x: np.ndarray,
    options: SolverOptions,
    tuning: Tuning,
    comfort_on: bool,
    budget: int,
    keep_off_limits: bool = False,
    warm: State | None = None,
) -> PhaseEnd:
    """Up to ``budget`` iterations from solver variables x.

    Without comfort, ``keep_off_limits`` still steps in the comfort's curvature metric (no comfort part), so
    restoring the constraints after the comfort phase does not drive joints onto their limits. ``warm``: a state
    x may be (the previous frame's end), whose values x shares (:meth:`State.adopt`).
    """
    evaluate = Evaluator(problem, comfort_on, warm)
    at = evaluate(x)
    f = evaluate.cost(at.state)
    ctl = _Controls(tuning.initial_mu, tuning.max_step)
    memory = CurvatureMemory(tuning.memory) if comfort_on else None
    watch = StagnationWatch(tuning, comfort_on)
    previous: tuple[Trial, Linearization, Step] | None = None
    move_limit = None  # per joint, the far steps' turn limit: made once a step is far (most frames: never)
    capped = tuning  # the tuning with the comfort part's current cap (ctl.comfort_cap; 0: uncapped)
    for iteration in range(1, budget + 1):
        lin = _linearize(problem, at, comfort_on, keep_off_limits)
        if memory is not None and previous is not None and at.worst <= tuning.comfort_slack:
            _remember(memory, problem, previous, at, lin)
        if ctl.comfort_cap != capped.max_comfort_step:  # dataclasses.replace costs ~10 us: once per new cap
            capped = replace(tuning, max_comfort_step=ctl.comfort_cap) if ctl.comfort_cap else tuning
        step = compute_step(problem, at, lin, ctl.mu, ctl.radius, capped, memory)
        previous = (at, lin, step)
        negligible = options.comfort_tolerance * max(evaluate.size(at.state), 1.0)
        if at.worst <= 1.0 and (step.gain_left <= negligible or ctl.quiet >= 2):
            return PhaseEnd(at, iteration, StopReason.CONVERGED)
        hovers = 1.0 < at.worst <= tuning.comfort_slack and ctl.gained < tuning.hover_gain * negligible
        ctl.hovering = ctl.hovering + 1 if hovers else 0
        if comfort_on and ctl.hovering > tuning.hover_limit:
            return PhaseEnd(at, iteration, StopReason.HOVERING)
        far = at.worst > tuning.comfort_slack
        if move_limit is None and not at.worst <= tuning.comfort_slack:  # far, as LineSearch.near tells (NaN too)
            move_limit = np.where(problem.model.prismatic, tuning.max_slide, tuning.max_turn)
        task_first = (tuning.task_first or (tuning.task_first_far and far)) and ctl.dropped
        outcome = LineSearch(evaluate, at, f, lin, step, tuning, move_limit, task_first).run()
        _adapt_comfort(ctl, outcome, step, tuning, task_first)
        settled = _adapt(ctl, outcome, at, f, step, negligible, tuning, task_first)
        if outcome.trial is not None:
            at, f = outcome.trial, outcome.cost
        elif ctl.rejected >= tuning.max_rejected:
            return PhaseEnd(at, iteration, StopReason.NO_PROGRESS)
        if settled:
            return PhaseEnd(at, iteration, StopReason.CONVERGED)
        if watch.stalled(at.merit, at.worst):
            return PhaseEnd(at, iteration, StopReason.STAGNATED)
    return PhaseEnd(at, budget, StopReason.ITERATION_LIMIT if budget else StopReason.NOT_RUN)


def _linearize(problem: Problem, at: Trial, comfort_on: bool, keep_off_limits: bool) -> Linearization:
    """The constraint Jacobian and the comfort model (or only its curvature, or nothing) at a trial."""
    live, jac = problem.live_jacobian(at.state)
    if comfort_on:
        grad_f, curv_f = problem.comfort_model(at.state)
        rows = problem.comfort_rows(at.state)
        rows = None if rows is None else rows * problem.scale
        return Linearization(jac, live, grad_f, curv_f, True, rows)
    zeros = np.zeros(problem.n_var)  # no comfort gradient (made only here: most linearisations carry comfort)
    if keep_off_limits:
        return Linearization(jac, live, zeros, problem.comfort_model(at.state)[1], False)
    return Linearization(jac, live, zeros, np.zeros(problem.n_var), False)


def _remember(memory: CurvatureMemory, problem: Problem, previous, at: Trial, lin: Linearization) -> None:
    """Add the curvature pair of the last accepted step (only near the constraints: far away the multipliers
    are no estimate yet)."""
    before, lin_before, step_before = previous
    if before.x is at.x:
        return
    lam = step_before.multipliers
    change = lin.grad_f - lin_before.grad_f + lin.jac.T @ lam[lin.live] - lin_before.jac.T @ lam[lin_before.live]
    step = (at.x - before.x) / problem.scale
    if lin.rows is not None:  # the exact low-rank curvature is in the model already: learn only the rest
        change = change - lin.rows.T @ (lin.rows @ step)
    memory.add(step, change)


def _adapt_comfort(ctl: _Controls, outcome: Outcome, step: Step, tuning: Tuning, task_first: bool) -> None:
    """The comfort part's trust region: after comfort was given up, the next comfort part is capped below the
    rejected one; after a full step with comfort the cap doubles back toward ``max_comfort_step``."""
    tried = step.predicted_gain > 0 and not task_first  # the comfort part was tried first
    ctl.dropped = tried and (outcome.trial is None or not outcome.with_comfort)
    if tuning.comfort_shrink >= 1.0:
        return
    if ctl.dropped:
        biggest = float(np.abs(step.comfort).max(initial=0.0))
        ctl.comfort_cap = max(tuning.comfort_shrink * biggest, 1e-6)
    elif ctl.comfort_cap and outcome.trial is not None and outcome.with_comfort and outcome.alpha == 1.0:
        ctl.comfort_cap = min(2.0 * ctl.comfort_cap, tuning.max_comfort_step)
        ctl.comfort_cap = 0.0 if ctl.comfort_cap >= tuning.max_comfort_step else ctl.comfort_cap


def _adapt(
    ctl: _Controls,
    outcome: Outcome,
    at: Trial,
    f: float,
    step: Step,
    negligible: float,
    tuning: Tuning,
    task_first: bool = False,
):
    """Update mu, the trust region and the counters after a line search; True when the phase has settled (a
    full, feasible comfort step that was to gain little, or did gain little as a modest prediction confirmed).
    A search that tried the task part alone (``task_first``) says nothing of the comfort model: mu stays."""
    near = at.worst <= tuning.comfort_slack and not task_first
    factor = tuning.mu_factor
    if near and step.predicted_gain > 0:
        if outcome.trial is not None and outcome.with_comfort:
            ratio = (f - outcome.cost) / (outcome.alpha * step.predicted_gain)
            ctl.mu = (
                ctl.mu / factor
                if (ratio > 0.75 and outcome.alpha == 1.0)
                else (ctl.mu * factor if ratio < 0.25 else ctl.mu)
            )
        else:
            ctl.mu *= factor
    ctl.mu = min(max(float(ctl.mu), 1e-8), 1e8)  # np.clip's value, without its overhead
    if outcome.trial is None:
        ctl.gained = 0.0
        ctl.rejected += 1
        ctl.radius = max(ctl.radius / 4, 1e-6)
        return False
    new = outcome.trial
    gained = f - outcome.cost
    quiet = new.worst <= 1.0 and abs(gained) < negligible and (outcome.with_comfort or step.gain_left <= negligible)
    ctl.quiet = ctl.quiet + 1 if quiet else 0
    ctl.gained = gained
    ctl.rejected = 0
    ctl.radius = min(2 * ctl.radius, tuning.max_step) if outcome.alpha == 1.0 else ctl.radius
    small = step.gain_left < tuning.final_gain * negligible
    confirmed = gained < negligible and step.predicted_gain < 2 * tuning.final_gain * negligible
    return outcome.with_comfort and outcome.alpha == 1.0 and new.worst <= 1.0 and (small or confirmed)
