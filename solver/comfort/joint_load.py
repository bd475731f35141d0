"""Joint-load discomfort (thesis eqs. 3.10-3.11): sum_i c_i (tau_i / s_i)^2, the strain of every revolute joint.

tau_i is the moment about joint i's axis that gravity, loads and contact forces put on it, s_i the joint's
strength in the direction its muscles must act (they must produce -tau), c_i the model's per-joint comfort weight.
"""

from __future__ import annotations

import numpy as np

from .. import kernels
from ..body.model import Model
from ..body.state import State
from ..kernels.comfort import load_factors, load_strains
from .base import ComfortTerm


class JointLoad(ComfortTerm):
    """Squared strain of the revolute joints; the curvature model is the Gauss-Newton diagonal."""

    name = "load"
    description = "joint moments / strength"

    def __init__(self, model: Model) -> None:
        strength = np.where(np.isfinite(model.strength) & (model.strength > 0), model.strength, np.inf)
        inverse = 1.0 / strength  # (n, 2): for negative and positive muscle moments
        self._inv_negative = inverse[:, 0].copy()
        self._inv_positive = inverse[:, 1].copy()
        self.joint_weight = np.ascontiguousarray(np.where(model.prismatic, 0.0, model.range_weight), dtype=float)

    def _strain_scale(self, tau: np.ndarray) -> np.ndarray:
        # The muscles must produce -tau: positive capacity when tau < 0.
        return np.where(tau < 0.0, self._inv_positive, self._inv_negative)

    def cost(self, state: State) -> float:
        tau = state.statics.axis_loads()
        if kernels.active():  # the squares in one loop, their weighted sum by BLAS as below
            squares = np.empty(len(tau))
            load_strains(tau, self._inv_negative, self._inv_positive, squares)
            return float(self.joint_weight @ squares)
        strain = tau * self._strain_scale(tau)
        return float(self.joint_weight @ (strain * strain))

    def derivatives(self, state: State, weight: float) -> tuple[np.ndarray, np.ndarray]:
        tau = state.statics.axis_loads()
        if kernels.active():
            coef, rows = np.empty(len(tau)), np.empty(len(tau))
            load_factors(tau, self._inv_negative, self._inv_positive, self.joint_weight, float(weight), coef, rows)
        else:
            scale = self._strain_scale(tau)
            coef = 2.0 * self.joint_weight * tau * scale * scale
            rows = 2.0 * weight * self.joint_weight * scale * scale
        linear, squared = state.statics.axis_load_contractions(coef, rows)
        return weight * linear, squared
