"""What a problem's constraints report at a state: the unmet ones' names, the residuals in their own units and the
clearance rows within their margin; each constraint's once per state (kept in the state's cache by the constraint,
so a motion's frame that keeps its pose shares them with the frame before: :meth:`State.adopt`)."""

from __future__ import annotations

from collections.abc import Sequence
from functools import partial

from ..body.state import State
from ..constraints import Constraint
from ..constraints.clearance import ClearanceRows, Closeness


def closest(constraints: Sequence[Constraint], state: State) -> list[Closeness]:
    """The rows of every :class:`ClearanceRows` within their margin, nearest first."""
    rows = [c for c in constraints if isinstance(c, ClearanceRows)]
    near = [pair for c in rows for pair in state.once(c, "closest", partial(c.closest, state))]
    return sorted(near, key=lambda pair: pair.distance)


def residuals(constraints: Sequence[Constraint], state: State) -> dict[str, float]:
    """Every constraint's readable residuals (m, rad, N, N*m), by ``<name>.<quantity>``."""
    out: dict[str, float] = {}
    for c in constraints:
        out.update(state.once(c, "residuals", partial(c.residuals, state)))
    return out


def unmet(constraints: Sequence[Constraint], state: State) -> list[str]:
    """The names of what is not met (a constraint's name, or its members')."""
    return [name for c in constraints for name in state.once(c, "unmet", partial(c.unmet, state))]
