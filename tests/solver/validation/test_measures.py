"""The posture measures on constructed skeletons with known angles, and the mapping of CMU's frame into ours."""

from __future__ import annotations

import numpy as np
import pytest

from solver.validation.measures import MEASURES, calibrated, measure
from solver.validation.skeleton import Skeleton, to_our_frame


def _rot(axis: np.ndarray, deg: float) -> np.ndarray:
    """Rodrigues: the rotation about unit ``axis`` by ``deg``."""
    a = np.radians(deg)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(a) * k + (1 - np.cos(a)) * k @ k


def standing() -> dict[str, np.ndarray]:
    """Upright, facing -y, left at +x, arms hanging: every angle zero."""
    p = {
        "hip_r": [-0.1, 0, 0.9], "hip_l": [0.1, 0, 0.9], "knee_r": [-0.1, 0, 0.5], "knee_l": [0.1, 0, 0.5],
        "ankle_r": [-0.1, 0, 0.08], "ankle_l": [0.1, 0, 0.08], "toe_r": [-0.1, -0.15, 0.02],
        "toe_l": [0.1, -0.15, 0.02], "neck": [0, 0, 1.45], "head": [0, 0, 1.55], "head_top": [0, 0, 1.75],
        "shoulder_r": [-0.2, 0, 1.42], "shoulder_l": [0.2, 0, 1.42], "elbow_r": [-0.2, 0, 1.12],
        "elbow_l": [0.2, 0, 1.12], "wrist_r": [-0.2, 0, 0.86], "wrist_l": [0.2, 0, 0.86],
    }  # fmt: skip
    return {k: np.array(v, dtype=float) for k, v in p.items()}


def test_upright_reads_zero() -> None:
    m = measure(Skeleton(standing()), 1.75)
    for name in MEASURES:
        expected = 0.9 / 1.75 if name == "pelvis_height" else 0.0
        assert m[name] == pytest.approx(expected, abs=1e-9), name


def test_known_angles() -> None:
    p = standing()
    mid = np.array([0, 0, 0.9])
    lean = _rot(np.array([1.0, 0, 0]), 30)  # about +x by 30 deg tips +z towards -y: forward
    for k in ("neck", "head", "head_top", "shoulder_r", "shoulder_l", "elbow_r", "elbow_l", "wrist_r", "wrist_l"):
        p[k] = mid + lean @ (p[k] - mid)
    p["knee_r"] = p["hip_r"] + np.array([0, -0.4, 0])  # thigh horizontal forward: hip 90 + 30
    p["ankle_r"] = p["knee_r"] + np.array([0, 0, -0.42])  # shank down: knee 90
    s = p["shoulder_l"]
    p["elbow_l"] = s + lean @ np.array([0, -0.3, 0])  # upper arm forward, square to the trunk: 90
    p["wrist_l"] = p["elbow_l"] + lean @ np.array([0, 0, 0.26])  # forearm up along the trunk: elbow 90
    m = measure(Skeleton(p), 1.75)
    assert m["trunk_flexion"] == pytest.approx(30)
    assert m["lateral_bend"] == pytest.approx(0, abs=1e-9)
    assert m["hip_flexion_r"] == pytest.approx(120)
    assert m["hip_flexion_l"] == pytest.approx(30)
    assert m["knee_flexion_r"] == pytest.approx(90)
    assert m["knee_flexion_l"] == pytest.approx(0, abs=1e-6)
    assert m["shoulder_elevation_l"] == pytest.approx(90)
    assert m["elbow_flexion_l"] == pytest.approx(90)
    assert m["shoulder_elevation_r"] == pytest.approx(0, abs=1e-6)
    assert m["head_flexion"] == pytest.approx(0, abs=1e-6)


def test_lateral_bend_is_positive_to_the_right() -> None:
    p = standing()
    mid = np.array([0, 0, 0.9])
    bend = _rot(np.array([0, 1.0, 0]), -20)  # about +y by -20 deg tips +z towards -x: the right side
    for k in ("neck", "head", "head_top"):
        p[k] = mid + bend @ (p[k] - mid)
    m = measure(Skeleton(p), 1.75)
    assert m["lateral_bend"] == pytest.approx(20)
    assert m["trunk_flexion"] == pytest.approx(0, abs=1e-9)


def test_calibration_moves_only_the_upright_zeroed_measures() -> None:
    values = {name: 10.0 for name in MEASURES}
    upright = {name: 4.0 for name in MEASURES}
    ours = {name: 1.0 for name in MEASURES}
    out = calibrated(values, upright, ours)
    assert out["trunk_flexion"] == pytest.approx(7.0)
    assert out["knee_flexion_r"] == pytest.approx(10.0)


def test_cmu_frame_mapped_to_ours() -> None:
    # a CMU skeleton (y up) facing +x (its left hip towards -z), standing 2 m from the origin
    ours = standing()
    cmu = {}
    for k, v in ours.items():  # ours -> CMU: turn so our -y (forward) becomes CMU's +x, then z up -> y up
        x, y, z = v
        cmu[k] = np.array([-y + 2.0, z + 0.05, -x + 3.0])  # 5 cm floor offset
    mapped = to_our_frame(cmu, floor=0.05)
    for k in ours:
        assert mapped[k] == pytest.approx(ours[k], abs=1e-9), k
