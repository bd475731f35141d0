"""Contact-spread discomfort: sum_k (w_k / body weight)^2, a small preference for sharing load among contacts."""

from __future__ import annotations

import numpy as np

from .. import kernels
from ..body.model import GRAVITY, Model
from ..body.state import State
from ..kernels.comfort import contact_cost, contact_derivatives
from .base import ComfortTerm


class ContactSpread(ComfortTerm):
    """Squared contact edge weights (forces / body weight); the curvature model is exact."""

    name = "contact"
    description = "even contact forces"

    def __init__(self, model: Model) -> None:
        self.n = model.n
        self.body_weight = model.total_mass * float(np.linalg.norm(GRAVITY))  # N

    def cost(self, state: State) -> float:
        if kernels.active() and len(state.w) <= 128:  # beyond, np.sum splits the sum in halves: NumPy's below
            return float(contact_cost(state.w, self.body_weight))
        return float(np.sum((state.w / self.body_weight) ** 2)) if len(state.w) else 0.0

    def derivatives(self, state: State, weight: float) -> tuple[np.ndarray, np.ndarray]:
        if kernels.active():
            return contact_derivatives(state.w, self.n, self.body_weight, float(weight))
        grad, curv = np.zeros(state.n_x), np.zeros(state.n_x)
        if len(state.w):
            grad[self.n :] = weight * 2.0 * state.w / self.body_weight**2
            curv[self.n :] = weight * 2.0 / self.body_weight**2
        return grad, curv
