"""Two-bone IK: turn a limb (upper segment about the hip or shoulder, lower about the knee or elbow) so its end
reaches a goal, keeping the plane the limb bends in. NumPy only; positions in m."""

from __future__ import annotations

import numpy as np

from .skeleton import rotation_between, unit

STRAIGHT = 1e-4  # a limb whose middle joint lies within this fraction of the upper length of the line is straight


def two_bone_ik(
    root: np.ndarray, middle: np.ndarray, end: np.ndarray, goal: np.ndarray, pole: np.ndarray
) -> tuple[np.ndarray, np.ndarray, float]:
    """Rotations ``(upper, lower, miss)``: ``upper`` (3x3) turns the upper segment about ``root``, ``lower``
    turns the lower segment (already carried by ``upper``) about the new middle joint, so that ``end`` lands on
    ``goal``; ``miss`` (m) is how far it stays from the goal when the goal is out of reach (the limb points at
    it, straight or folded). The middle joint stays in the plane through ``root``, ``goal`` and its current
    position; a straight limb bends towards ``pole`` (a direction: forward for a knee, backward for an elbow)."""
    root, middle, end, goal = (np.asarray(v, dtype=float) for v in (root, middle, end, goal))
    upper_len = float(np.linalg.norm(middle - root))
    lower_len = float(np.linalg.norm(end - middle))
    to_goal = goal - root
    wanted = float(np.linalg.norm(to_goal))
    if wanted < 1e-9 or upper_len < 1e-9 or lower_len < 1e-9:
        return np.eye(3), np.eye(3), float(np.linalg.norm(end - goal))
    along = to_goal / wanted
    reach = float(np.clip(wanted, abs(upper_len - lower_len), upper_len + lower_len))
    bend = middle - root
    side = bend - along * float(bend @ along)
    if np.linalg.norm(side) < STRAIGHT * upper_len:
        side = np.asarray(pole, dtype=float) - along * float(np.asarray(pole, dtype=float) @ along)
    side = unit(side)
    cos_a = (upper_len**2 + reach**2 - lower_len**2) / (2.0 * upper_len * reach)
    cos_a = float(np.clip(cos_a, -1.0, 1.0))
    new_middle = root + upper_len * (cos_a * along + np.sqrt(1.0 - cos_a**2) * side)
    new_end = root + reach * along
    upper = rotation_between(middle - root, new_middle - root)
    lower = rotation_between(upper @ (end - middle), new_end - new_middle)
    return upper, lower, abs(wanted - reach)
