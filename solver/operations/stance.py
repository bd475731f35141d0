"""Where the feet go: ONE call site for the stance finder (:func:`solver.stance.find_stance`), and the paces
between two stances.

An operation whose hand targets are beyond a comfortable planted reach (:data:`COMFORT_REACH` m horizontally from
the feet's middle) first steps to a stance found for them. The feet are walked up to the targets (their middle
:data:`STANDOFF` m behind them, facing as before: the stance finder moves a foot at most a step per call and stops
at the first stance that meets the targets, which for a far target is a stretched lean at the edge of reach), then
the stance finder takes it from there: the hands' targets (and the held object's weight) as a problem whose feet
may step, solved in balance and clear of the obstacles (and called again from the stance it found while it does
not converge, :data:`CALLS` times at most). A ``step`` with
``to`` goes where the user says (the feet kept at their spacing and facing).

The way there is a step-to gait: paces of at most :data:`PACE` m, one foot at a time (the other the only support,
the weight shifted over it first), each foot lifted :data:`LIFT` m at mid-swing, MTM-1 W-P (15 TMU) a pace.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..body.model import GRAVITY
from ..problem.problem import Problem
from ..problem.specs import ExternalLoad, Target
from ..stance import Step, find_stance, foot_targets

PACE = 0.45  # m: the longest pace (a foot's travel)
LIFT = 0.05  # m: a swinging foot's height at mid-swing
COMFORT_REACH = 0.70  # m: hand targets farther than this from the feet's middle (horizontally) are stepped to
STANDOFF = 0.65  # m: the feet's middle this far behind the hands' targets when walked up (then found)
CALLS = 4  # find_stance calls at most (each moves a foot at most a step)
HAND_LOCK = ("x", "y", "z")  # the stance is found for the hands' positions


def stance_for(feet: dict[str, np.ndarray], to: np.ndarray) -> dict[str, np.ndarray]:
    """The feet's positions (3,) m for a ``step`` to ``to`` (x, y of their middle), kept at their spacing."""
    middle = sum(feet.values()) / len(feet)
    shift = np.array([to[0] - middle[0], to[1] - middle[1], 0.0])
    return {tcp: p + shift for tcp, p in feet.items()}


def beyond_comfort(feet: dict[str, np.ndarray], points: list[np.ndarray]) -> bool:
    """Whether any of ``points`` is farther than :data:`COMFORT_REACH` m from the feet's middle, horizontally."""
    middle = sum(feet.values()) / len(feet)
    return any(float(np.hypot(*(np.asarray(p)[:2] - middle[:2]))) > COMFORT_REACH for p in points)


def walk_up(feet: dict[str, np.ndarray], hands: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """The feet walked up to the hands' targets: their middle :data:`STANDOFF` m behind the targets' middle along
    the facing (-y, as the zero pose and :data:`.timeline.CARRY`), at their spacing; the stance finder starts
    there."""
    middle = sum(feet.values()) / len(feet)
    centre = sum(hands.values()) / len(hands)
    to = np.array([centre[0], centre[1] + STANDOFF])
    if float(np.hypot(*(to - middle[:2]))) < 1e-3:
        return dict(feet)
    return stance_for(feet, to)


class StanceFinder:
    """Stances for hand targets over a scenario's first-frame ``base`` problem (its feet, obstacles, comfort)."""

    def __init__(self, base: Problem) -> None:
        self.base = base

    def __call__(self, feet: dict[str, np.ndarray], hands: dict[str, np.ndarray], mass: float,
                 obstacles: list) -> tuple[dict[str, np.ndarray], str]:  # fmt: skip
        """The feet (tcp -> (3,) m) for ``hands`` (tcp -> (3,) m) holding ``mass`` kg among ``obstacles``, and the
        stance finder's line (its steps, or what is short)."""
        walked = walk_up(feet, hands)
        problem = self._problem(walked, hands, mass, obstacles)
        model = self.base.model
        x = model.zero_pose()  # the zero pose carried to the walked-up stance (the root's x, y)
        x[np.flatnonzero(model.prismatic)[:2]] += (sum(walked.values()) - sum(feet.values()))[:2] / len(feet)
        lines: list[str] = []
        for _ in range(CALLS):
            found = find_stance(problem, x)
            lines.append(found.message)
            problem, x = found.problem, found.result.x
            if found.converged:
                break
        final = foot_targets(problem)
        moved = {t.tcp: np.asarray(t.position, dtype=float) for t in final.values()}
        out = {tcp: np.array([*moved[tcp][:2], feet[tcp][2]]) for tcp in feet}
        if not found.converged:
            return out, lines[-1]
        # the steps from where the feet stood (the walk-up and the finder's last step together)
        turns = {t.tcp: turn_deg(t.rotation) for t in final.values()}
        steps = [net_step(tcp, feet[tcp], out[tcp], turns.get(tcp, 0.0)) for tcp in feet]
        return out, "; ".join(s.text() for s in steps if s.length > 0.01 or abs(s.turn_deg) > 1.0) or lines[-1]

    def _problem(self, feet: dict, hands: dict, mass: float, obstacles: list) -> Problem:
        base = self.base
        targets = [dataclasses.replace(t, position=np.asarray(feet[t.tcp], dtype=float)) for t in base.all_targets
                   if t.support and t.tcp in feet]  # fmt: skip
        targets += [
            Target(tcp, np.asarray(p, dtype=float), None, lock=HAND_LOCK, priority=1) for tcp, p in hands.items()
        ]
        loads = [ExternalLoad(tcp, mass * GRAVITY / len(hands)) for tcp in hands] if mass > 0 else []
        spec = base.spec.replace(targets=targets, loads=loads, obstacles=[*base.spec.obstacles, *obstacles])
        return Problem(base.model, spec)


def turn_deg(rotation: np.ndarray | None) -> float:
    """A foot target's turn about z from the facing (deg, left positive); 0 without a rotation."""
    if rotation is None:
        return 0.0
    heading = np.asarray(rotation, dtype=float)[:, 1]  # the sole's long axis, +y at the zero pose
    return float(np.degrees(np.arctan2(-heading[0], heading[1])))


def net_step(tcp: str, start: np.ndarray, end: np.ndarray, turn: float) -> Step:
    """The step of ``tcp`` from ``start`` to ``end`` (m), its direction from the facing (-y), left positive."""
    d = (end - start)[:2]
    direction = float(np.degrees(np.arctan2(d[0], -d[1]))) if np.linalg.norm(d) > 1e-9 else 0.0
    return Step(tcp, float(np.linalg.norm(d)), direction, turn,
                tuple(map(float, start)), tuple(map(float, end)))


def paces(start: dict[str, np.ndarray], goal: dict[str, np.ndarray]) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """The swings from ``start`` to ``goal`` feet: (foot TCP, from (3,), to (3,)), alternating, the leading foot
    (the one on the side the stance moves to) first, each at most :data:`PACE` m (step-to gait)."""
    travel = max(float(np.linalg.norm(goal[t] - start[t])) for t in goal)
    if travel < 1e-3:
        return []
    count = max(1, math.ceil(travel / PACE))
    direction = sum(goal.values()) / len(goal) - sum(start.values()) / len(start)
    order = sorted(goal, key=lambda t: -float((start[t] - sum(start.values()) / len(start)) @ direction))
    out = []
    for j in range(1, count + 1):  # step-to: each foot in turn to the same share of the way
        for foot in order:
            out.append(
                (
                    foot,
                    start[foot] + (goal[foot] - start[foot]) * (j - 1) / count,
                    start[foot] + (goal[foot] - start[foot]) * j / count,
                )
            )
    return out


def swing_at(start: np.ndarray, goal: np.ndarray, share: float) -> np.ndarray:
    """A swinging foot at ``share`` (0..1, already min-jerk shaped) of its way: lifted at mid-swing."""
    p = start + (goal - start) * share
    return p + np.array([0.0, 0.0, LIFT * math.sin(math.pi * share)])
