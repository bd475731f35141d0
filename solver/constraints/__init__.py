"""Constraints, one per module, all with the interface of :class:`Constraint`."""

from .balance import BalanceConstraint
from .base import Constraint
from .frame import AXES, FrameConstraint, lock_operator

__all__ = ["AXES", "BalanceConstraint", "Constraint", "FrameConstraint", "lock_operator"]
