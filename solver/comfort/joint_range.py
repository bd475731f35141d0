"""Joint-range discomfort (thesis §3.3): sum_i c_i tan^2(u_i), 0 at a joint's neutral value, steep at its limits.

u_i = (pi/2)(theta_i - n_i)/(hi_i - n_i) above the neutral value n_i and (pi/2)(theta_i - n_i)/(n_i - lo_i) below:
the thesis's tan^2 form, generalised to asymmetric limits; past |u| = U_MAX it continues linearly (C1) so it stays
finite. c_i is the model's per-joint comfort weight (1/17 per thoracolumbar vertebra, so bending the whole region
costs like one joint). With ``posture`` (the behaviour model: on when a problem's ``trunk`` comfort weight is
positive, see :mod:`.standard`) c_i is also scaled by :data:`POSTURE_SCALE` and n_i replaced by
:data:`POSTURE_NEUTRAL` where they list the joint's motion.
"""

from __future__ import annotations

import numpy as np

from .. import kernels
from ..body.model import Model
from ..body.state import State
from ..kernels.comfort import range_angles, range_per_joint, weighted_pair
from .base import ComfortTerm

U_MAX = 0.48 * np.pi
# Per motion (bone_motion, either side): the range cost's scale in the behaviour model. Bending the knees, hips and
# ankles costs less per degree than leaning the trunk (priced by :mod:`.trunk_tilt`): with 1 everywhere a squat cost
# 4 times a stoop and the manikin stooped every low lift where people bend the knees. Fitted on the training subjects
# of the motion-capture validation (docs/explanation/mocap-validation.md, docs/TUNING.md); the held-out test them.
POSTURE_SCALE = {"knee_flexion": 0.3, "hip_flexion": 0.5, "ankle_dorsiflexion": 0.2}


# Per motion: a neutral value (rad) replacing the model's in the behaviour model (clipped into the joint's limits).
# The elbow's: RULA (McAtamney & Corlett 1993) scores the lower arm best from 60 to 100 deg of flexion; with 0 the
# manikin reached near targets with straight elbows and raised arms. 60 deg is the lower end of that band, within
# the flat optimum (50-80 deg) on the training subjects (docs/TUNING.md).
POSTURE_NEUTRAL: dict[str, float] = {"elbow_flexion": float(np.radians(60.0))}
# Below a neutral value moved by POSTURE_NEUTRAL, the tan^2 span is at least this share of the joint's full range
# (not only the distance down to its lower limit): with the elbow's 60 deg against its 0 deg limit the straight
# elbow of every start pose stood at the wall (u = -pi/2), and the random benchmark's iterations went x2.35; with
# 0.5 (the wall 12.5 deg past the limit, tan^2 = 13 at a straight elbow) x1.18, and the training subjects' elbows
# are fitted as well as with the wall (docs/TUNING.md).
POSTURE_SPAN = 0.5
# Per motion: the tan^2 span above the neutral value (rad) in the behaviour model, where shorter than the span up to
# the joint's limit: the cost's wall comes before the limit, so bending further costs steeply more. The knee's at
# 110 deg (limit 140): people lift in a semi-squat, knees 30-60 deg, and avoid the full squat (Burgess-Limerick &
# Abernethy 1997; REBA adds to the legs' score from 60 deg of knee flexion, Hignett & McAtamney 2000), and the knee
# extensors' moment grows with flexion (van Dieen et al. 1999). Costs x 0.3: 0.4 at 60 deg, 3.5 at 90, 15 at 100 deg.
POSTURE_SPAN_UP: dict[str, float] = {"knee_flexion": float(np.radians(110.0))}


def posture_scale(names: tuple[str, ...], table: dict[str, float] = POSTURE_SCALE, other: float = 1.0) -> np.ndarray:
    """Per joint, the value ``table`` gives its motion (``knee_r_flexion`` -> ``knee_flexion``), else ``other``."""
    out = np.full(len(names), other)
    for i, name in enumerate(names):
        parts = name.split("_")
        if len(parts) == 3 and parts[1] in ("r", "l"):
            out[i] = table.get(f"{parts[0]}_{parts[2]}", other)
    return out


def posture_neutral(model: Model, table: dict[str, float] = POSTURE_NEUTRAL) -> np.ndarray:
    """The model's neutral values with those ``table`` gives by motion (rad), clipped into the joints' limits."""
    out = np.array(model.neutral, dtype=float)
    for i, name in enumerate(model.joint_names):
        parts = name.split("_")
        key = f"{parts[0]}_{parts[-1]}" if len(parts) == 3 and parts[1] in ("r", "l") else None
        if key in table:
            out[i] = min(max(table[key], model.lower[i]), model.upper[i])
    return out


class JointRange(ComfortTerm):
    """tan^2 range cost of every joint with finite limits; the curvature model is exact."""

    name = "range"
    description = "joints near their limits"

    def __init__(self, model: Model, posture: bool = False) -> None:
        self.model = model
        self.posture = posture  # the behaviour model's scales and neutral values (off: the thesis's form)
        lo, hi = model.lower, model.upper
        self.neutral = mid = posture_neutral(model) if posture else np.array(model.neutral, dtype=float)
        scale = posture_scale(model.joint_names) if posture else 1.0
        finite = np.isfinite(lo) & np.isfinite(hi) & (hi > lo)
        self.joint_weight = np.where(finite, model.range_weight * scale, 0.0)
        up = np.minimum(hi - mid, posture_scale(model.joint_names, POSTURE_SPAN_UP, np.inf)) if posture else hi - mid
        self.span_up = np.where(finite, np.maximum(up, 1e-9), 1.0)
        down = mid - lo
        if posture:  # a moved neutral value keeps its wall off the lower limit (POSTURE_SPAN)
            moved = mid != np.asarray(model.neutral, dtype=float)
            down = np.where(moved, np.maximum(down, POSTURE_SPAN * (hi - lo)), down)
        self.span_down = np.where(finite, np.maximum(down, 1e-9), 1.0)

    def per_joint(self, theta: np.ndarray, derivatives: bool = True) -> tuple[np.ndarray, ...]:
        """tan^2(u) per joint (unweighted) and, with ``derivatives``, its first and second derivative (per rad or m)."""
        if kernels.active():
            theta, out, work = np.asarray(theta, dtype=float), np.empty((3, len(theta))), np.empty((3, len(theta)))
            range_angles(theta, self.neutral, self.span_up, self.span_down, float(U_MAX), work)
            np.tan(work[1], out=work[1])  # NumPy's tan (its own vector code), as below
            range_per_joint(work, float(U_MAX), out[0], out[1], out[2])
            return (out[0], out[1], out[2]) if derivatives else (out[0],)
        d = theta - self.neutral
        span = np.where(d >= 0.0, self.span_up, self.span_down)
        u = 0.5 * np.pi * d / span
        t = np.tan(np.clip(u, -U_MAX, U_MAX))
        t2 = t * t
        slope = 2.0 * t * (1.0 + t2)
        beyond = np.abs(u) - U_MAX
        value = t2 + np.where(beyond > 0.0, np.abs(slope) * beyond, 0.0)
        if not derivatives:
            return (value,)
        du = 0.5 * np.pi / span
        curvature = 2.0 * (1.0 + t2) * (1.0 + 3.0 * t * t) * du * du
        return value, slope * du, curvature

    def _at(self, state: State) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """:meth:`per_joint` with derivatives at ``state``, once per state (the value and the step share it)."""
        cached = state.cache.get(self)
        if cached is None:
            cached = state.cache[self] = self.per_joint(state.theta)
        return cached

    def cost(self, state: State) -> float:
        return float(self.joint_weight @ self._at(state)[0])

    def derivatives(self, state: State, weight: float) -> tuple[np.ndarray, np.ndarray]:
        n = self.model.n
        _, slope, curvature = self._at(state)
        if kernels.active():
            return weighted_pair(float(weight), self.joint_weight, slope, curvature, state.n_x)
        grad, curv = np.zeros(state.n_x), np.zeros(state.n_x)
        grad[:n] = weight * self.joint_weight * slope
        curv[:n] = weight * self.joint_weight * curvature
        return grad, curv
