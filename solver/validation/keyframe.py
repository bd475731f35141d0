"""A motion-capture key frame made a pose problem: a body from the subject's stature (and arm lengths), the
measured wrists as reach targets, the measured feet as planted supports, solved from the zero pose (the behaviour
model starts from a crouch for a low hand)."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from ..body.humans.human import build_human
from ..body.humans.measurements import MEASUREMENTS
from ..body.model import Model, Tcp
from ..comfort import BEHAVIOUR, STANDARD
from ..iteration import solve
from ..options import SolverOptions
from ..problem.problem import Problem
from ..problem.specs import ProblemSpec, Target
from .skeleton import Skeleton

BMI = 24.0  # kg/m^2, the mass estimate where a subject's mass is not published (as presets/manikins/male_50.toml)
FRICTION = 0.6


@dataclass
class Subject:
    """What a subject's body is made from: sex, stature (m), mass (kg; None: BMI 24 x stature^2) and joint-centre
    arm lengths (m) from the skeleton."""

    name: str
    sex: str
    stature: float
    mass: float | None = None
    upper_arm: float | None = None
    forearm: float | None = None


def subject_body(subject: Subject) -> Model:
    """The manikin of ``subject``, with a TCP at each wrist joint (the point the hand targets hold)."""
    h = subject.stature
    measured = {}
    for key, value in (("upper_arm_length", subject.upper_arm), ("forearm_length", subject.forearm)):
        lo, hi = MEASUREMENTS[key]
        if value is not None and lo * h <= value <= hi * h:  # CMU's joint-centre lengths, used as the landmarks'
            measured[key] = value
    mass = subject.mass if subject.mass is not None else BMI * h * h
    model = build_human(subject.sex, h, mass, name=f"cmu_{subject.name}", measurements=measured)
    return with_wrist_tcps(model)


def with_wrist_tcps(model: Model) -> Model:
    """``model`` with TCPs ``wrist_r``, ``wrist_l`` at the wrist joints (the hand links' origins)."""
    tcps = dict(model.tcps)
    for side in ("r", "l"):
        tcps[f"wrist_{side}"] = Tcp(f"wrist_{side}", model.link_index(f"hand_{side}"), np.eye(3), np.zeros(3))
    return dataclasses.replace(model, tcps=tcps)


def _yaw(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def foot_targets(model: Model, measured: Skeleton) -> list[Target]:
    """Each foot planted flat on the floor under the measured ankle, turned as the measured foot (ankle -> toe)."""
    zero = model.forward(model.zero_pose())
    out = []
    for side in ("r", "l"):
        tcp = model.tcp(f"foot_{side}")
        rot0, pos0 = zero.tcp_frame(tcp)
        ankle0 = zero.position[model.link_index(f"ankle_{side}_dorsiflexion")]
        toward = measured[f"toe_{side}"] - measured[f"ankle_{side}"]
        turn = _yaw(float(np.arctan2(toward[0], -toward[1])))  # our foot points along -y in the zero pose
        offset = pos0 - ankle0
        offset[2] = 0.0
        at = measured[f"ankle_{side}"] + turn @ offset
        at[2] = pos0[2]  # the sole's point on the floor
        out.append(Target(f"foot_{side}", at, turn @ rot0, support=True, friction=FRICTION))
    return out


def key_frame_problem(model: Model, measured: Skeleton, hands: tuple[str, ...], behaviour: bool = True) -> Problem:
    """Feet planted where measured, each wrist in ``hands`` ("r", "l") held at its measured point (position only:
    CMU's hand segment has too few markers for its roll to be trusted), in balance, floor and self-collision on;
    comfort is the behaviour model (:data:`~solver.comfort.BEHAVIOUR`) unless ``behaviour`` is False."""
    targets = foot_targets(model, measured)
    for side in hands:
        targets.append(Target(f"wrist_{side}", measured[f"wrist_{side}"].copy(), lock=("x", "y", "z")))
    weights = BEHAVIOUR if behaviour else STANDARD
    return Problem(model, ProblemSpec(targets=tuple(targets), balance=True, comfort_weights=weights))


def solve_key_frame(
    model: Model, measured: Skeleton, hands: tuple[str, ...], options: SolverOptions | None = None,
    behaviour: bool = True,
):  # fmt: skip
    """The solver's pose for the key frame (a :class:`~solver.iteration.result.Result`), from the zero pose: with
    ``behaviour`` the behaviour model (which starts from a crouch when a hand is below the standing hip,
    :mod:`solver.problem.starts`), else the standard comfort."""
    problem = key_frame_problem(model, measured, hands, behaviour)
    return solve(problem, model.zero_pose(), options or SolverOptions())
