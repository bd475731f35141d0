"""One-sided constraints g(x) >= floor (clearances, heights): met rows are zero, so they plug into the stacked rows.

The error of a row is min(g - floor, 0): zero while the row is met, so it neither pulls nor takes a rank of the
task step, and its Jacobian row is dg/dx only while it is violated (an active set that the iteration need not
know about). Comfort steps may touch such a bound; the next task step pushes back onto it.
"""

from __future__ import annotations

from abc import abstractmethod

import numpy as np

from ..body.state import State
from .base import Constraint


class Inequality(Constraint):
    """Rows g(x) >= ``floor``; subclasses give g (:meth:`value`) and dg/dx (:meth:`value_jacobian`)."""

    floor: np.ndarray  # (rows,) in g's units

    @abstractmethod
    def value(self, state: State) -> np.ndarray:
        """g(x), (rows,)."""

    @abstractmethod
    def value_jacobian(self, state: State) -> np.ndarray:
        """dg/dx, (rows, n_x)."""

    def gap(self, state: State) -> np.ndarray:
        """g - floor per row (g's units), once per state: the error, the slack and the Jacobian's rows of a trial
        point all read it (not to be written to)."""
        key = (self, "gap")
        found = state.cache.get(key)
        if found is None:
            found = state.cache[key] = self.value(state) - self.floor
        return found

    def error(self, state: State) -> np.ndarray:
        return np.minimum(self.gap(state), 0.0)

    def slack(self, state: State) -> np.ndarray:
        """How far each met row is above its floor (0 on unmet rows), in g's units."""
        return np.maximum(self.gap(state), 0.0)

    def jacobian(self, state: State) -> np.ndarray:
        jac = np.array(self.value_jacobian(state), dtype=float)
        jac[self.gap(state) > 0.0] = 0.0
        return jac

    def jacobian_rows(self, state: State) -> tuple[np.ndarray, np.ndarray]:
        rows = np.flatnonzero(~(self.gap(state) > 0.0))  # NaN rows stay, as in jacobian
        return rows, np.asarray(self.value_jacobian(state), dtype=float)[rows]

    def residuals(self, state: State) -> dict[str, float]:
        """The largest shortfall below the floor (0 when met), in g's units."""
        return {f"{self.name}.shortfall": abs(float(np.min(self.error(state), initial=0.0)))}
