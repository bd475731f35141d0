"""Static balance (thesis eqs. 3.5-3.9): total force and total moment on the manikin are zero.

Gravity on every link, the contact forces (unknowns, see contacts.py) and user loads at TCPs. The moment is
taken about the world origin; once the forces balance, the point does not matter.
"""

from __future__ import annotations

import numpy as np

from ..body.spatial import length
from ..body.state import State
from .base import MET_FACTOR, Constraint

FORCE_TOLERANCE = 1.0  # N
MOMENT_TOLERANCE = 0.1  # N*m
# per row, Constraint.met_rows's bound: a row is met when |error| <= it (N, N*m)
_MET = [tolerance * MET_FACTOR for tolerance in [FORCE_TOLERANCE] * 3 + [MOMENT_TOLERANCE] * 3]


class BalanceConstraint(Constraint):
    """Six rows: sum of forces (N) and sum of moments (N*m) on the whole body."""

    name = "balance"

    def __init__(self, n_x: int, weight: float = 1.0) -> None:
        self.n_x = n_x
        self.weight = weight

    @property
    def rows(self) -> int:
        return 6

    def tolerance(self) -> np.ndarray:
        return np.array([FORCE_TOLERANCE] * 3 + [MOMENT_TOLERANCE] * 3)

    def error(self, state: State) -> np.ndarray:
        return state.statics.balance_error()

    def jacobian(self, state: State) -> np.ndarray:
        return state.statics.balance_rows()

    def residuals(self, state: State) -> dict[str, float]:
        err = self.error(state)
        return {"balance.force": length(err[:3]), "balance.moment": length(err[3:])}  # np.linalg.norm's numbers

    def unmet(self, state: State) -> list[str]:
        """["balance"] when a row is outside its tolerance (NaN too); six rows compared as Python floats."""
        met = all(abs(e) <= bound for e, bound in zip(self.error(state).tolist(), _MET, strict=True))
        return [] if met else [self.name]
