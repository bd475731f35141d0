"""The one skeleton both sides are measured on: named joint centres (m, z up, the floor at z = 0), taken from a
CMU BVH frame or from a posed manikin, and the mapping of CMU's frame into ours.

CMU's joints map to ours by name (:data:`CMU_POINTS`, :data:`MODEL_POINTS`); the joint centres are each side's own
estimates (CMU's from markers, ours from published anthropometry), so the same posture gives slightly different
lines (docs/explanation/mocap-validation.md says what that costs).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .bvh import Bvh

INCH = 0.0254  # m
CMU_UNIT = INCH / 0.45  # m per BVH unit: the ASF files say "length 0.45", i.e. lengths are inches / 0.45
# joint centre name -> CMU joint (its point); "head_top" is the Head End Site
CMU_POINTS = {
    "hip_r": "RightUpLeg", "hip_l": "LeftUpLeg", "knee_r": "RightLeg", "knee_l": "LeftLeg",
    "ankle_r": "RightFoot", "ankle_l": "LeftFoot", "toe_r": "RightToeBase", "toe_l": "LeftToeBase",
    "neck": "Neck", "head": "Head", "shoulder_r": "RightArm", "shoulder_l": "LeftArm",
    "elbow_r": "RightForeArm", "elbow_l": "LeftForeArm", "wrist_r": "RightHand", "wrist_l": "LeftHand",
}  # fmt: skip
# joint centre name -> our link whose origin it is
MODEL_POINTS = {
    "hip_r": "hip_r_flexion", "hip_l": "hip_l_flexion", "knee_r": "shank_r", "knee_l": "shank_l",
    "ankle_r": "ankle_r_dorsiflexion", "ankle_l": "ankle_l_dorsiflexion", "toe_r": "toes_r", "toe_l": "toes_l",
    "neck": "c7_rx", "head": "head", "shoulder_r": "shoulder_r_flexion", "shoulder_l": "shoulder_l_flexion",
    "elbow_r": "elbow_r_flexion", "elbow_l": "elbow_l_flexion", "wrist_r": "wrist_r_flexion",
    "wrist_l": "wrist_l_flexion",
}  # fmt: skip
NAMES = (*CMU_POINTS, "head_top")
# lines drawn in the pictures
BONES = (
    ("hip_r", "hip_l"), ("hip_r", "knee_r"), ("knee_r", "ankle_r"), ("ankle_r", "toe_r"), ("hip_l", "knee_l"),
    ("knee_l", "ankle_l"), ("ankle_l", "toe_l"), ("hip_r", "neck"), ("hip_l", "neck"), ("neck", "head"),
    ("head", "head_top"), ("neck", "shoulder_r"), ("shoulder_r", "elbow_r"), ("elbow_r", "wrist_r"),
    ("neck", "shoulder_l"), ("shoulder_l", "elbow_l"), ("elbow_l", "wrist_l"),
)  # fmt: skip
ANKLE_H = 0.039  # ankle joint height / stature (Winter 2009, Fig. 4.1): the sole below CMU's ankle joint


@dataclass
class Skeleton:
    """Named joint centres (m) in our frame: z up, the floor at z = 0, the subject facing -y, left at +x."""

    points: dict[str, np.ndarray]

    def __getitem__(self, name: str) -> np.ndarray:
        return self.points[name]


def cmu_points(bvh: Bvh, frame: int) -> dict[str, np.ndarray]:
    """The joint centres of ``frame`` in CMU's own frame (y up), in m."""
    rotations, points = bvh.pose(frame)
    out = {name: points[bvh.index(joint)] * CMU_UNIT for name, joint in CMU_POINTS.items()}
    out["head_top"] = bvh.end_point("Head", rotations, points) * CMU_UNIT
    return out


def stature_and_floor(reference: dict[str, np.ndarray]) -> tuple[float, float]:
    """A subject's stature (m) and floor height (m, CMU's y) from its standing reference frame's points: the
    head top's height over the lower ankle joint is stature x (1 - :data:`ANKLE_H`)."""
    ankle = min(reference["ankle_r"][1], reference["ankle_l"][1])
    stature = (reference["head_top"][1] - ankle) / (1.0 - ANKLE_H)
    return float(stature), float(ankle - ANKLE_H * stature)


def to_our_frame(points: dict[str, np.ndarray], floor: float) -> Skeleton:
    """CMU points (y up) -> ours: z up, the floor at 0, the midpoint of the ankles over the origin, the pelvis
    facing -y (its left hip towards +x)."""
    up = {k: np.array([p[0], -p[2], p[1] - floor]) for k, p in points.items()}  # a proper rotation: x, -z, y
    left = up["hip_l"] - up["hip_r"]
    yaw = np.arctan2(left[1], left[0])  # turn the hip line onto +x
    c, s = np.cos(-yaw), np.sin(-yaw)
    turn = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    centre = (up["ankle_r"] + up["ankle_l"]) / 2.0
    centre[2] = 0.0
    return Skeleton({k: turn @ (p - centre) for k, p in up.items()})


def model_skeleton(model, theta: np.ndarray, stature: float) -> Skeleton:
    """Our joint centres for joint values ``theta``; the head top is the vertex, ``stature`` above the floor in the
    zero pose, carried by the head link."""
    kin = model.forward(theta)
    points = {name: kin.position[model.link_index(link)].copy() for name, link in MODEL_POINTS.items()}
    head = model.link_index("head")
    zero = model.forward(model.zero_pose())
    top = np.array([0.0, 0.0, stature]) - zero.position[head]
    points["head_top"] = kin.position[head] + kin.rotation[head] @ (zero.rotation[head].T @ top)
    return Skeleton(points)
