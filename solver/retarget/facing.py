"""Which way a skeleton faces at rest, and the turn about the world's up axis from ours to a target's. NumPy only.

A standing character's forward is its left (right hip joint to left hip joint) crossed with up (world +z):
Blender's usual -y for a character whose left hip is at +x. The motion turns by the angle between the manikin's
forward and the target's, about world up, so a character facing +y, or whose object is turned half a turn, walks
its own way instead of bending backwards.
"""

from __future__ import annotations

import numpy as np

from .skeleton import Skeleton

UP = np.array([0.0, 0.0, 1.0])  # world up (m); an FBX import's Y-up lives in its object's rotation


def forward(skel: Skeleton, left_hip: str, right_hip: str) -> np.ndarray | None:
    """The skeleton's horizontal forward direction (unit, world) from its hip joints (the thigh bones' heads),
    or None when they lie one above the other (a character lying down: no facing to read)."""
    left = skel.heads[skel.index(left_hip)] - skel.heads[skel.index(right_hip)]
    left = left - UP * float(left @ UP)
    norm = float(np.linalg.norm(left))
    if norm < 1e-6:
        return None
    return np.cross(left / norm, UP)


def yaw(angle: float) -> np.ndarray:
    """The rotation (3x3) by ``angle`` (rad) about world up."""
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def facing_turn(source: Skeleton, target: Skeleton, bone_map: dict[str, str]) -> tuple[np.ndarray, float]:
    """(rotation about world up taking our facing onto the target's, its angle in degrees); identity when either
    facing cannot be read."""
    ours = forward(source, "thigh_l", "thigh_r")
    theirs = forward(target, bone_map["thigh_l"], bone_map["thigh_r"])
    if ours is None or theirs is None:
        return np.eye(3), 0.0
    angle = float(np.arctan2(np.cross(ours, theirs) @ UP, ours @ theirs))
    return yaw(angle), float(np.degrees(angle))
