"""The behaviour model's start: a crouch instead of standing when a reach target is low.

A local solver stays in the basin of its start. From the standing zero pose the comfort step straightens a knee
that has no reason to bend yet, so the solver stoops to a low box even where the behaviour model rates a squat far
better. The rule (no per-task knob): with the behaviour model on (:func:`solver.comfort.standard.behaviour_on`), a
solve that would start from the standing zero pose starts from :func:`crouched_pose` when a reach target that
holds a height lies below the standing hip joint. Measured on the motion-capture key frames
(docs/explanation/mocap-validation.md): solving from both starts and keeping the more comfortable pose gives the
same errors within 0.3 deg for about twice the iterations. Any other solve from the zero pose starts with the
joints the range term's posture tables give a neutral value (the elbows at 60 deg) there: from straight elbows the
random benchmark took x1.18 the iterations of the model off, from rested ones x0.84 (docs/TUNING.md).
"""

from __future__ import annotations

import weakref
from typing import Protocol

import numpy as np

from ..body.model import Model
from ..comfort import Comfort
from ..comfort.joint_range import posture_neutral
from ..comfort.standard import behaviour_on
from .specs import ProblemSpec


class PoseTask(Protocol):
    """What the rule reads of a :class:`~solver.problem.problem.Problem` (which imports this module)."""

    model: Model
    spec: ProblemSpec
    comfort: Comfort


# The crouch: knees 60 deg, hips 60 deg, ankles 10 deg dorsiflexed, on both sides (the semi-squat people lift in,
# knees 30-60 deg: Burgess-Limerick & Abernethy 1997; the solver moves on from it). A deeper start (knees 100, hips
# 80, ankles 15) over-squatted low picks and set-downs (docs/TUNING.md).
CROUCH_DEG = {"knee_{s}_flexion": 60.0, "hip_{s}_flexion": 60.0, "ankle_{s}_dorsiflexion": 10.0}
HIP_JOINT = "hip_r_flexion"

# Per model, what the rule reads of it (the standing hip height, the crouch, the rested pose): computed once, not on
# every solve from the zero pose (~0.1 ms: a forward pass and the joint names' lookups). Models are frozen.
_PER_MODEL: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def _once(model: Model, key: str, compute):
    known = _PER_MODEL.setdefault(model, {})
    if key not in known:
        known[key] = compute(model)
    return known[key]


def _standing_hip(model: Model) -> float:
    """World z of the hip joint in the zero pose (m)."""
    return float(model.forward(model.zero_pose()).position[model.joint_names.index(HIP_JOINT)][2])


def crouched_pose(model: Model) -> np.ndarray | None:
    """The zero pose with the legs bent as :data:`CROUCH_DEG` (within limits), None when the model has no such legs."""
    crouch = _once(model, "crouch", _crouched)
    return None if crouch is None else crouch.copy()


def _crouched(model: Model) -> np.ndarray | None:
    theta = model.zero_pose().copy()
    names = model.joint_names
    for side in ("r", "l"):
        for template, degrees in CROUCH_DEG.items():
            name = template.format(s=side)
            if name not in names:
                return None
            i = names.index(name)
            theta[i] = np.clip(np.radians(degrees), model.lower[i], model.upper[i])
    return theta


def low_reach(problem: PoseTask) -> bool:
    """Whether a reach target (not a support) that holds a height (locks z) lies below the standing hip joint (m,
    world z; the zero pose stands on z = 0)."""
    model = problem.model
    if HIP_JOINT not in model.joint_names:
        return False
    hip = _once(model, "hip", _standing_hip)
    for target in problem.spec.targets:
        if target.support or not target.enabled or target.operator is not None or "z" not in target.lock:
            continue
        if float(target.position[2]) < hip:
            return True
    return False


def rested_pose(model: Model) -> np.ndarray:
    """The zero pose with the joints the behaviour model moves the neutral value of (the elbows) at that value."""
    return _once(model, "rested", _rested).copy()


def _rested(model: Model) -> np.ndarray:
    theta = model.zero_pose().copy()
    neutral = posture_neutral(model)
    moved = neutral != np.asarray(model.neutral, dtype=float)
    theta[moved] = neutral[moved]
    return theta


def behaviour_start(problem: PoseTask) -> np.ndarray | None:
    """The joint values to start from instead of the zero pose (the crouch, or the rested elbows), None to keep
    it (the behaviour model off)."""
    weights = problem.comfort.weights
    if weights is None or not behaviour_on(weights):
        return None
    crouch = crouched_pose(problem.model) if low_reach(problem) else None
    return crouch if crouch is not None else rested_pose(problem.model)
