"""The one interface every comfort term implements: a dimensionless cost, its gradient and a curvature model."""

from __future__ import annotations

from abc import ABC, abstractmethod

import numpy as np

from ..body.state import State


class ComfortTerm(ABC):
    """A cost c(x) >= 0 (0 = comfortable); comfort h = -sum of weight x cost over the terms."""

    name: str  # the key of this term in reports (``Result.comfort_parts``)
    relative: bool = True  # its size sets the scale of the solver's relative comfort tolerance
    description: str = ""  # what its weight weighs, in a few words for a user (a standard term's weight's tooltip)

    @abstractmethod
    def cost(self, state: State) -> float:
        """c(x), unweighted."""

    @abstractmethod
    def derivatives(self, state: State, weight: float) -> tuple[np.ndarray, np.ndarray]:
        """(d(weight c)/dx (n_x,), a positive diagonal curvature model of weight c (n_x,))."""

    def curvature_rows(self, state: State, weight: float) -> np.ndarray | None:
        """Rows R (k, n_x) whose R^T R is curvature of weight c beyond the diagonal model (None: there is none)."""
        return None

    def with_targets(self, targets: list) -> ComfortTerm:
        """This term for a problem of ``targets`` (a term that reads them returns another; most return self)."""
        return self
