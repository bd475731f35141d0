"""Constraints, one per module, all with the interface of :class:`Constraint`."""

from .balance import BalanceConstraint
from .base import Constraint
from .frame import AXES, FrameConstraint, FrameGroup, lock_operator
from .inequality import Inequality

__all__ = ["AXES", "BalanceConstraint", "Constraint", "FrameConstraint", "FrameGroup", "Inequality", "lock_operator"]
