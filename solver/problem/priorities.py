"""Priorities: what must hold and what is met as closely as it can be when not everything can.

Priority 1 (hard): supports, loops, balance and any extra constraint (e.g. collision distances). Priority 2
(soft): reach targets. A solve first treats every row as a constraint; when that fails, the problem is solved
again *ranked*: the priority-1 rows stay constraints and the priority-2 targets move into the objective as their
shortfall (a smooth distance in tolerances), weighted so that it outweighs comfort. The answer is then the pose
nearest the unreachable targets with the feet on theirs and the body in balance; comfort only decides what reach
leaves free, and keeps joints off the walls of their limits (where it rises faster than REACH_WEIGHT per mm).
Within one priority, shortfalls are traded off by the sum of their distances (in tolerances, x each target's
weight).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..body.state import State
from ..comfort import Comfort
from ..comfort.base import ComfortTerm
from ..constraints import FrameGroup
from .specs import HARD, SOFT

if TYPE_CHECKING:
    from .problem import Problem

REACH_WEIGHT = 100.0  # objective units per tolerance of shortfall: a millimetre of reach outweighs any comfort


class ReachShortfall(ComfortTerm):
    """sum over soft targets of sqrt(1 + |e_t|^2) - 1, e_t a target's weighted errors in tolerances.

    A smooth distance (a pseudo-Huber norm): about |e_t| far off, so the cost counts tolerances (mm, 0.2 deg) of
    shortfall and stays well scaled however far a target is; |e_t|^2 / 2 near it. Its curvature is given exactly
    (Gauss-Newton) as rows R (:meth:`curvature_rows`): a diagonal model of a rank-3 matrix spread over thirty
    joints would overshoot thirtyfold. ``relative`` is False: its size does not set the comfort tolerance.
    """

    name = "reach shortfall"
    relative = False

    def __init__(self, group: FrameGroup) -> None:
        self.group = group
        self.row_scale = group.row_weight() / group.tolerance()
        self.member = group.row_member
        self.starts = np.array([rows.start for rows in group.member_rows], dtype=int)

    def scaled_error(self, state: State) -> np.ndarray:
        """The soft targets' rows, weighted, in tolerances."""
        return self.group.error(state) * self.row_scale

    def _parts(self, state: State) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(scaled row errors e, per target |e_t|, per target sqrt(1 + |e_t|^2))."""
        e = self.scaled_error(state)
        size = np.sqrt(np.add.reduceat(e * e, self.starts)) if len(e) else np.zeros(0)
        return e, size, np.sqrt(1.0 + size * size)

    def cost(self, state: State) -> float:
        return float(np.sum(self._parts(state)[2] - 1.0))

    def derivatives(self, state: State, weight: float) -> tuple[np.ndarray, np.ndarray]:
        e, _, root = self._parts(state)
        jac = self.group.jacobian(state) * self.row_scale[:, None]
        return weight * (jac.T @ (e / root[self.member])), np.zeros(state.n_x)

    def curvature_rows(self, state: State, weight: float) -> np.ndarray | None:
        # Hessian (Gauss-Newton) J^T (I - e e^T / s^2) J / s per target, s = sqrt(1 + |e|^2); its square root
        # shrinks the component along u = e / |e| by 1/s and keeps the rest.
        e, size, root = self._parts(state)
        jac = self.group.jacobian(state) * self.row_scale[:, None]
        along = np.add.reduceat(e[:, None] * jac, self.starts, axis=0)  # |e_t| u_t^T J_t per target
        shrink = np.divide(1.0 - 1.0 / root, size * size, out=np.zeros_like(size), where=size > 0)
        rows = jac - (shrink[self.member] * e)[:, None] * along[self.member]
        return rows * np.sqrt(weight / root)[self.member][:, None]


def ranked(problem: Problem) -> Problem | None:
    """``problem`` with its soft targets moved from the constraints into the objective (None if it has none)."""
    pairs = list(zip(problem.targets, problem.target_constraints, strict=True))
    soft = [c for t, c in pairs if t.effective_priority == SOFT]
    if not soft:
        return None
    hard = [c for t, c in pairs if t.effective_priority == HARD]
    term = ReachShortfall(FrameGroup(soft))
    comfort = Comfort([(REACH_WEIGHT, term), *problem.comfort.terms], problem.comfort.weights)
    return problem.with_frames(hard, comfort)


def hard_unmet(problem: Problem, unmet: list[str]) -> list[str]:
    """The names in ``unmet`` that must hold (everything but the soft targets)."""
    if not unmet:  # a converged result's: no set of names to build
        return []
    soft = {t.tcp for t in problem.targets if t.effective_priority == SOFT}
    return [name for name in unmet if name not in soft]


def soft_shortfall(ranked_problem: Problem, state: State) -> float:
    """The reach-shortfall cost of a :func:`ranked` problem at ``state`` (0 if it has no such term)."""
    return sum(term.cost(state) for _, term in ranked_problem.comfort.terms if isinstance(term, ReachShortfall))


def shortfalls(problem: Problem, unmet: list[str], residuals: dict[str, float]) -> dict[str, dict[str, float]]:
    """Per unmet soft target: how far it is off on what its lock constrains, {"position_m": .., "rotation_deg": ..}
    (or {"combined": ..} in the units of a general operator's rows)."""
    out: dict[str, dict[str, float]] = {}
    if not unmet:  # a converged result's: no target to look at
        return out
    for t in problem.targets:
        if t.effective_priority != SOFT or t.tcp not in unmet:
            continue
        parts = {}
        if f"{t.tcp}.position" in residuals:
            parts["position_m"] = residuals[f"{t.tcp}.position"]
        if f"{t.tcp}.rotation" in residuals:
            parts["rotation_deg"] = float(np.rad2deg(residuals[f"{t.tcp}.rotation"]))
        if t.tcp in residuals:  # a general operator: one combined residual
            parts["combined"] = residuals[t.tcp]
        out[t.tcp] = parts
    return out
