"""What a solve returns: the pose, contact forces, residuals in their own units, and a readable summary."""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import partial
from typing import TYPE_CHECKING

import numpy as np

from ..constraints.clearance import ClearanceRows
from ..problem.priorities import hard_unmet, shortfalls
from .trial import COST, PARTS

if TYPE_CHECKING:
    from ..body.state import State
    from ..constraints.clearance import Closeness
    from ..problem.problem import Problem
    from .stopping import StopReason

BODY_COM = ("body", "center of mass")  # the whole body's com (m), kept under a name: a state's, whatever the problem


@dataclass
class Result:
    """Outcome of :func:`solver.solve`. ``x`` = [joint values, contact edge weights]; never NaN."""

    problem: Problem
    x: np.ndarray
    converged: bool
    iterations: int
    time_s: float
    residuals: dict[str, float]
    unmet: list[str]
    comfort: float
    comfort_parts: dict[str, float]
    contacts: list[dict]
    com: np.ndarray
    notes: list[str] = field(default_factory=list)
    stop: StopReason | None = None  # why the iteration ended (None for a pose that was not solved)
    broken: list[str] = field(default_factory=list)  # unmet constraints of priority 1 (supports, loops, balance)
    # unmet reach targets: how far each is off, {"position_m": .., "rotation_deg": ..}
    shortfall: dict[str, dict[str, float]] = field(default_factory=dict)
    # clearance rows within their margin at x, nearest first (kept: recomputing them costs a distance query)
    closest: list[Closeness] = field(default_factory=list)
    # (problem, x, the State of x) once asked for (see ``state``); a field, so Result(**vars(result)) copies it
    _state: tuple | None = field(default=None, repr=False, compare=False)

    @classmethod
    def from_state(cls, problem: Problem, state: State, iterations: int, time_s: float) -> Result:
        unmet, residuals, closest = problem.report(state)
        parts, comfort = _comfort(problem, state)
        result = cls(
            problem=problem,
            x=state.x.copy(),
            converged=not unmet,
            iterations=iterations,
            time_s=time_s,
            residuals=residuals,
            unmet=unmet,
            comfort=comfort,
            comfort_parts=parts,
            contacts=[dict(c) for c in state.once(problem.contacts, "wrenches", partial(_wrenches, problem, state))],
            com=state.once(*BODY_COM, state.kin.body_com),  # a held pose's frames share it (State.adopt)
            broken=hard_unmet(problem, unmet),
            shortfall=shortfalls(problem, unmet, residuals),
            closest=closest,
        )
        result._state = (problem, result.x, state)  # the solve's last evaluation: what it computed is kept
        return result

    @property
    def theta(self) -> np.ndarray:
        """Joint values, rad (m for the prismatic root joints)."""
        return self.x[: self.problem.model.n]

    @property
    def state(self) -> State:
        """The evaluation point of ``x``, made once per Result (and per ``problem`` and ``x`` it is given): a writer
        and a report of the same frame share its kinematics and statics, and a solved Result starts with those of
        its solve's last evaluation."""
        kept = self._state
        if kept is None or kept[0] is not self.problem or kept[1] is not self.x:
            kept = self._state = (self.problem, self.x, self.problem.state_of_x(self.x))
        return kept[2]

    def joint_values(self) -> dict[str, float]:
        return dict(zip(self.problem.model.joint_names, map(float, self.theta), strict=True))

    def verdict(self) -> str:
        """One line: converged, or what is short and by how much, or what could not be held."""
        if self.converged:
            return "converged"
        short = "; ".join(f"{name} short by " + shortfall_text(parts) for name, parts in self.shortfall.items())
        if self.broken:
            return "NOT held (priority 1): " + ", ".join(self.broken) + (f"; {short}" if short else "")
        return f"out of reach: {short} (supports, loops, balance and clearances held)" if short else "not converged"

    def summary(self) -> str:
        """A few lines a person can read: status, each constraint's residual, contacts, comfort."""
        status = "converged" if self.converged else "NOT converged"
        lines = [f"{self.problem.model.name}: {status} in {self.iterations} iterations, {self.time_s * 1e3:.1f} ms"]
        if self.stop is not None:
            lines.append(f"  stopped: {self.stop.value} ({self.stop.describe()})")
        if self.unmet:
            lines.append("  unmet: " + ", ".join(self.unmet))
        if self.broken:
            lines.append("  NOT held (priority 1): " + ", ".join(self.broken))
        elif self.unmet:
            lines.append("  held: supports, loops, balance and clearances (priority 1)")
        for name, parts in self.shortfall.items():
            lines.append(f"  short: {name} by " + shortfall_text(parts))
        lines.extend(f"  note: {note}" for note in self.notes)
        distances = {f"{c.name}.shortfall" for c in self.problem.constraints if isinstance(c, ClearanceRows)}
        for name, value in self.residuals.items():
            unit = "mm" if name in distances else _unit(name)  # a clearance's shortfall is a distance (m)
            shown = np.rad2deg(value) if unit == "deg" else value * (1e3 if unit == "mm" else 1.0)
            lines.append(f"  {name:<32s} {shown:10.3f} {unit}")
        for c in self.contacts:
            f = c["force"]
            lines.append(
                f"  contact {c['tcp']:<24s} force [{f[0]:8.1f} {f[1]:8.1f} {f[2]:8.1f}] N"
                f"  COP [{c['point'][0]:.3f} {c['point'][1]:.3f} {c['point'][2]:.3f}] m"
            )
        parts = ", ".join(f"{k} {v:.3f}" for k, v in self.comfort_parts.items())
        lines.append(f"  comfort {self.comfort:.4f} ({parts})")
        lines.append(f"  center of mass [{self.com[0]:.3f} {self.com[1]:.3f} {self.com[2]:.3f}] m")
        return "\n".join(lines)


def _comfort(problem: Problem, state: State) -> tuple[dict[str, float], float]:
    """(the comfort's parts, h) at ``state``: the last trial's when it was evaluated with comfort (kept with its cost
    f = -h, and -(-h) is h to the bit), else computed."""
    comfort = problem.comfort
    kept = state.cache.get((comfort, PARTS))
    if kept is None:
        parts = comfort.parts(state)
        return parts, comfort.total(parts)
    cost = state.cache.get((comfort, COST))
    return dict(kept), -cost[0] if cost is not None else comfort.total(kept)


def _wrenches(problem: Problem, state: State) -> list[dict]:
    """The contacts' wrenches at ``state``, from its statics' corner points and forces when the solve computed them
    (the balance's: the same numbers, as the statics' kernel computes them in einsum's order)."""
    statics = state.__dict__.get("statics")  # computed_once keeps it there
    if statics is None or statics.layout.contacts is not problem.contacts:
        return problem.contacts.wrenches(state.kin, state.w)
    return problem.contacts.wrenches(state.kin, state.w, statics.corner_points, statics.corner_forces)


def shortfall_text(parts: dict[str, float]) -> str:
    """ "12.3 mm, 4.56 deg" for a target's shortfall parts (m and deg)."""
    shown = []
    for part, value in parts.items():
        units = {"position_m": f"{value * 1e3:.1f} mm", "rotation_deg": f"{value:.2f} deg"}
        shown.append(units.get(part, f"{value:.4g} (combined)"))
    return ", ".join(shown)


def _unit(name: str) -> str:
    if name.endswith(".position"):
        return "mm"
    if name.endswith(".rotation"):
        return "deg"
    if name.endswith(".force"):
        return "N"
    if name.endswith(".moment"):
        return "N*m"
    return ""
