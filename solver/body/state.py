"""One evaluation point of a problem: x = [theta, w], with its kinematics and statics computed once."""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np

from .model import Kinematics

if TYPE_CHECKING:
    from .statics import Statics, StaticsLayout


class computed_once:  # noqa: N801 (a decorator, named like functools.cached_property)
    """functools.cached_property without its lock: the value is kept in the instance's ``__dict__`` under the same
    name (Python 3.11's takes a lock on every first access, ~0.3 us; a solve makes ~50 states)."""

    def __init__(self, function) -> None:
        self.function = function
        self.name = function.__name__
        self.__doc__ = function.__doc__

    def __set_name__(self, owner, name: str) -> None:
        self.name = name

    def __get__(self, instance, owner=None):
        if instance is None:
            return self
        value = instance.__dict__[self.name] = self.function(instance)
        return value


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

    @computed_once
    def kin(self) -> Kinematics:
        return self._layout.model.forward(self.theta)

    @computed_once
    def statics(self) -> Statics:
        return self._layout.evaluate(self.kin, self.w)

    def once(self, owner: object, what: str, compute: Callable[[], Any]) -> Any:
        """``compute()``, kept in the cache under ``(owner, what)``: a value that depends on ``owner`` (a constraint,
        a comfort) and this state alone."""
        key = (owner, what)
        found = self.cache.get(key)
        if found is None:
            found = self.cache[key] = compute()
        return found

    def adopt(self, other: State, owners: set[int] | None = None) -> State:
        """This state, with what ``other`` computed already when it is the same point of the same problem layout:
        its kinematics and statics, and the values its cache keeps by object (a constraint's, a comfort term's, a
        comfort's: each depends on its object and the point alone, so a problem sharing the object shares them; a
        motion's next frame starts where the last one ended, with other targets). ``owners``: the ids of the
        objects whose values to take (those of the problem at hand; a key's object is the key or its first item,
        and values kept under a name are always taken), so that a pose held for many frames does not carry every
        earlier frame's moved targets along."""
        if other._layout is self._layout and other.n_joints == self.n_joints and np.array_equal(other.x, self.x):
            for name in ("kin", "statics"):
                if name in other.__dict__:  # computed (computed_once keeps it there)
                    self.__dict__.setdefault(name, other.__dict__[name])
            taken = other.cache.items()
            if owners is not None:  # one comprehension: a frame's first point takes ~40 values
                taken = [(key, value) for key, value in taken
                         if type(owner := key[0] if type(key) is tuple else key) is str
                         or id(owner) in owners]  # fmt: skip
            mine = self.cache
            if mine:  # what this state has already stays (as setdefault would keep it)
                taken = [(key, value) for key, value in taken if key not in mine]
            mine.update(taken)
        return self
