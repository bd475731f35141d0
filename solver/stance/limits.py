"""Where stepping feet may stand: the bounds that keep a reach with ``--feet step`` a stance a person can take.

Each foot stays a support flat on the floor (its target locks z, roll and pitch; it slides in x, y and turns about
z) and these one-sided rows (priority 1, with balance) bound where it goes, each g >= 0:

* each foot's centre within one step (``step`` m) of where it stood;
* the feet's centres at most one step apart (no split wider than a step);
* neither foot crossed over or onto the other: the left foot's centre at least ``width`` m to the left of the right
  one, measured across the right sole (its x axis), and the same seen from the left sole;
* each foot turned at most ``yaw`` rad about z from its start.

The numbers are documented assumptions (docs/tutorials/envelope.md and the user guide, "Stepping"): ``step`` =
STEP_FRACTION x stature, a comfortable walking step (adults' step at free walking speed is roughly 0.6-0.8 m), not a
maximal lunge; ``width`` the sole's own width (the model's sole, 0.055 x stature by Drillis & Contini via Winter
2009), so the soles neither cross nor overlap side by side; ``yaw`` YAW_MAX_DEG, a pivot on the spot. Units: m, rad.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..body.humans.anthropometry import WINTER_H
from ..body.model import Model
from ..body.spatial import cross
from ..body.state import State
from ..constraints.inequality import Inequality

STEP_FRACTION = 0.4  # of stature: how far a foot may move from its start, and the feet's largest distance apart
YAW_MAX_DEG = 45.0  # how far a foot may turn about z from its start
TOLERANCE = 1e-3  # m (and the cosine rows' units): a row this far past its bound still counts as met
WATCH = 0.01  # a met row this close to its bound gives the step its Jacobian (held there, not pushed past)
FEET = ("foot_l", "foot_r")
ROWS = ("foot_l step", "foot_r step", "feet apart", "feet crossed (across foot_r)", "feet crossed (across foot_l)",
        "foot_l turn", "foot_r turn")  # fmt: skip


@dataclass(frozen=True)
class StanceLimits:
    """How far stepping feet may go: ``step`` m (each foot from its start; the feet apart), ``width`` m (the least
    sideways distance of each foot's centre from the other's, across the other sole), ``yaw`` rad (each foot's turn)."""

    step: float
    width: float
    yaw: float


def stature_of(model: Model) -> float:
    """The body's stature (m): its own, else its shoulder height over Winter's shoulder fraction (0.818)."""
    stature = model.info.get("stature")
    if isinstance(stature, int | float) and stature > 0:
        return float(stature)
    zero = model.forward(model.zero_pose())
    return float(zero.tcp_frame(model.tcp("shoulder_r"))[1][2]) / WINTER_H["shoulder_height"]


def stance_limits(model: Model) -> StanceLimits:
    """The limits of ``model``'s stepping feet (see the module docstring)."""
    stature = stature_of(model)
    sole = model.tcp("foot_r").sole
    width = float(np.ptp(np.asarray(sole)[:, 0])) if sole is not None else WINTER_H["foot_width"] * stature
    return StanceLimits(STEP_FRACTION * stature, width, np.radians(YAW_MAX_DEG))


class StanceBounds(Inequality):
    """The rows of the module docstring for the feet's ``starts`` ({foot: (rotation 3x3, position (3,))}, world)."""

    name = "stance"

    def __init__(self, model: Model, limits: StanceLimits, starts: dict[str, tuple[np.ndarray, np.ndarray]]) -> None:
        self.model, self.limits = model, limits
        self.tcps = [model.tcp(f) for f in FEET]
        self.start_position = np.array([starts[f][1] for f in FEET], dtype=float)
        self.start_heading = np.array([starts[f][0][:, 1] for f in FEET], dtype=float)  # the sole's long axis
        self.floor = np.zeros(len(ROWS))

    @property
    def rows(self) -> int:
        return len(ROWS)

    def tolerance(self) -> np.ndarray:
        return np.full(self.rows, TOLERANCE)

    def _evaluate(self, state: State) -> tuple[np.ndarray, np.ndarray]:
        """(g (rows,), dg/dtheta (rows, n)), once per state."""
        cached = state.cache.get(self)
        if cached is None:
            cached = state.cache[self] = self._rows(state)
        return cached

    def _rows(self, state: State) -> tuple[np.ndarray, np.ndarray]:
        kin, lim = state.kin, self.limits
        frames = [kin.tcp_frame(t) for t in self.tcps]
        jac = [kin.frame_jacobian(t.link, p) for t, (_, p) in zip(self.tcps, frames, strict=True)]
        lin = [j[:3] for j in jac]
        ang = [j[3:] for j in jac]
        g, rows = [], []
        for k in range(2):  # each foot within a step of its start
            d = (frames[k][1] - self.start_position[k]) * (1.0, 1.0, 0.0)
            size = max(float(np.linalg.norm(d)), 1e-12)
            g.append(lim.step - size)
            rows.append(-(d / size) @ lin[k])
        apart = frames[0][1] - frames[1][1]  # left minus right
        flat = apart * (1.0, 1.0, 0.0)
        size = max(float(np.linalg.norm(flat)), 1e-12)
        g.append(lim.step - size)
        rows.append(-(flat / size) @ (lin[0] - lin[1]))
        for k in (1, 0):  # the left foot to the left of the right one, across the right sole, then the left
            side = frames[k][0][:, 0]  # the sole's x axis: the foot's left (level while the soles are flat)
            g.append(float(apart @ side) - lim.width)
            rows.append(side @ (lin[0] - lin[1]) + cross(side, apart) @ ang[k])
        for k in range(2):  # each foot turned at most yaw: cos(turn) >= cos(yaw)
            heading = frames[k][0][:, 1]
            g.append(float(heading @ self.start_heading[k]) - np.cos(lim.yaw))
            rows.append(cross(heading, self.start_heading[k]) @ ang[k])
        return np.array(g), np.array(rows)

    def value(self, state: State) -> np.ndarray:
        return self._evaluate(state)[0]

    def value_jacobian(self, state: State) -> np.ndarray:
        out = np.zeros((self.rows, state.n_x))
        out[:, : state.n_joints] = self._evaluate(state)[1]
        return out

    def jacobian(self, state: State) -> np.ndarray:
        """d error / dx on the rows past their bound or within WATCH of it (as the clearances: the step holds a met
        row at its bound instead of pushing it past); zero on the others."""
        rows, jac = self.jacobian_rows(state)
        out = np.zeros((self.rows, state.n_x))
        out[rows] = jac
        return out

    def jacobian_rows(self, state: State) -> tuple[np.ndarray, np.ndarray]:
        rows = np.flatnonzero(~(self.value(state) - self.floor >= WATCH))
        return rows, self.value_jacobian(state)[rows]

    def unmet(self, state: State) -> list[str]:
        """The bounds a stance breaks, e.g. "feet apart"."""
        return [ROWS[i] for i in np.flatnonzero(~self.met_rows(state))]
