"""The step cost: a comfort term that lets a foot step only as far as the step helps.

cost = sum over the feet of (d / L)^2 + (1 - cos turn) / (1 - cos TURN_REF), d the foot centre's horizontal distance (m)
from where it stood, L the comfortable step (COMFORT_FRACTION x stature) and turn the foot's rotation about z. Why: a
person reaching for something takes a step when leaning or stretching would be worse, and then no longer a step than the
reach needs; the cost is minimised in the constraints' null space with the other comfort terms, so a target met from the
planted stance keeps the feet where they stand unless a step makes the whole pose (joints, loads, step) more
comfortable, and a target out of planted reach gets the shortest step that, with the rest of the pose, meets it.
Squared, like the other terms, so its gradient is zero at the start (a planted pose is not pushed off) and a step of L
costs 1, about one joint at the edge of its comfortable range; a turn of TURN_REF costs 1 too (about (turn /
TURN_REF)^2): without it the feet swung to the 45 deg bound whenever a turn eased a hip a little.
"""

from __future__ import annotations

import numpy as np

from ..body.model import Model
from ..body.state import State
from ..comfort.base import ComfortTerm

COMFORT_FRACTION = 0.3  # of stature: a comfortable step, about 0.5 m for a 1.75 m adult (a relaxed walking step)
WEIGHT = 3.0  # next to the standard terms' 1: at 1 a reach at the planted edge took ~0.5 m steps, at 3 ~0.3 m
TURN_REF = np.radians(30.0)  # rad: a turn that costs as much as a comfortable step
FLAT = np.array([1.0, 1.0, 0.0])


class StepCost(ComfortTerm):
    """(d / L)^2 summed over ``feet`` ({tcp: start position (3,), world m}); curvature as exact Gauss-Newton rows."""

    name = "step"
    relative = False  # zero at the start: it must not set the scale of the comfort tolerance
    description = "feet stepping from where they stood"

    def __init__(self, model: Model, starts: dict[str, tuple[np.ndarray, np.ndarray]], comfortable: float) -> None:
        """``starts``: {foot: (rotation 3x3, position (3,)), world} where each foot stood; ``comfortable`` L (m)."""
        self.tcps = [model.tcp(f) for f in starts]
        self.starts = [np.asarray(p, dtype=float) for _, p in starts.values()]
        self.headings = [np.asarray(r, dtype=float)[:, 1] for r, _ in starts.values()]  # the sole's long axis
        self.length = float(comfortable)
        self.turn_scale = 1.0 / (1.0 - np.cos(TURN_REF))

    def _parts(self, state: State):
        """Per foot: (horizontal offset (3,) m, d offset / d theta (3, n), heading (3,), d heading.start / d theta
        (n,), d turn about z / d theta (n,))."""
        kin = state.kin
        for tcp, start, h0 in zip(self.tcps, self.starts, self.headings, strict=True):
            rot, position = kin.tcp_frame(tcp)
            jac = kin.frame_jacobian(tcp.link, position)
            h = rot[:, 1]
            yield (position - start) * FLAT, jac[:3] * FLAT[:, None], h, np.cross(h, h0) @ jac[3:], jac[5]

    def cost(self, state: State) -> float:
        total = 0.0
        for d, _, _, _, _ in self._parts(state):
            total += d @ d / self.length**2
        return float(total + self.turn_scale * sum(1.0 - h @ h0 for (_, _, h, _, _), h0 in
                                                  zip(self._parts(state), self.headings, strict=True)))

    def derivatives(self, state: State, weight: float) -> tuple[np.ndarray, np.ndarray]:
        grad = np.zeros(state.n_x)
        for d, jac, _, dcos, _ in self._parts(state):
            grad[: state.n_joints] += weight * (2.0 * (d @ jac) / self.length**2 - self.turn_scale * dcos)
        return grad, np.zeros(state.n_x)

    def curvature_rows(self, state: State, weight: float) -> np.ndarray | None:
        rows = np.zeros((4 * len(self.tcps), state.n_x))
        for k, ((_, jac, h, _, spin), h0) in enumerate(zip(self._parts(state), self.headings, strict=True)):
            rows[4 * k : 4 * k + 3, : state.n_joints] = np.sqrt(2.0 * weight) * jac / self.length
            bend = max(float(h @ h0), 0.0)  # d2(1 - cos turn)/d turn^2 = cos turn, kept >= 0
            rows[4 * k + 3, : state.n_joints] = np.sqrt(weight * self.turn_scale * bend) * spin
        return rows
