"""Trunk-tilt discomfort: (1 - cos phi) / (1 - cos 20 deg), phi the thorax's tilt from vertical (about (phi/20 deg)^2).

Ergonomic posture scores rate the trunk by its inclination from vertical, whatever bends it (pelvis, hips or spine):
RULA (McAtamney & Corlett 1993) and REBA (Hignett & McAtamney 2000) from 20 deg on, OWAS from 20 deg of bending,
and the load on the low back grows with the trunk's lean. The joint-range term alone sees a stoop as hip flexion
about as costly as the knee, hip and ankle flexion of a squat, so it stooped every low lift; people keep the trunk
more upright and bend the knees (docs/explanation/mocap-validation.md: the weight is fitted there on the training
subjects). The tilted axis is the thorax's up axis (the link the top thoracic joint moves); a model without that
joint (the snake) has no trunk and costs 0. Its weight is 5 by default; a positive weight is the switch of the whole
behaviour model (:func:`.standard.behaviour_on`), 0 gives the standard model.
"""

from __future__ import annotations

import numpy as np

from .. import kernels
from ..body.model import Model
from ..body.state import State
from ..kernels.comfort import trunk_derivatives
from .base import ComfortTerm

THORAX_JOINT = "t1_rz"  # the last joint of the top thoracic vertebra: its link is the thorax
REFERENCE_TILT = np.radians(20.0)  # rad, RULA's and REBA's first trunk-flexion band: cost 1 there


class TrunkTilt(ComfortTerm):
    """k (1 - z . up), z the thorax's up axis; the curvature model is the exact diagonal of the Hessian (>= 0)."""

    name = "trunk"
    description = "trunk lean; above 0 the behaviour model (knees bend, elbows rest bent)"

    def __init__(self, model: Model) -> None:
        self.link = model.joint_names.index(THORAX_JOINT) if THORAX_JOINT in model.joint_names else -1
        chain = model.descendant[:, self.link] & ~model.prismatic if self.link >= 0 else np.zeros(model.n, bool)
        self.chain = np.flatnonzero(chain)  # the revolute joints that turn the thorax (root and spine)
        self.scale = 1.0 / (1.0 - np.cos(REFERENCE_TILT))

    def _up(self, state: State) -> np.ndarray:
        return state.kin.rotation[self.link][:, 2]

    def cost(self, state: State) -> float:
        if self.link < 0:
            return 0.0
        return float(self.scale * (1.0 - self._up(state)[2]))

    def derivatives(self, state: State, weight: float) -> tuple[np.ndarray, np.ndarray]:
        if kernels.active() and self.link >= 0:
            kin = state.kin
            along = kin.axis[self.chain] @ self._up(state)  # BLAS's products, as below
            factor = weight * self.scale
            return trunk_derivatives(kin.rotation, kin.axis, self.link, self.chain, along, factor, state.n_x)
        grad, curv = np.zeros(state.n_x), np.zeros(state.n_x)
        if self.link < 0:
            return grad, curv
        z = self._up(state)
        a = state.kin.axis[self.chain]  # world axes; turning joint j by d turns z by d a_j x z
        grad[self.chain] = -weight * self.scale * np.cross(a, z)[:, 2]
        second = z[2] - a[:, 2] * (a @ z)  # d2(1 - z_z)/d theta_j^2 = z_z - a_z (a . z)
        curv[self.chain] = weight * self.scale * np.maximum(second, 0.0)
        return grad, curv
