"""The armature layout (blender_manikin/rigging/bones.py, no bpy): bone channels reproduce the solver's kinematics
exactly.

Blender computes a pose bone's armature-space matrix as parent_pose @ parent_rest^-1 @ rest @ basis with
basis = T(location) @ R(euler, rotation mode); these tests apply that formula in NumPy.
"""

from __future__ import annotations

import numpy as np
import pytest
from helpers import random_tree

from blender_manikin.rigging.bones import RigLayout, joint_groups
from solver.io.scenario.bodies import load_body


def _axis_rotation(k: int, angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    i, j = [(1, 2), (2, 0), (0, 1)][k]
    r = np.eye(3)
    r[i, i], r[i, j], r[j, i], r[j, j] = c, -s, s, c
    return r


def _euler_matrix(euler: np.ndarray, mode: str) -> np.ndarray:
    """Blender's Euler modes: 'XYZ' applies X first, i.e. R = Rz @ Ry @ Rx."""
    r = np.eye(3)
    for letter in mode:
        k = "XYZ".index(letter)
        r = _axis_rotation(k, euler[k]) @ r
    return r


def _blender_pose(layout: RigLayout, basis: np.ndarray) -> np.ndarray:
    pose = np.zeros_like(basis)
    for b, bone in enumerate(layout.bones):
        local = bone.matrix() if bone.parent < 0 else np.linalg.solve(layout.bones[bone.parent].matrix(), bone.matrix())
        pose[b] = (pose[bone.parent] if bone.parent >= 0 else np.eye(4)) @ local @ basis[b]
    return pose


def _random_theta(model, rng: np.random.Generator) -> np.ndarray:
    lo = np.where(np.isfinite(model.lower), model.lower, -1.0)
    hi = np.where(np.isfinite(model.upper), model.upper, 1.0)
    return lo + (hi - lo) * rng.random(model.n)


@pytest.mark.parametrize("preset", ["male_50", "female_5", "snake"])
def test_euler_channels_reproduce_forward_kinematics(preset: str) -> None:
    model = load_body(preset=preset)
    layout = RigLayout(model)
    assert all(bone.exact for bone in layout.bones)
    assert layout.bones[0].parent == -1 and set(layout.bones[0].joints) >= set(range(6))  # the exterior root
    rng = np.random.default_rng(1)
    for _ in range(3):
        theta = _random_theta(model, rng)
        kin = model.forward(theta)
        loc, euler = layout.channel_values(theta)
        basis = np.zeros((len(layout.bones), 4, 4))
        for b, bone in enumerate(layout.bones):
            basis[b, :3, :3] = _euler_matrix(euler[b], bone.rotation_mode)
            basis[b, :3, 3] = loc[b]
            basis[b, 3, 3] = 1.0
        pose = _blender_pose(layout, basis)
        np.testing.assert_allclose(pose, layout.bone_matrices(kin), atol=1e-9)
        np.testing.assert_allclose(layout.theta_from_channels(loc, euler, np.zeros(model.n)), theta, atol=1e-12)
        for name in model.tcps:
            b, offset = layout.tcp_in_bone(name)
            rot, pos = kin.tcp_frame(model.tcp(name))
            np.testing.assert_allclose((pose[b] @ offset)[:3, :3], rot, atol=1e-9)
            np.testing.assert_allclose((pose[b] @ offset)[:3, 3], pos, atol=1e-9)


def test_rest_frames_are_rotations_and_groups_partition_joints() -> None:
    model = load_body(preset="male_50")
    layout = RigLayout(model)
    joints = sorted(j for g in joint_groups(model) for j in g)
    assert joints == list(range(model.n))
    for bone in layout.bones:
        np.testing.assert_allclose(bone.rest.T @ bone.rest, np.eye(3), atol=1e-12)
        assert np.linalg.det(bone.rest) > 0 and bone.length >= 0.01
    names = [b.name for b in layout.bones]
    assert len(set(names)) == len(names)
    hip = layout.bones[layout.index["thigh_r"]]
    assert [model.joint_names[j] for j in hip.joints] == ["hip_r_flexion", "hip_r_abduction", "hip_r_rotation"]
    assert layout.bones[layout.index["shank_r"]].lock_rotation.count(True) == 2  # the knee turns about one axis


def test_quaternion_fallback_for_oblique_axes(tree) -> None:
    layout = RigLayout(tree)
    assert not all(bone.exact for bone in layout.bones)
    theta = _random_theta(tree, np.random.default_rng(2))
    kin = tree.forward(theta)
    np.testing.assert_allclose(_blender_pose(layout, layout.basis_matrices(kin)), layout.bone_matrices(kin), atol=1e-9)


def test_random_tree_layout_is_consistent() -> None:
    model = random_tree(5)
    layout = RigLayout(model)
    assert sorted(j for b in layout.bones for j in b.joints) == list(range(model.n))
