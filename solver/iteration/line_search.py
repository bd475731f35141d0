"""The line search of one iteration: trials along the step, and the rules that accept or reject each."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .. import kernels
from ..kernels import step as compiled
from ..kernels.trial import step_point
from .step import Linearization, Step
from .trial import Evaluator, Trial

if TYPE_CHECKING:
    from .tuning import Tuning

_MAX = np.maximum.reduce  # np.max without its Python wrapper (the same reduction)
_WHOLE = np.zeros(0)  # step_point's ``task`` for a whole step along one direction
CONTACT_LOOKAHEAD = 0.05  # m: a clearance row farther than this at the start counts as this far (the query's margin)


@dataclass(slots=True)
class Outcome:
    """What the line search found: the accepted trial (None if every try failed) and how it was reached."""

    trial: Trial | None
    cost: float  # f at the accepted trial
    alpha: float  # the step length that was accepted (or the last tried)
    with_comfort: bool  # whether the comfort part was in the accepted step (or the last tried)


class LineSearch:
    """Tries the step of one iteration from ``at`` (cost ``f``) and judges each trial.

    Far from the constraints only the task part matters (comfort may ride along if the error still falls);
    near them task + comfort comes first, judged on the exact-penalty merit after a second-order correction,
    then the task part alone with a safeguarded quadratic backtracking.
    """

    def __init__(
        self,
        evaluate: Evaluator,
        at: Trial,
        f: float,
        lin: Linearization,
        step: Step,
        tuning: Tuning,
        move_limit,
        task_first: bool = False,
    ) -> None:
        """``move_limit``: per joint, the largest change of a step far from the constraints (rad or m);
        ``task_first``: the task part alone only (the last iteration gave comfort up: ``Tuning.task_first``)."""
        self.task_first = task_first
        self.evaluate, self.at, self.f, self.lin, self.step, self.tuning = evaluate, at, f, lin, step, tuning
        self.move_limit = move_limit
        self.problem = evaluate.problem
        self.near = at.worst <= tuning.comfort_slack
        self.joints = self.problem.joint_supports() if (kernels.active() and not self.near) else None
        self.task_change = 0.0  # f's predicted rise from the task part alone: a ride-along need not undo it
        if not self.near and step.predicted_gain > 0:
            task, grad_f, curv_f = step.task, lin.grad_f, lin.curv_f
            self.task_change = max(float(grad_f @ task + 0.5 * (curv_f * task) @ task), 0.0)

    def attempts(self) -> list[tuple[bool, int]]:
        """(with comfort, tries) in the order they are tried."""
        t = self.tuning
        if self.step.predicted_gain <= 0 or self.task_first:
            return [(False, t.task_tries)]
        if self.near:
            return [(True, t.near_comfort_tries), (False, t.task_tries - 1)]
        return [(True, t.far_comfort_tries), (False, t.task_tries)]

    def run(self) -> Outcome:
        alpha, with_comfort = 1.0, False
        for with_comfort, tries in self.attempts():
            found, alpha = self._try(with_comfort, tries)
            if found is not None:
                return Outcome(found, self.evaluate.cost(found.state), alpha, with_comfort)
        return Outcome(None, self.f, alpha, with_comfort)

    def _direction(self, with_comfort: bool) -> np.ndarray:
        step = self.step
        direction = step.task + step.comfort if with_comfort else step.task
        if not self.near:  # far away, a joint turns at most max_turn per step: the linear model holds about that far
            direction = self._turn_limited(direction)
        return direction

    def _turn_limited(self, change: np.ndarray) -> np.ndarray:
        """The scaled step ``change`` shortened so that no joint turns more than its ``move_limit``."""
        problem = self.problem
        if self.joints is not None:  # the same numbers in one loop (solver.kernels.step.turn_share)
            share = compiled.turn_share(change, problem.scale, *self.joints, self.move_limit)
        else:
            move = np.abs(problem.joint_change(self.at.state, change * problem.scale)) / self.move_limit
            share = float(_MAX(move, initial=0.0))
        return change / max(share, 1.0)

    def _point(self, alpha: float, direction: np.ndarray, task: np.ndarray) -> np.ndarray:
        """The clipped trial point x + alpha direction (x + (task + alpha direction) with a ``task``), by the kernel."""
        bounds, x = self.problem.bounds, self.at.x
        out = np.empty(len(x))
        step_point(x, alpha, direction, task, bounds.scale, bounds.lower, bounds.upper, out)
        return out

    def _try(self, with_comfort: bool, tries: int) -> tuple[Trial | None, float]:
        """Up to ``tries`` step lengths along one direction: (the accepted trial or None, the last alpha).

        With ``Tuning.comfort_retry`` near the constraints, alpha scales only the comfort part of a comfort try
        (the task part stays whole) and shrinks by that factor after a rejection."""
        at, problem = self.at, self.problem
        direction = self._direction(with_comfort)
        lin = self.lin
        slope = 0.0 if with_comfort else 2.0 * float(at.err[lin.live] @ (lin.jac @ direction))  # d merit / d alpha at 0
        hopeless = self.tuning.hopeless * self.tuning.comfort_slack
        retry = self.tuning.comfort_retry if (with_comfort and self.near) else 0.0
        if kernels.active():  # the same point in one loop (solver.kernels.trial.step_point)
            moved, task = (self.step.comfort, self.step.task) if retry else (direction, _WHOLE)

            def along(a: float) -> np.ndarray:
                return self._point(a, moved, task)
        elif retry:
            task, comfort = self.step.task, self.step.comfort

            def along(a: float) -> np.ndarray:
                return problem.bounds.clip(at.x + (task + a * comfort) * problem.scale)
        else:

            def along(a: float) -> np.ndarray:
                return problem.bounds.clip(at.x + a * direction * problem.scale)

        shrink = retry or 0.5
        alpha = 1.0
        for _ in range(tries):
            trial = self.evaluate(along(alpha))
            trial, alpha = self._short_of_contact(trial, alpha, along)
            if with_comfort and self.near and trial.worst > hopeless:
                alpha *= shrink  # too far off for a correction to bring it back: shorten without trying one
                continue
            if not (with_comfort and self.near and not self.tuning.correct_accepted and self._accepts(trial, True)):
                trial = self._corrected(trial, with_comfort, alpha)
            if self._accepts(trial, with_comfort):
                return trial, alpha
            if with_comfort or not math.isfinite(trial.merit):
                alpha *= shrink
            else:  # minimum of the quadratic through merit(0), its slope and merit(alpha), safeguarded
                bend = (trial.merit - at.merit - alpha * slope) / alpha**2
                guess = -slope / (2.0 * bend) if (slope < 0.0 and bend > 0.0) else 0.5 * alpha
                alpha = min(max(float(guess), 0.1 * alpha), 0.5 * alpha)  # np.clip's value, without its overhead
        return None, alpha

    def _accepts(self, trial: Trial, with_comfort: bool) -> bool:
        """The acceptance rule, on a finite trial with a finite cost."""
        if not (self._better(trial, with_comfort) and math.isfinite(trial.merit)):
            return False
        return math.isfinite(self.evaluate.cost(trial.state))

    def _short_of_contact(self, trial: Trial, alpha: float, along) -> tuple[Trial, float]:
        """(trial, alpha), cut back to where the first obstacle row met at the start would reach its clearance, when
        the trial goes into it by more than its tolerance: the step's linear model sees only the rows near contact,
        so a long step would carry a hand into an obstacle it did not know of (and out again only slowly). Linear in
        alpha from the row's slack (at most CONTACT_LOOKAHEAD: rows farther are not measured exactly) to its depth.
        The floor's and the body's own rows are not cut for: parts pass them on the way to good poses and come back
        out quickly (docs/TUNING.md)."""
        at, problem = self.at, self.problem
        if not problem.any_obstacle_rows:  # nothing to stop short of (the mask below would be all False)
            return trial, alpha
        entered = problem.obstacle_rows & (at.err == 0.0) & (trial.err * self.evaluate.unweight < -1.0)
        if not entered.any():
            return trial, alpha
        entered[self.lin.live] = False  # rows in the step's model (within their watch band) are held by the step
        if not entered.any():
            return trial, alpha
        scale = (problem.row_weight / problem.row_tolerance)[entered]
        slack = np.minimum(problem.scaled_slack(at.state)[entered], CONTACT_LOOKAHEAD * scale)
        share = float(np.min(slack / (slack - trial.err[entered])))
        if share < self.tuning.least_contact_share:
            return trial, alpha  # already touching it: the step's hold keeps it, a cut would stall
        alpha *= share
        return self.evaluate(along(alpha)), alpha

    def _corrected(self, trial: Trial, with_comfort: bool, alpha: float) -> Trial:
        """The trial after a second-order correction, when one applies and lowers the error below its bar.

        A comfort step near the constraints is pulled back onto them (kept if it lowers the error); a full step
        that the constraints' curvature undid (the balance moment is bilinear in joint motion and forces) gets
        the same correction before backtracking (kept if it beats the current error).
        """
        if with_comfort and self.near:
            bar = trial.merit if trial.worst > 1.0 else None
        else:
            full = self.evaluate.comfort_on and alpha == 1.0
            bar = self.at.merit if (full and self.at.merit <= trial.merit < np.inf) else None
        if bar is None:
            return trial
        problem = self.problem
        change = (trial.x - self.at.x) / problem.scale + self.step.correction(trial.err)
        if not self.near:  # the corrected step keeps the far steps' turn limit too
            change = self._turn_limited(change)
        if kernels.active():
            x_soc = self._point(1.0, change, _WHOLE)  # 1.0 * change: the same numbers
        else:
            x_soc = problem.bounds.clip(self.at.x + change * problem.scale)
        corrected = self.evaluate(x_soc)
        return corrected if corrected.merit < bar else trial

    def _better(self, trial: Trial, with_comfort: bool) -> bool:
        """The acceptance rule of the part being tried."""
        at, f = self.at, self.f
        if not with_comfort:
            return trial.merit < at.merit
        cost = self.evaluate.cost
        if not self.near:  # comfort rides along a task step: the error falls and comfort ends no worse than predicted
            if not self.tuning.far_comfort_check:  # the error falls: the near phase mends what comfort lost
                return trial.merit < at.merit
            return trial.merit < at.merit and cost(trial.state) < f + self.task_change + self.step.predicted_gain
        # the exact-penalty merit, or (as a filter would) any feasible point that is more comfortable
        weight = self.step.penalty * (self.tuning.penalty_margin / 2.0)  # Step.penalty is 2 max |lambda|
        penalty = weight * (np.abs(trial.err).sum() - np.abs(at.err).sum())
        cost_try = cost(trial.state)
        feasible_gain = trial.worst <= 1.0 and cost_try < f
        return trial.worst <= self.tuning.comfort_slack and (cost_try - f + penalty < 0.0 or feasible_gain)
