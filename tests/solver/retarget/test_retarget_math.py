"""Retargeting math (solver.retarget, no bpy): two-bone IK, the rest-aligned transfer (identity onto itself, a scaled
T-posed copy with other rolls), local transforms that compose back to the poses, bone names filled in across rig
conventions (the shipped maps reproduced), and one-line errors for bad maps."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from blender_manikin.rigging.bones import RigLayout
from solver.body.spatial import exp_so3, log_so3
from solver.bodymesh import fit_body
from solver.errors import ModelError
from solver.io.scenario.bodies import load_preset
from solver.retarget.bone_map import REQUIRED, SHIPPED_RIGS, check_map, dumps_map, load_map, shipped_path
from solver.retarget.names import auto_map, parse
from solver.retarget.shipped import rig_bones, rig_map
from solver.retarget.skeleton import (
    Skeleton,
    object_scale,
    rigid,
    rigid_inverse,
    rigid_local,
    rigid_world,
    rotation_between,
    skeleton,
)
from solver.retarget.transfer import LIMBS, basis_matrices, miss_cause, plan, pose_frame, solve_motion
from solver.retarget.two_bone import two_bone_ik

ENDS = ("hand_l", "hand_r", "foot_l", "foot_r")


@pytest.fixture(scope="module")
def model():
    return load_preset("male_50")


@pytest.fixture(scope="module")
def layout(model) -> RigLayout:
    return RigLayout(model)


@pytest.fixture(scope="module")
def ours(layout) -> Skeleton:
    bones = layout.bones
    return skeleton([b.name for b in bones], [bones[b.parent].name if b.parent >= 0 else None for b in bones],
                    np.array([b.matrix() for b in bones]), np.array([b.length for b in bones]))  # fmt: skip


@pytest.fixture(scope="module")
def body(model):
    return fit_body(model)


def random_poses(model, layout: RigLayout, n: int, seed: int = 1) -> list[np.ndarray]:
    """(bones, 4, 4) pose frames of ``n`` random poses within the joint limits, the root moved and turned a little."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        theta = model.lower + rng.uniform(0.2, 0.8, model.n) * (model.upper - model.lower)
        theta[:6] = rng.uniform(-0.2, 0.2, 6)
        out.append(layout.bone_matrices(model.forward(theta)))
    return out


def transformed(skel: Skeleton, scale: float, offset: np.ndarray, twist_seed: int) -> Skeleton:
    """``skel`` scaled about the origin, moved, and every bone turned about its own axis (another roll)."""
    rng = np.random.default_rng(twist_seed)
    rest = skel.rest.copy()
    for b in range(len(rest)):
        rest[b, :3, :3] = rest[b, :3, :3] @ exp_so3(np.array([0.0, rng.uniform(-np.pi, np.pi), 0.0]))
    rest[:, :3, 3] = scale * rest[:, :3, 3] + offset
    return Skeleton(skel.names, skel.parents, rest, scale * skel.lengths)


def t_posed(skel: Skeleton) -> Skeleton:
    """``skel`` with each arm (and everything below the upper arm) turned about the shoulder to point sideways."""
    rest = skel.rest.copy()
    for side, sign in (("l", 1.0), ("r", -1.0)):
        top = skel.index(f"upper_arm_{side}")
        turn = rotation_between(skel.tails[top] - skel.heads[top], np.array([sign, 0.0, 0.0]))
        pivot = skel.heads[top]
        for b in range(len(rest)):
            if b == top or top in skel.ancestors(b):
                rest[b, :3, :3] = turn @ rest[b, :3, :3]
                rest[b, :3, 3] = pivot + turn @ (rest[b, :3, 3] - pivot)
    return Skeleton(skel.names, skel.parents, rest, skel.lengths)


def test_two_bone_ik_reaches_keeps_lengths_and_the_bend_plane() -> None:
    rng = np.random.default_rng(3)
    for _ in range(200):
        root, middle, end = rng.normal(size=(3, 3))
        goal = root + rng.uniform(0.3, 0.95) * (np.linalg.norm(middle - root) + np.linalg.norm(end - middle)) * \
            rotation_between(np.array([1.0, 0, 0]), rng.normal(size=3)) @ np.array([1.0, 0, 0])  # fmt: skip
        upper, lower, miss = two_bone_ik(root, middle, end, goal, np.array([0.0, 1.0, 0.0]))
        new_middle = root + upper @ (middle - root)
        new_end = new_middle + lower @ upper @ (end - middle)
        if abs(np.linalg.norm(middle - root) - np.linalg.norm(end - middle)) > np.linalg.norm(goal - root):
            continue  # inside the inner radius: not reachable from here
        assert miss == 0.0 and np.linalg.norm(new_end - goal) < 1e-9
        for m in (upper, lower):
            np.testing.assert_allclose(m @ m.T, np.eye(3), atol=1e-12)
        normal = np.cross(goal - root, middle - root)  # the middle joint stays in the plane root, goal, middle
        assert abs(normal @ (new_middle - root)) < 1e-9 * max(1.0, np.linalg.norm(normal))


def test_two_bone_ik_out_of_reach_points_the_straight_limb_at_the_goal() -> None:
    root, middle, end = np.zeros(3), np.array([0.0, 0.0, -0.4]), np.array([0.0, 0.05, -0.8])
    goal = np.array([0.3, 0.0, -1.0])
    upper, lower, miss = two_bone_ik(root, middle, end, goal, np.array([0.0, -1.0, 0.0]))
    new_middle = upper @ middle
    new_end = new_middle + lower @ upper @ (end - middle)
    reach = np.linalg.norm(middle) + np.linalg.norm(end - middle)
    assert miss == pytest.approx(np.linalg.norm(goal) - reach)
    np.testing.assert_allclose(new_end, goal / np.linalg.norm(goal) * reach, atol=1e-9)


def test_a_straight_limb_bends_towards_the_pole() -> None:
    root, middle, end = np.zeros(3), np.array([0.0, 0.0, -0.4]), np.array([0.0, 0.0, -0.8])
    upper, _, _ = two_bone_ik(root, middle, end, np.array([0.0, 0.0, -0.6]), np.array([0.0, -1.0, 0.0]))
    assert (upper @ middle)[1] < -0.1  # the knee goes forward (-y)


def test_onto_itself_every_bone_follows_exactly(model, layout, ours) -> None:
    """Our skeleton onto a copy of itself, every bone mapped: the target's poses are ours, pinned or not."""
    identity = {n: n for n in ours.names}
    the_plan = plan(ours, ours, identity, np.eye(3))
    assert the_plan.ratio == pytest.approx(1.0)
    for source in random_poses(model, layout, 5):
        for pinned in ((), tuple(LIMBS)):
            poses, misses = pose_frame(the_plan, source, pinned)
            np.testing.assert_allclose(poses, source, atol=1e-9)
            assert all(m < 1e-9 for m in misses.values())


def test_a_scaled_t_posed_copy_with_other_rolls_puts_hands_and_feet_where_ours_are_scaled(model, layout, ours) -> None:
    """Uniformly scaled (x1.2), moved, every bone rolled, arms in a T-pose: without pins the rest alignment alone
    puts the wrists and ankles on ours scaled about the ankles' midpoint (1e-6 m); the hands turn as ours do."""
    offset = np.array([2.0, -1.0, 0.3])
    target = t_posed(transformed(ours, 1.2, offset, twist_seed=5))
    the_plan = plan(ours, target, {n: n for n in ours.names}, np.eye(3))
    assert the_plan.ratio == pytest.approx(1.2)
    for source in random_poses(model, layout, 5, seed=7):
        poses, _ = pose_frame(the_plan, source)
        for end in ENDS:
            b = ours.index(end)
            np.testing.assert_allclose(poses[b, :3, 3], the_plan.scaled(source[b, :3, 3]), atol=1e-6)
        for end in ("foot_l", "foot_r"):  # feet are not aligned (legs stand alike): their turn is ours exactly
            b = ours.index(end)
            ours_turn = source[b, :3, :3] @ ours.rest[b, :3, :3].T
            np.testing.assert_allclose(poses[b, :3, :3] @ target.rest[b, :3, :3].T, ours_turn, atol=1e-9)


def test_pins_put_the_ends_on_their_goals_when_the_arms_are_shorter(model, layout, ours) -> None:
    """Forearms 15 % shorter than a uniform scale: unpinned, the wrists miss ours (scaled) by centimetres; pinned,
    they land on them, or as close as the arm reaches."""
    target = transformed(ours, 1.0, np.zeros(3), twist_seed=2)
    rest = target.rest.copy()
    for side in "lr":  # shorten each forearm: everything below it moves up its axis
        fore = target.index(f"forearm_{side}")
        shift = -0.15 * target.lengths[fore] * target.rest[fore, :3, 1]
        for b in range(len(rest)):
            if fore in target.ancestors(b):
                rest[b, :3, 3] += shift
    target = Skeleton(target.names, target.parents, rest, target.lengths)
    the_plan = plan(ours, target, {n: n for n in ours.names}, np.eye(3))
    source = random_poses(model, layout, 1, seed=11)[0]
    free, _ = pose_frame(the_plan, source)
    pinned, misses = pose_frame(the_plan, source, ("hand_l", "hand_r"))
    for side in "lr":
        b = ours.index(f"hand_{side}")
        goal = the_plan.scaled(source[b, :3, 3])
        missed = np.linalg.norm(pinned[b, :3, 3] - goal)
        assert np.linalg.norm(free[b, :3, 3] - goal) > 0.01 > missed
        assert missed == pytest.approx(misses[f"hand_{side}"], abs=1e-9)  # 0 in reach, else straight at the goal


@settings(max_examples=20, deadline=None)
@given(seed=st.integers(0, 10_000), scale=st.floats(0.01, 3.0))
def test_local_transforms_compose_back_to_the_poses(ours, model, layout, seed: int, scale: float) -> None:
    """pose = parent pose parent rest^-1 rest basis, the basis translation in the object's units (scaled)."""
    target = transformed(ours, 1.0, np.zeros(3), twist_seed=seed)
    poses = random_poses(model, layout, 1, seed=seed)[0] @ np.linalg.inv(ours.rest) @ target.rest
    basis = basis_matrices(target, poses, scale)
    for b in range(len(target.names)):
        p = int(target.parents[b])
        local = basis[b].copy()
        local[:3, 3] *= scale
        parent = np.eye(4) if p < 0 else poses[p] @ rigid_inverse(target.rest[p])
        np.testing.assert_allclose(parent @ target.rest[b] @ local, poses[b], atol=1e-9)


def test_world_and_object_frames_round_trip_and_scales_must_be_uniform() -> None:
    world = rigid(exp_so3(np.array([np.pi / 2, 0.0, 0.3])), np.array([1.0, 2.0, 3.0]))
    world[:3, :3] *= 0.01  # an FBX import: cm, Y up
    local = np.array([rigid(exp_so3(np.array([0.1, 0.2, 0.3])), np.array([10.0, 20.0, 30.0]))])
    np.testing.assert_allclose(rigid_local(world, rigid_world(world, local)), local, atol=1e-9)
    assert object_scale(world) == pytest.approx(0.01)
    world[:3, 0] *= 2.0
    with pytest.raises(ModelError, match="scale is not uniform"):
        object_scale(world)


def test_skeletons_are_ordered_parents_first_and_checked() -> None:
    rest, lengths = np.stack([np.eye(4)] * 3), np.ones(3)
    skel = skeleton(["c", "a", "b"], ["b", None, "a"], rest, lengths)
    assert skel.names == ("a", "b", "c") and skel.parents.tolist() == [-1, 0, 1]
    with pytest.raises(ModelError, match="parent 'x' is not in the armature"):
        skeleton(["a", "b"], [None, "x"], rest[:2], lengths[:2])
    with pytest.raises(ModelError, match="its own ancestor"):
        skeleton(["a", "b"], ["b", "a"], rest[:2], lengths[:2])


@pytest.mark.parametrize(
    "name, expected",
    [
        ("mixamorig:LeftUpLeg", ("l", "upleg")),
        ("mixamorig:RightHandIndex1", ("r", "handindex")),
        ("upper_arm.L", ("l", "upperarm")),
        ("DEF-thigh.R.001", ("r", "thigh")),
        ("thigh_l", ("l", "thigh")),
        ("L_Thigh", ("l", "thigh")),
        ("Bip01 R Forearm", ("r", "forearm")),
        ("J_Bip_L_UpperArm", ("l", "upperarm")),
        ("lShldr", ("l", "shldr")),
        ("RThumb", ("r", "thumb")),
        ("J_Bip_C_Hips", ("", "hips")),
        ("spine.006", ("", "spine")),
    ],
)
def test_names_split_into_side_and_words(name: str, expected: tuple[str, str]) -> None:
    assert parse(name)[:2] == expected


def test_mch_bones_are_never_mapped() -> None:
    assert parse("MCH-thigh_parent.L")[3] == -1


def _rig_skeleton(body, rig: str) -> Skeleton:
    bones = rig_bones(body, rig)
    rest = []
    for b in bones:  # any roll: the map does not depend on it
        y = (b.tail - b.head) / np.linalg.norm(b.tail - b.head)
        rest.append(rigid(rotation_between(np.array([0.0, 1.0, 0.0]), y), b.head))
    return skeleton([b.name for b in bones], [b.parent for b in bones], np.array(rest),
                    np.array([np.linalg.norm(b.tail - b.head) for b in bones]))  # fmt: skip


@pytest.mark.parametrize("rig", list(SHIPPED_RIGS))
def test_auto_map_reproduces_each_shipped_map(rig: str, ours, body) -> None:
    """The shipped maps were filled in by auto_map and checked by hand: auto_map still gives exactly them."""
    target = _rig_skeleton(body, rig)
    shipped = rig_map(rig)
    assert auto_map(ours, target) == shipped
    theirs = {n: (target.names[p] if p >= 0 else None) for n, p in zip(target.names, target.parents, strict=True)}
    check_map(shipped, ours.names, theirs, rig)
    assert load_map(shipped_path(rig))[0] == rig


def _renamed(ours: Skeleton, names: dict[str, str]) -> Skeleton:
    new = [names.get(n, f"bone_{i:02d}") for i, n in enumerate(ours.names)]
    return Skeleton(tuple(new), ours.parents, ours.rest, ours.lengths)


@pytest.mark.parametrize(
    "convention",
    [
        {
            "pelvis": "Bip01 Pelvis",
            "thigh": "Bip01 {S} Thigh",
            "shank": "Bip01 {S} Calf",
            "foot": "Bip01 {S} Foot",
            "clavicle": "Bip01 {S} Clavicle",
            "upper_arm": "Bip01 {S} UpperArm",
            "forearm": "Bip01 {S} Forearm",
            "hand": "Bip01 {S} Hand",
            "head": "Bip01 Head",
            "thumb_{s}_metacarpal": "Bip01 {S} Finger0",
            "index_{s}_proximal": "Bip01 {S} Finger1",
            "index_{s}_middle": "Bip01 {S} Finger11",
        },
        {
            "pelvis": "J_Bip_C_Hips",
            "thigh": "J_Bip_{S}_UpperLeg",
            "shank": "J_Bip_{S}_LowerLeg",
            "foot": "J_Bip_{S}_Foot",
            "toes": "J_Bip_{S}_ToeBase",
            "clavicle": "J_Bip_{S}_Shoulder",
            "upper_arm": "J_Bip_{S}_UpperArm",
            "forearm": "J_Bip_{S}_LowerArm",
            "hand": "J_Bip_{S}_Hand",
            "head": "J_Bip_C_Head",
            "index_{s}_proximal": "J_Bip_{S}_Index1",
        },
        {
            "pelvis": "Pelvis",
            "thigh": "{S}_Hip",
            "shank": "{S}_Knee",
            "foot": "{S}_Ankle",
            "clavicle": "{S}_Collar",
            "upper_arm": "{S}_Shoulder",
            "forearm": "{S}_Elbow",
            "hand": "{S}_Wrist",
            "head": "Head",
        },
        {
            "pelvis": "hip",
            "thigh": "{s}Thigh",
            "shank": "{s}Shin",
            "foot": "{s}Foot",
            "clavicle": "{s}Collar",
            "upper_arm": "{s}Shldr",
            "forearm": "{s}ForeArm",
            "hand": "{s}Hand",
            "head": "head",
        },
        {
            "pelvis": "Hips",
            "thigh": "thigh_{s}",
            "shank": "shin_{s}",
            "foot": "foot_{s}",
            "upper_arm": "arm_{s}",
            "forearm": "forearm_{s}",
            "hand": "hand_{s}",
            "head": "Head",
            "clavicle": "shoulder_{s}",
        },
    ],
    ids=["3ds Max biped", "VRoid", "SMPL joints", "Poser BVH", "generic"],
)
def test_auto_map_reads_other_conventions(convention: dict[str, str], ours) -> None:
    """3ds Max, VRoid, SMPL's joint names, Poser's BVH and a plain naming: each limb bone, the pelvis and the head."""
    names, expected = {}, {}
    for part, pattern in convention.items():
        for s, big in (("l", "L"), ("r", "R")):
            ours_name = part.format(s=s) if "{s}" in part else part if part in ("pelvis", "head") else f"{part}_{s}"
            names[ours_name] = pattern.format(S=big, s=s)
            expected[ours_name] = names[ours_name]
    found = auto_map(ours, _renamed(ours, names))
    assert {k: found.get(k) for k in expected} == expected
    assert set(REQUIRED) <= set(found)


@pytest.mark.parametrize(
    "change, message",
    [
        (lambda m: m.update(spleen="Hips"), "'spleen' is not a bone of the manikin"),
        (lambda m: m.update(pelvis="Nope"), "pelvis -> 'Nope': 'rig' has no such bone"),
        (lambda m: m.update(l3=m["thigh_l"]), "is mapped from both"),
        (lambda m: (m.pop("hand_l"), m.pop("foot_r")), "no bone for hand_l, foot_r"),
        (lambda m: m.update(shank_l=m["thigh_l"], thigh_l=m["shank_l"]), "is not below thigh_l"),
    ],
)
def test_bad_maps_are_one_line_errors(change, message: str, ours, body) -> None:
    target = _rig_skeleton(body, "mixamo")
    theirs = {n: (target.names[p] if p >= 0 else None) for n, p in zip(target.names, target.parents, strict=True)}
    bone_map = {k.replace("mixamorig:", ""): v for k, v in rig_map("mixamo").items()}
    change(bone_map)
    with pytest.raises(ModelError, match=message) as caught:
        check_map(bone_map, ours.names, theirs, "rig")
    assert "\n" not in str(caught.value)


def test_map_files_round_trip_and_bad_files_name_the_key(tmp_path) -> None:
    bone_map = {"pelvis": "Hips", "thigh_l": "Left Thigh", "spine.weird": 'a "quoted" name'}
    path = tmp_path / "map.toml"
    path.write_text(dumps_map(bone_map, "mine"), encoding="utf-8")
    assert load_map(path) == ("mine", bone_map)
    cases = {"[bones]\npelvis = 3\n": "bones.pelvis: expected a bone name, got 3", "rig = 1\n[bones]\n": "rig:",
             "bones = 2\n": "bones: expected a table", "[bones\n": "not a bone map"}  # fmt: skip
    for text, message in cases.items():
        path.write_text(text, encoding="utf-8")
        with pytest.raises(ModelError, match=message):
            load_map(path)
    with pytest.raises(ModelError, match="bone map not found"):
        load_map(tmp_path / "missing.toml")


@pytest.mark.parametrize("rig", list(SHIPPED_RIGS))
def test_shipped_rigs_list_parents_first_with_bones_of_length(rig: str, body) -> None:
    bones = rig_bones(body, rig)
    seen: set[str] = set()
    for b in bones:
        assert b.parent is None or b.parent in seen
        assert np.linalg.norm(b.tail - b.head) > 0.005
        seen.add(b.name)
    assert set(rig_map(rig).values()) <= seen
    with pytest.raises(ModelError, match="no shipped rig 'bogus'"):
        rig_bones(body, "bogus")


def test_rotation_between_turns_one_direction_onto_another() -> None:
    rng = np.random.default_rng(0)
    for a, b in [*rng.normal(size=(20, 2, 3)), (np.array([1.0, 0, 0]), np.array([-1.0, 0, 0]))]:
        r = rotation_between(a, b)
        np.testing.assert_allclose(r @ (a / np.linalg.norm(a)), b / np.linalg.norm(b), atol=1e-12)
        assert np.linalg.norm(log_so3(r)) <= np.pi + 1e-9


def turned(skel: Skeleton, angle: float) -> Skeleton:
    """``skel`` turned by ``angle`` (rad) about world up through the origin: a character facing another way."""
    turn = np.eye(4)
    turn[:3, :3] = exp_so3(np.array([0.0, 0.0, angle]))
    return Skeleton(skel.names, skel.parents, turn @ skel.rest, skel.lengths)


@pytest.mark.parametrize("angle", [np.pi, np.pi / 2, -0.3])
def test_a_character_facing_another_way_moves_in_its_own_facing(model, layout, ours, angle: float) -> None:
    """Our skeleton turned about world up (facing +y for half a turn): the facing is read from the hips and the
    motion turns with it, every bone exactly ours turned (was: played in world axes, bending it backwards)."""
    target = turned(ours, angle)
    the_plan = plan(ours, target, {n: n for n in ours.names}, np.eye(3))
    assert np.radians(the_plan.facing_deg) == pytest.approx(angle, abs=1e-9)
    turn = np.eye(4)
    turn[:3, :3] = exp_so3(np.array([0.0, 0.0, angle]))
    for source in random_poses(model, layout, 3, seed=5):
        for pinned in ((), tuple(LIMBS)):
            poses, misses = pose_frame(the_plan, source, pinned)
            np.testing.assert_allclose(poses, turn @ source, atol=1e-9)
            assert all(m < 1e-9 for m in misses.values())


def test_arm_relative_hand_goals_are_reached_where_body_goals_are_not(model, layout, ours) -> None:
    """Arms 25 % shorter than the legs' scale (a Rigify meta-rig's proportions): hand goals scaled with the body are
    out of reach; arm-relative goals (about the shoulder, by the arm ratio) are reached, and ``auto`` picks them
    for the whole motion."""
    target = transformed(ours, 1.0, np.zeros(3), twist_seed=4)
    rest = target.rest.copy()
    for side in "lr":
        upper = target.index(f"upper_arm_{side}")
        shoulder = rest[upper, :3, 3].copy()
        for b in range(len(rest)):  # everything below the shoulder pulled 25 % towards it
            if upper in target.ancestors(b):
                rest[b, :3, 3] = shoulder + 0.75 * (rest[b, :3, 3] - shoulder)
    target = Skeleton(target.names, target.parents, rest, target.lengths)
    the_plan = plan(ours, target, {n: n for n in ours.names}, np.eye(3))
    assert the_plan.arm_ratios["hand_l"] == pytest.approx(0.75) and the_plan.ratio == pytest.approx(1.0)
    sources = np.array(random_poses(model, layout, 3, seed=9))
    hands = [["hand_l", "hand_r"]] * len(sources)
    _, body_misses, used = solve_motion(the_plan, sources, hands, "body")
    assert used == "body" and max(m for f in body_misses for m in f.values()) > 0.01
    poses, misses, used = solve_motion(the_plan, sources, hands, "auto")
    assert used == "arm" and max(m for f in misses for m in f.values()) < 1e-9
    for pose, source in zip(poses, sources, strict=True):
        for side in "lr":
            upper, hand = ours.index(f"upper_arm_{side}"), ours.index(f"hand_{side}")
            reach = 0.75 * (source[hand, :3, 3] - source[upper, :3, 3])
            np.testing.assert_allclose(pose[hand, :3, 3] - pose[upper, :3, 3], reach, atol=1e-9)
    assert "relatively shorter" in miss_cause(the_plan, "hand_l", "body")
    with pytest.raises(ModelError, match="hand goals: expected one of auto, body, arm"):
        solve_motion(the_plan, sources, hands, "nearest")
