"""A problem's stacked constraint rows at one point: the scaled slack of its one-sided rows and the live rows of its
scaled Jacobian (:meth:`~solver.problem.problem.Problem.scaled_slack`,
:meth:`~solver.problem.problem.Problem.live_jacobian`), each once per state: the step and the line search ask for
them at the same trial point."""

from __future__ import annotations

from typing import Protocol

import numpy as np

from .. import kernels
from ..body.reduction import Reduction
from ..body.state import State
from ..constraints import Constraint
from ..kernels.reduction import reduce_and_scale


class StackedRows(Protocol):
    """What these read of a :class:`~solver.problem.problem.Problem` (which imports this module): its stacked rows
    and their tables (``Problem._set_constraints``), its solver variables."""

    constraints: list[Constraint]
    n_rows: int
    n_var: int
    row_weight: np.ndarray
    row_tolerance: np.ndarray
    reduction: Reduction | None
    scale: np.ndarray
    _one_sided_at: list[tuple[int, slice]]
    _sizes: list[int]
    _all_rows: np.ndarray
    _row_offsets: np.ndarray
    _row_scale: np.ndarray

    def reduction_jacobian(self, state: State) -> np.ndarray: ...


_NO_REDUCTION = (np.zeros(0, dtype=np.int64), np.zeros(0))  # reduce_and_scale's supports for x itself: scaling only
SLACK = "scaled slack"  # the key of a problem's scaled slack in a state's cache: (problem, SLACK)
ROWS = "jacobian rows"  # the key of a constraint's (rows, Jacobian rows) in a state's cache: (constraint, ROWS)


def scaled_slack(problem: StackedRows, state: State) -> np.ndarray:
    """Per row of ``problem``, how far a met one-sided row is above its floor, times weight / tolerance (0 on the
    other rows), once per state (not to be written to)."""
    key = (problem, SLACK)
    out = state.cache.get(key)
    if out is None:
        out = state.cache[key] = np.zeros(problem.n_rows)
        for i, rows in problem._one_sided_at:  # the one-sided constraints' rows alone: the rest stays 0
            out[rows] = problem.constraints[i].slack(state)
        out *= problem.row_weight  # in place: slack * weight / tolerance, the same rounding
        out /= problem.row_tolerance
    return out


def live_jacobian(problem: StackedRows, state: State) -> tuple[np.ndarray, np.ndarray]:
    """(the rows of ``problem`` that may be nonzero, their rows of its scaled Jacobian (k, n_var))."""
    if not problem.constraints:
        return np.zeros(0, dtype=int), np.zeros((0, problem.n_var))
    rows, jacs, cache = [], [], state.cache  # each constraint's once per state (State.once inline: no closure)
    for c in problem.constraints:
        found = cache.get((c, ROWS))
        found = cache.setdefault((c, ROWS), c.jacobian_rows(state)) if found is None else found
        rows.append(found[0])
        jacs.append(found[1])
    sizes = [len(r) for r in rows]
    if sizes == problem._sizes:
        live = problem._all_rows  # every row (the rows of each are sorted and distinct): no new index array
    else:  # each constraint's rows after the rows of those before it: one addition
        live = np.concatenate(rows)
        live += np.repeat(problem._row_offsets, sizes)
    jac = np.concatenate(jacs)
    red = problem.reduction
    if (red is None or red.linear) and kernels.active():  # the basis product and the scaling in one loop
        out = np.empty((len(jac), problem.n_var))
        supports = _NO_REDUCTION if red is None else red.kernel_supports
        reduce_and_scale(jac, live, problem._row_scale[:, 0], problem.scale, *supports, out)
        return live, out
    jac = in_solver_variables(problem, jac, state)
    jac *= problem._row_scale[live]  # in place: a fresh temporary costs page faults, more than the product
    jac *= problem.scale
    return live, jac


def in_solver_variables(problem: StackedRows, jac: np.ndarray, state: State) -> np.ndarray:
    """d rows / dx (k, n_x) -> d rows / dv (k, n_var) of ``problem``'s solver variables v."""
    red = problem.reduction
    if red is None:
        return jac
    used = np.flatnonzero(jac.any(axis=1))  # met one-sided rows are zero: not worth carrying through phi
    reduced = np.zeros((len(jac), problem.n_var))
    reduced[used] = red.times_basis(jac[used]) if red.linear else jac[used] @ problem.reduction_jacobian(state)
    return reduced
