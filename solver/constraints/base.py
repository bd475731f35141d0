"""The one interface every constraint implements (thesis §5.3): rows, error, Jacobian, tolerance."""

from __future__ import annotations

from abc import ABC, abstractmethod

import numpy as np

from ..body.state import State

MET_FACTOR = 1 + 1e-9  # a row within its tolerance but for the last bits of rounding is met


class Constraint(ABC):
    """g(x) = 0 rows. ``tolerance`` is per row in the row's own units; |error| <= tolerance is met."""

    name: str
    weight: float = 1.0

    @property
    @abstractmethod
    def rows(self) -> int: ...

    @abstractmethod
    def tolerance(self) -> np.ndarray: ...

    @abstractmethod
    def error(self, state: State) -> np.ndarray: ...

    @abstractmethod
    def jacobian(self, state: State) -> np.ndarray:
        """(rows, n_x): d error / d x, x = [theta, w]."""

    def jacobian_rows(self, state: State) -> tuple[np.ndarray, np.ndarray]:
        """(indices of the rows that may be nonzero, their Jacobian rows (k, n_x)); the other rows are zero."""
        return np.arange(self.rows), self.jacobian(state)

    @abstractmethod
    def residuals(self, state: State) -> dict[str, float]:
        """Readable residuals in their own units (m, rad, N, N*m), keyed ``<name>.<quantity>``."""

    def row_weight(self) -> np.ndarray:
        """Per row: its weight in the stacked, scaled error."""
        return np.full(self.rows, self.weight)

    def met_rows(self, state: State) -> np.ndarray:
        """Per row: |error| within tolerance (NaN counts as unmet)."""
        return np.abs(self.error(state)) <= self.tolerance() * MET_FACTOR

    def unmet(self, state: State) -> list[str]:
        """Names of what is not met at ``state`` (this constraint's name, or its members')."""
        return [] if self.met_rows(state).all() else [self.name]
