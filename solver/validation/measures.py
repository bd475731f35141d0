"""Posture measures computed the same way on any :class:`~.skeleton.Skeleton` (degrees; the pelvis height as a
fraction of stature).

The pelvis frame: up is world z, left is the hip line (right hip -> left hip) made horizontal, forward = left x up.
The trunk line runs from the mid-hip point to the neck base. Sagittal angles are measured in the pelvis's
forward-up plane (0 = vertical, + forward); the others are 3-D angles between segment lines.
"""

from __future__ import annotations

import numpy as np

from .skeleton import Skeleton

MEASURES = (
    "trunk_flexion", "lateral_bend", "hip_flexion_r", "hip_flexion_l", "knee_flexion_r", "knee_flexion_l",
    "pelvis_height", "shoulder_elevation_r", "shoulder_elevation_l", "elbow_flexion_r", "elbow_flexion_l",
    "head_flexion",
)  # fmt: skip
# measures zeroed at each skeleton's own upright pose (see :func:`calibrated`): the two skeletons place the hip,
# neck and head joint centres differently, which tilts the lines between them by up to ~15 deg when standing
UPRIGHT_ZEROED = ("trunk_flexion", "lateral_bend", "hip_flexion_r", "hip_flexion_l", "head_flexion", "pelvis_height")
UNITS = {name: ("fraction of stature" if name == "pelvis_height" else "deg") for name in MEASURES}


def _unit(v: np.ndarray) -> np.ndarray:
    return v / max(float(np.linalg.norm(v)), 1e-12)


def _angle(a: np.ndarray, b: np.ndarray) -> float:
    """The angle between two vectors, deg."""
    return float(np.degrees(np.arccos(np.clip(_unit(a) @ _unit(b), -1.0, 1.0))))


def pelvis_axes(s: Skeleton) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Forward, left and up unit vectors of the pelvis frame."""
    up = np.array([0.0, 0.0, 1.0])
    left = s["hip_l"] - s["hip_r"]
    left = _unit(left - (left @ up) * up)
    return np.cross(left, up), left, up


def sagittal(v: np.ndarray, forward: np.ndarray, up: np.ndarray) -> float:
    """The forward tilt (deg) of ``v`` from vertical in the forward-up plane."""
    return float(np.degrees(np.arctan2(v @ forward, v @ up)))


def measure(s: Skeleton, stature: float) -> dict[str, float]:
    """Every measure of :data:`MEASURES` for skeleton ``s`` of a body of ``stature`` (m)."""
    forward, left, up = pelvis_axes(s)
    mid = (s["hip_r"] + s["hip_l"]) / 2.0
    trunk = s["neck"] - mid
    trunk_tilt = sagittal(trunk, forward, up)
    out = {
        "trunk_flexion": trunk_tilt,
        "lateral_bend": float(np.degrees(np.arcsin(np.clip(_unit(trunk) @ -left, -1.0, 1.0)))),  # + to the right
        "pelvis_height": float(mid[2] / stature),
        "head_flexion": sagittal(s["head_top"] - s["neck"], forward, up) - trunk_tilt,
    }
    for side in ("r", "l"):
        thigh = s[f"knee_{side}"] - s[f"hip_{side}"]
        thigh_fwd = float(np.degrees(np.arctan2(thigh @ forward, -(thigh @ up))))  # 0 hanging, + forward
        out[f"hip_flexion_{side}"] = thigh_fwd + trunk_tilt
        out[f"knee_flexion_{side}"] = _angle(thigh, s[f"ankle_{side}"] - s[f"knee_{side}"])
        upper = s[f"elbow_{side}"] - s[f"shoulder_{side}"]
        out[f"shoulder_elevation_{side}"] = _angle(upper, -trunk)
        out[f"elbow_flexion_{side}"] = _angle(upper, s[f"wrist_{side}"] - s[f"elbow_{side}"])
    return {name: out[name] for name in MEASURES}


def calibrated(values: dict[str, float], upright: dict[str, float], ours_upright: dict[str, float]) -> dict[str, float]:
    """``values`` measured on one skeleton, with each :data:`UPRIGHT_ZEROED` measure moved by that skeleton's
    upright value (``upright``) onto ours (``ours_upright``, the manikin's zero pose): both then read the same when
    both stand upright."""
    return {k: v - upright[k] + ours_upright[k] if k in UPRIGHT_ZEROED else v for k, v in values.items()}
