"""What a problem's constraints report at a state: the unmet ones' names, the residuals in their own units and the
clearance rows within their margin; each constraint's three once per state, together (kept in the state's cache by
the constraint, so a motion's frame that keeps its pose shares them with the frame before: :meth:`State.adopt`)."""

from __future__ import annotations

from collections.abc import Sequence
from operator import itemgetter
from typing import NamedTuple

from ..body.state import State
from ..constraints import Constraint
from ..constraints.clearance import ClearanceRows, Closeness

ANSWERS = "report"  # a constraint's (unmet, residuals, closest) are kept under (the constraint, ANSWERS)
_by_distance = itemgetter(2)  # Closeness.distance, as a key without a lambda's call
_is_clearance: dict[type, bool] = {}  # per constraint type: a ClearanceRows? (isinstance of an ABC is a Python call)


class Report(NamedTuple):
    """A state's report: the names of what is not met, the residuals by ``<name>.<quantity>`` (m, rad, N, N*m) and
    the clearance rows within their margin, nearest first."""

    unmet: list[str]
    residuals: dict[str, float]
    closest: list[Closeness]


def report(constraints: Sequence[Constraint], state: State) -> Report:
    """:func:`unmet`, :func:`residuals` and :func:`closest` in one pass over ``constraints`` (what a result reports)."""
    unmet: list[str] = []
    residuals: dict[str, float] = {}
    near: list[Closeness] = []
    cache = state.cache
    for c in constraints:
        key = (c, ANSWERS)
        answers = cache.get(key)
        if answers is None:
            answers = cache[key] = _answers(c, state)
        unmet += answers[0]
        residuals.update(answers[1])
        near += answers[2]
    near.sort(key=_by_distance)  # stable: rows at one distance stay in constraint order
    return Report(unmet, residuals, near)


def _answers(c: Constraint, state: State) -> tuple[list[str], dict[str, float], list[Closeness]]:
    """(unmet names, residuals, rows within the margin) of one constraint at ``state``, asked in that order."""
    clearance = _is_clearance.get(type(c))
    if clearance is None:
        clearance = _is_clearance[type(c)] = issubclass(type(c), ClearanceRows)
    return c.unmet(state), c.residuals(state), c.closest(state) if clearance else []


def closest(constraints: Sequence[Constraint], state: State) -> list[Closeness]:
    """The rows of every :class:`ClearanceRows` within their margin, nearest first."""
    return report(constraints, state).closest


def residuals(constraints: Sequence[Constraint], state: State) -> dict[str, float]:
    """Every constraint's readable residuals (m, rad, N, N*m), by ``<name>.<quantity>``."""
    return report(constraints, state).residuals


def unmet(constraints: Sequence[Constraint], state: State) -> list[str]:
    """The names of what is not met (a constraint's name, or its members')."""
    return report(constraints, state).unmet
