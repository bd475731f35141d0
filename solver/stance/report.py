"""What the feet did: each step's foot, length (m), direction and turn (deg), and the notes a solve's result gets
(the steps taken; or, with planted feet and a target out of reach, that the feet stayed planted).

Direction is measured from the manikin's facing at its start stance (the feet's mean forward axis: the soles' -y,
level), counterclockwise seen from above: 0 forward, 90 to its left, -90 to its right, 180 back. Turn is the foot's
rotation about z from its start, counterclockwise (to the left) positive.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import TYPE_CHECKING

import numpy as np

from .limits import FEET
from .step_problem import bounds_of, foot_targets

if TYPE_CHECKING:
    from ..body.state import State
    from ..iteration.result import Result
    from ..problem.problem import Problem

MOVED = 0.005  # m: a foot this close to where it stood (and turned less than TURNED) took no step
TURNED = np.radians(1.0)
PLANTED_NOTE = ("the feet stayed planted (the default: can the worker do this from here?); --feet step (scenario "
                '[stance] feet = "step") lets the manikin step toward the target')  # fmt: skip


@dataclass(frozen=True)
class Step:
    """One foot's step: ``length`` m (horizontal), ``direction_deg`` (0 forward, 90 left of the facing),
    ``turn_deg`` (about z, left positive), ``start`` and ``end`` (foot centre (x, y, z), world m)."""

    foot: str
    length: float
    direction_deg: float
    turn_deg: float
    start: tuple[float, float, float]
    end: tuple[float, float, float]

    def as_dict(self) -> dict:
        return asdict(self)

    def text(self) -> str:
        """ "foot_r stepped 0.42 m at 12 deg (left of forward), turned -5 deg"."""
        side = "forward" if abs(self.direction_deg) < 0.5 else ("left" if self.direction_deg > 0 else "right")
        where = f"{abs(self.direction_deg):.0f} deg {side} of forward" if side != "forward" else "straight forward"
        return f"{self.foot} stepped {self.length:.2f} m, {where}, turned {round(self.turn_deg)} deg"  # never "-0"


def _angle(a: np.ndarray, b: np.ndarray) -> float:
    """The angle (rad) from level vector ``a`` to ``b`` about +z."""
    return float(np.arctan2(a[0] * b[1] - a[1] * b[0], a[0] * b[0] + a[1] * b[1]))


def steps_of(problem: Problem, state: State, moved_only: bool = True) -> list[Step]:
    """The steps of a stepping ``problem``'s feet at ``state`` (none for planted feet; with ``moved_only`` only the
    feet that moved more than MOVED m or turned more than TURNED)."""
    bounds = bounds_of(problem)
    if bounds is None:
        return []
    facing = -bounds.start_heading.sum(axis=0) * (1.0, 1.0, 0.0)  # the soles' -y: forward
    facing /= max(float(np.linalg.norm(facing)), 1e-12)
    steps = []
    for k, tcp in enumerate(bounds.tcps):
        rot, pos = state.kin.tcp_frame(tcp)
        start = bounds.start_position[k]
        d = (pos - start) * (1.0, 1.0, 0.0)
        length = float(np.linalg.norm(d))
        turn = _angle(bounds.start_heading[k], rot[:, 1])
        if moved_only and length <= MOVED and abs(turn) <= TURNED:
            continue
        direction = _angle(facing, d) if length > MOVED else 0.0
        steps.append(Step(FEET[k], length, float(np.degrees(direction)), float(np.degrees(turn)),
                          tuple(map(float, start)), tuple(map(float, pos))))  # fmt: skip
    return steps


def annotate(result: Result) -> Result:
    """``result`` with its steps as notes (a stepping problem), or, with feet planted and a reach target short, the
    note that the feet stayed planted and how to let them step. Returns ``result``."""
    problem = result.problem
    if bounds_of(problem) is not None:
        steps = steps_of(problem, result.state)
        result.notes.extend(s.text() for s in steps)
        if not steps:
            result.notes.append("the feet did not step (no step helped)")
    elif result.shortfall and set(foot_targets(problem)) == set(FEET) and PLANTED_NOTE not in result.notes:
        result.notes.append(PLANTED_NOTE)
    return result


def step_dicts(result: Result) -> list[dict] | None:
    """The result file's ``steps`` of a stepping problem (a list, maybe empty), None for planted feet."""
    if bounds_of(result.problem) is None:
        return None
    return [s.as_dict() for s in steps_of(result.problem, result.state)]


def frame_moves(problem: Problem, before: State, after: State) -> list[str]:
    """Between two frames of a stepping motion: "foot_r moved 0.12 m, turned 3 deg between frames" for each foot
    that moved (the baked motion slides it along the floor: no lift-and-place phase yet)."""
    bounds = bounds_of(problem)
    if bounds is None:
        return []
    out = []
    for k, tcp in enumerate(bounds.tcps):
        (r0, p0), (r1, p1) = before.kin.tcp_frame(tcp), after.kin.tcp_frame(tcp)
        length = float(np.linalg.norm((p1 - p0)[:2]))
        turn = np.degrees(_angle(r0[:, 1], r1[:, 1]))
        if length > MOVED or abs(np.radians(turn)) > TURNED:
            out.append(f"{FEET[k]} moved {length:.3f} m, turned {turn:.0f} deg since the previous frame (slid along "
                       "the floor: the motion has no lift-and-place step yet)")  # fmt: skip
    return out
