"""One evaluation point of a problem: x = [theta, w], with its kinematics and statics computed once."""

from __future__ import annotations

from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np

from .model import Kinematics

if TYPE_CHECKING:
    from .statics import Statics, StaticsLayout


class State:
    """x split into joint values ``theta`` (rad/m) and contact edge weights ``w`` (N), lazily evaluated."""

    def __init__(self, x: np.ndarray, n_joints: int, layout: StaticsLayout) -> None:
        self.x = x
        self.theta = x[:n_joints]
        self.w = x[n_joints:]
        self.n_joints = n_joints
        self.n_x = len(x)
        self._layout = layout
        self.variables: np.ndarray | None = None  # the solver variables beta, when x = phi(beta) is nonlinear
        self.reduction_jacobian: np.ndarray | None = None  # dphi/dbeta there, once computed
        self.cache: dict = {}  # per-object intermediates (constraints, comfort) shared by values and derivatives

    @cached_property
    def kin(self) -> Kinematics:
        return self._layout.model.forward(self.theta)

    @cached_property
    def statics(self) -> Statics:
        return self._layout.evaluate(self.kin, self.w)
