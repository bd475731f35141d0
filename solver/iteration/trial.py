"""A trial point of one iteration: its variables, state and scaled error, evaluated once (cost cached per state)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..body.state import State
from ..problem.problem import Problem

COST = "iteration cost"  # f = -h of a state and its relative size, kept under (the comfort, COST)
PARTS = "comfort parts"  # the comfort's parts, kept under (the comfort, PARTS): the result of a solve reuses them


@dataclass(slots=True)
class Trial:
    """One evaluated point: solver variables, state, scaled error and its measures (never modified)."""

    x: np.ndarray  # solver variables
    state: State
    err: np.ndarray  # scaled error rows (weight / tolerance)
    merit: float  # sum of squares of ``err``
    worst: float  # largest |row error| / tolerance, weights taken out: <= 1 means met


class Evaluator:
    """Evaluates x once into a :class:`Trial`; f = -h on demand (:meth:`cost`), since trial points rejected on
    their error never need it."""

    def __init__(self, problem: Problem, comfort_on: bool, warm: State | None = None) -> None:
        self.problem = problem
        self.comfort_on = comfort_on
        self.unweight = 1.0 / problem.row_weight if problem.n_rows else np.zeros(0)
        self.warm = warm  # a state the first point may be (:meth:`State.adopt`): the previous frame's end

    def __call__(self, x: np.ndarray) -> Trial:
        state = self.problem.state(x)
        if self.warm is not None:
            comfort = self.problem.comfort
            users = (*self.problem.constraints, comfort, self.problem.contacts, *(term for _, term in comfort.terms))
            state.adopt(self.warm, {id(o) for o in users})
            self.warm = None
        err, worst = self.problem.scaled_error_and_worst(state, self.unweight)
        return Trial(x, state, err, float(err @ err), worst)

    def cost(self, state: State) -> float:
        """f = -h at ``state`` (0 without comfort), computed once per state."""
        both = state.cache.get((self.problem.comfort, COST))  # asked ~40 times a solve: no second call
        return self._cost_and_size(state)[0] if both is None or not self.comfort_on else both[0]

    def size(self, state: State) -> float:
        """The part of f whose size sets the relative comfort tolerance (see ``ComfortTerm.relative``)."""
        return self._cost_and_size(state)[1]

    def _cost_and_size(self, state: State) -> tuple[float, float]:
        if not self.comfort_on:
            return 0.0, 0.0
        comfort = self.problem.comfort
        both = state.cache.get((comfort, COST))
        if both is None:
            parts = state.cache[comfort, PARTS] = comfort.parts(state)
            both = state.cache[comfort, COST] = (-comfort.total(parts), comfort.relative_size(parts))
        return both
