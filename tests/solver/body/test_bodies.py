"""Tests of the human and snake bodies: structure, mass, zero pose, balance, symmetry and joint directions."""

from __future__ import annotations

import re

import numpy as np
import pytest
from scipy.spatial import ConvexHull

from solver.body.humans import anthropometry as A
from solver.errors import ModelError
from solver.io.scenario.bodies import PRESETS_DIR, build_human, build_snake, list_presets, load_body

HUMANS = ("female_5", "male_50", "male_95")
MIRROR = np.diag([-1.0, 1.0, 1.0])


@pytest.fixture(scope="module", params=HUMANS)
def human(request):
    return load_body(request.param)


@pytest.fixture(scope="module")
def male():
    return load_body("male_50")


def tcp_at(model, theta, name):
    """(rotation, position) of TCP ``name`` for joint values ``theta``."""
    return model.forward(theta).tcp_frame(model.tcp(name))


def with_values(model, **values):
    theta = model.zero_pose()
    for joint, value in values.items():
        theta[model.joint_index(joint)] = value
    return theta


def tcp_shift(model, name, joint, value=0.3, **base):
    """Displacement (m) of TCP ``name`` when ``joint`` goes from its ``base`` value to ``base + value`` rad."""
    start = with_values(model, **base)
    moved = start.copy()
    moved[model.joint_index(joint)] += value
    return tcp_at(model, moved, name)[1] - tcp_at(model, start, name)[1]


def link_shift(model, link, joint, value=0.3):
    moved = with_values(model, **{joint: value})
    return (
        model.forward(moved).position[model.link_index(link)]
        - model.forward(model.zero_pose()).position[model.link_index(link)]
    )


def test_presets_are_listed_and_found():
    assert set(HUMANS) | {"snake"} <= set(list_presets())
    assert (PRESETS_DIR / "manikins" / "male_50.toml").is_file()


def test_joint_count_and_names(human):
    assert human.n == 160
    assert len(set(human.joint_names)) == 160 and len(set(human.link_names)) == 160
    spine = [j for j in human.joint_names if re.fullmatch(r"[ltc]\d+_r[xyz]", j)]
    assert len(spine) == 72
    for link in (
        "pelvis",
        "head",
        "eyes",
        "upper_arm_r",
        "forearm_l",
        "hand_r",
        "thigh_l",
        "shank_r",
        "foot_l",
        "toes_r",
        "t1",
        "l5",
    ):
        human.link_index(link)


def test_total_mass_and_info(human):
    assert human.total_mass == pytest.approx(human.info["mass"], rel=1e-9)
    for key in ("sex", "stature", "mass", "percentile", "source"):
        assert key in human.info
    assert human.info["source"]


def test_zero_pose_feet_hands_head(human):
    h = human.info["stature"]
    x_hip = 0.25 * A.WINTER_H["hip_width"] * h
    kin = human.forward(human.zero_pose())
    assert np.allclose(kin.rotation, np.eye(3))
    for name, sx in (("foot_r", -1.0), ("foot_l", 1.0)):
        rot, pos = kin.tcp_frame(human.tcp(name))
        assert np.allclose(rot, np.eye(3))
        assert np.allclose(pos, (sx * x_hip, 0.0, 0.0), atol=1e-12)
    hip_z = kin.position[human.link_index("thigh_r")][2]
    for name in ("hand_r", "hand_l"):
        assert kin.tcp_frame(human.tcp(name))[1][2] < hip_z
    head = kin.tcp_frame(human.tcp("head"))[1][2]
    assert kin.tcp_frame(human.tcp("shoulder_r"))[1][2] < head < h
    assert kin.tcp_frame(human.tcp("eyes"))[1][2] < h


def test_soles_are_counter_clockwise(human):
    for name in ("foot_r", "foot_l", "toe_r", "toe_l"):
        sole = human.tcp(name).sole
        x, y = sole[:, 0], sole[:, 1]
        assert 0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y) > 0


def test_com_inside_support_polygon(human):
    kin = human.forward(human.zero_pose())
    corners = []
    for name in ("foot_r", "foot_l"):
        rot, pos = kin.tcp_frame(human.tcp(name))
        for cx, cy in human.tcp(name).sole:
            corners.append((pos + rot @ (cx, cy, 0.0))[:2])
    hull = ConvexHull(np.array(corners))
    com = kin.body_com()[:2]
    assert np.all(hull.equations[:, :2] @ com + hull.equations[:, 2] < -1e-3)


def test_trunk_com_matches_de_leva_whole_trunk(human):
    """Sub-segment CMs (pelvis, l5-l1, t12-t1) combine near de Leva's whole-trunk CM (female: the OMPH/XYPH
    splits are estimates from mean sub-segment lengths, off by about 0.01 H; male: within 0.002 H)."""
    h, sex = human.info["stature"], human.info["sex"]
    kin = human.forward(human.zero_pose())
    trunk = [human.link_index(n) for n in ("pelvis", "l5", "l4", "l3", "l2", "l1")]
    trunk += [human.link_index(f"t{i}") for i in range(1, 13)]
    com = human.mass[trunk] @ kin.com[trunk] / human.mass[trunk].sum()
    supr, midh = A.WINTER_H["shoulder_height"] * h, A.WINTER_H["hip_height"] * h
    expected = supr + A.segment("trunk", sex)[1] * (midh - supr)
    assert com[2] == pytest.approx(expected, abs=(0.002 if sex == "male" else 0.011) * h)
    assert human.mass[trunk].sum() == pytest.approx(
        sum(A.mass_fractions(sex)[k] for k in ("upper_trunk", "mid_trunk", "low_trunk")) * human.info["mass"]
    )


def test_limits_contain_zero_and_neutral(human):
    assert np.all(human.lower <= 0.0) and np.all(human.upper >= 0.0)
    assert np.all(human.lower <= human.neutral) and np.all(human.neutral <= human.upper)
    assert np.all(human.lower < human.upper)
    assert np.all(human.strength > 0)


def test_range_weights(male):
    w = dict(zip(male.joint_names, male.range_weight, strict=True))
    lumbar_thoracic = [w[j] for j in w if re.fullmatch(r"[lt]\d+_r[xyz]", j)]
    cervical = [w[j] for j in w if re.fullmatch(r"c\d_r[xyz]", j)]
    assert sum(lumbar_thoracic) == pytest.approx(3.0) and sum(cervical) == pytest.approx(3.0)
    assert w["index_r_pip"] == pytest.approx(0.1) and w["thumb_l_ip"] == pytest.approx(0.1)
    assert w["eyes_yaw"] == pytest.approx(0.2) and w["root_tx"] == 0.0 and w["knee_r_flexion"] == 1.0


def _mirror_name(name: str) -> str:
    return re.sub(r"_l(?=_|$)", "_r", name)


def test_left_right_symmetry(male):
    rng = np.random.default_rng(1)
    theta = male.zero_pose()
    for i, name in enumerate(male.joint_names):
        if re.search(r"_r(?=_|$)", name):
            value = rng.uniform(male.lower[i], male.upper[i])
            theta[i] = value
            theta[male.joint_index(re.sub(r"_r(?=_|$)", "_l", name))] = value
    pairs = [(i, male.link_index(_mirror_name(n))) for i, n in enumerate(male.link_names) if _mirror_name(n) != n]
    assert len(pairs) == (160 - 6 - 72 - 2) // 2
    for pose in (male.zero_pose(), theta):
        kin = male.forward(pose)
        for left, right in pairs:
            assert np.allclose(kin.position[left], MIRROR @ kin.position[right], atol=1e-12)
            assert np.allclose(kin.rotation[left], MIRROR @ kin.rotation[right] @ MIRROR, atol=1e-12)
            assert np.allclose(kin.com[left], MIRROR @ kin.com[right], atol=1e-12)
        assert abs(kin.body_com()[0]) < 1e-12
    for left, right in pairs:
        assert male.mass[left] == male.mass[right]
        assert np.allclose(male.lower[left], male.lower[right]) and np.allclose(male.upper[left], male.upper[right])


@pytest.mark.parametrize(
    "tcp, joint, axis, sign, base",
    [
        ("hand_r", "shoulder_r_flexion", 1, -1, {}),
        ("hand_l", "shoulder_l_flexion", 1, -1, {}),
        ("hand_r", "shoulder_r_abduction", 0, -1, {}),
        ("hand_l", "shoulder_l_abduction", 0, 1, {}),
        ("hand_r", "shoulder_r_rotation", 0, 1, {"elbow_r_flexion": np.pi / 2}),  # internal: hand medial
        ("hand_l", "shoulder_l_rotation", 0, -1, {"elbow_l_flexion": np.pi / 2}),
        ("hand_r", "elbow_r_flexion", 1, -1, {}),
        ("hand_l", "elbow_l_flexion", 1, -1, {}),
        ("knuckles_r", "wrist_r_flexion", 0, 1, {}),  # toward the right palm (+x)
        ("knuckles_l", "wrist_l_flexion", 0, -1, {}),
        ("knuckles_r", "wrist_r_deviation", 1, -1, {}),  # radial: toward the thumb (forward)
        ("knuckles_l", "wrist_l_deviation", 1, -1, {}),
        ("shoulder_r", "clavicle_r_elevation", 2, 1, {}),
        ("shoulder_l", "clavicle_l_elevation", 2, 1, {}),
        ("shoulder_r", "clavicle_r_protraction", 1, -1, {}),
        ("shoulder_l", "scapula_l_protraction", 1, -1, {}),
        ("hand_r", "scapula_r_upward_rotation", 2, 1, {"shoulder_r_abduction": np.pi / 2}),
        ("hand_l", "scapula_l_upward_rotation", 2, 1, {"shoulder_l_abduction": np.pi / 2}),
        ("foot_r", "hip_r_flexion", 1, -1, {}),
        ("foot_l", "hip_l_abduction", 0, 1, {}),
        ("foot_r", "hip_r_abduction", 0, -1, {}),
        ("toe_r", "hip_r_rotation", 0, 1, {}),  # internal: toes turn medially
        ("toe_l", "hip_l_rotation", 0, -1, {}),
        ("foot_r", "knee_r_flexion", 1, 1, {}),
        ("foot_l", "knee_l_flexion", 1, 1, {}),
        ("toe_r", "ankle_r_dorsiflexion", 2, 1, {}),
        ("toe_l", "toes_l_flexion", 2, -1, {}),
        ("head", "l3_rx", 1, -1, {}),
        ("head", "t6_ry", 0, 1, {}),
        ("eyes", "c4_rz", 0, 1, {}),
        ("head", "c2_rx", 1, -1, {}),
    ],
)
def test_positive_values_do_what_the_names_say(male, tcp, joint, axis, sign, base):
    shift = tcp_shift(male, tcp, joint, **base)
    assert sign * shift[axis] > 1e-3, shift


def test_forearm_pronation_turns_palm_backward(male):
    for side, normal_x in (("r", 1.0), ("l", -1.0)):
        rot0 = tcp_at(male, male.zero_pose(), f"hand_{side}")[0]
        assert np.allclose(rot0[:, 2], (normal_x, 0.0, 0.0))  # palm normal faces the thigh
        assert np.allclose(rot0[:, 0], (0.0, 0.0, -1.0))  # x toward the fingertips
        rot = tcp_at(male, with_values(male, **{f"forearm_{side}_pronation": 0.5}), f"hand_{side}")[0]
        assert rot[1, 2] > 0.3  # palm normal turned toward +y (backward)


def test_ankle_inversion_and_eyes(male):
    for side, lateral in (("r", -1.0), ("l", 1.0)):
        rot = tcp_at(male, with_values(male, **{f"ankle_{side}_inversion": 0.3}), f"foot_{side}")[0]
        assert lateral * rot[0, 2] > 0.2  # sole normal tilts laterally: the sole faces medially
    gaze = (0.0, -1.0, 0.0)
    assert (tcp_at(male, with_values(male, eyes_pitch=0.3), "eyes")[0] @ gaze)[2] < -0.2  # look down
    assert (tcp_at(male, with_values(male, eyes_yaw=0.3), "eyes")[0] @ gaze)[0] > 0.2  # look left


def test_finger_directions(male):
    assert link_shift(male, "index_r_distal", "index_r_mcp_flexion")[0] > 1e-3  # toward the right palm
    assert link_shift(male, "index_l_distal", "index_l_pip")[0] < -1e-3  # toward the left palm
    assert link_shift(male, "index_r_distal", "index_r_mcp_abduction")[1] < -1e-3  # away from the middle finger
    assert link_shift(male, "little_l_distal", "little_l_mcp_abduction")[1] > 1e-3
    assert link_shift(male, "thumb_r_distal", "thumb_r_cmc_abduction")[0] > 1e-3  # palmar abduction
    hand_joints = [
        j for j in male.joint_names if j.startswith(("index_r", "middle_r", "ring_r", "little_r", "thumb_r"))
    ]
    assert len(hand_joints) == 20


def test_strength_sources(male):
    s = dict(zip(male.joint_names, map(tuple, male.strength), strict=True))
    scale = male.info["mass"] * 9.81 * male.info["stature"]
    assert s["hip_r_flexion"] == pytest.approx((0.161 * scale, 0.113 * scale))
    assert s["knee_l_flexion"] == pytest.approx((0.163 * scale, 0.087 * scale))
    assert s["ankle_r_dorsiflexion"] == pytest.approx((0.095 * scale, 0.033 * scale))
    assert s["elbow_r_flexion"] == (70.0, 101.0) and s["l1_rx"] == (688.0, 212.0)
    assert np.all(np.isinf(male.strength[:6]))


def test_build_human_scales_with_stature():
    small, tall = build_human("female", 1.5, 50.0), build_human("male", 2.0, 90.0)
    for model, h in ((small, 1.5), (tall, 2.0)):
        head = model.forward(model.zero_pose()).com[model.link_index("head")][2]
        assert 0.9 * h < head < h
    with pytest.raises(ModelError, match="sex"):
        build_human("other", 1.7, 70.0)
    with pytest.raises(ModelError, match="stature"):
        build_human("male", 3.0, 70.0)


def test_snake():
    snake = load_body("snake")
    assert snake.n == 6 + 27
    kin = snake.forward(snake.zero_pose())
    assert np.allclose(kin.tcp_frame(snake.tcp("top"))[1], (0.0, 0.0, 9 * 0.2 + 0.04))
    assert np.allclose(kin.tcp_frame(snake.tcp("floor"))[1], 0.0)
    assert snake.total_mass == pytest.approx(9 * 1.0 + 0.5)
    assert np.allclose(snake.upper[6:], np.pi / 2) and np.allclose(snake.lower[6:], -np.pi / 2)
    short = build_snake(segments=3, segment_length=0.5)
    assert short.n == 15
    assert short.forward(short.zero_pose()).tcp_frame(short.tcp("top"))[1][2] == pytest.approx(1.54)


def _write(tmp_path, text):
    path = tmp_path / "body.toml"
    path.write_text(text)
    return path


GOOD = '[body]\nkind = "human"\nsex = "male"\nstature = 1.8\nmass = 80.0\n'


def test_load_body_file(tmp_path):
    model = load_body(file=_write(tmp_path, GOOD))
    assert model.n == 160 and model.info["stature"] == 1.8
    snake = load_body(file=_write(tmp_path, '[body]\nkind = "snake"\nsegments = 4\n'))
    assert snake.n == 6 + 12


@pytest.mark.parametrize(
    "text, words",
    [
        ("[body\nkind = ", ["malformed TOML"]),
        ("[other]\nx = 1\n", ["[body]"]),
        ('[body]\nkind = "robot"\n', ["kind", "robot"]),
        (GOOD.replace('"male"', '"alien"'), ["sex", "alien"]),
        (GOOD.replace("80.0", "-5.0"), ["mass", "-5.0"]),
        (GOOD.replace("80.0", "nan"), ["mass"]),
        (GOOD.replace("1.8", '"tall"'), ["stature", "tall"]),
        (GOOD.replace("stature = 1.8\n", ""), ["stature", "missing"]),
        (GOOD + "statur = 1.8\n", ["unknown key", "statur"]),
        (GOOD + "percentile = 150\n", ["percentile"]),
        ('[body]\nkind = "snake"\nsegments = 0\n', ["segments"]),
    ],
)
def test_load_body_errors_name_the_key(tmp_path, text, words):
    path = _write(tmp_path, text)
    with pytest.raises(ModelError) as err:
        load_body(file=path)
    message = str(err.value)
    assert "\n" not in message and str(path) in message
    for word in words:
        assert word in message


def test_load_body_missing_and_unknown(tmp_path):
    with pytest.raises(ModelError, match="not found"):
        load_body(file=tmp_path / "nope.toml")
    with pytest.raises(ModelError, match="male_50") as err:
        load_body("giant")
    assert "giant" in str(err.value)
    with pytest.raises(ModelError):
        load_body()


def test_the_support_polygon_is_the_convex_hull_counter_clockwise():
    """The Result panel's support polygon (solver.body.contacts.support_polygon) against scipy's hull on random
    corner sets, with repeated and collinear points; fewer than three distinct points come back as given."""
    from solver.body.contacts import support_polygon

    rng = np.random.default_rng(3)
    for k in range(200):
        points = rng.uniform(-0.3, 0.3, size=(int(rng.integers(3, 17)), 3))
        if k % 3 == 0:  # a repeated corner and one halfway along an edge of two others
            points = np.vstack([points, points[:1], 0.5 * (points[1] + points[2])])
        polygon = support_polygon(points)
        flat = points[:, :2].round(12)
        hull = {tuple(p) for p in flat[ConvexHull(points[:, :2]).vertices]}
        assert hull <= {tuple(p) for p in polygon} <= {tuple(p) for p in flat}  # scipy's corners, all input points
        edges = np.roll(polygon, -1, axis=0) - polygon  # counter-clockwise: every point on the left of every edge
        to_point = flat[:, None, :] - polygon[None, :, :]
        assert (edges[None, :, 0] * to_point[:, :, 1] - edges[None, :, 1] * to_point[:, :, 0] >= -1e-12).all()
        x, y = polygon[:, 0], polygon[:, 1]
        assert 0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y) > 0
    line = np.array([[0.0, 0.0, 0.0], [0.1, 0.1, 0.0], [0.2, 0.2, 0.0]])  # collinear: the two ends
    assert support_polygon(line).tolist() == [[0.0, 0.0], [0.2, 0.2]]
    assert support_polygon(line[:2]).tolist() == [[0.0, 0.0], [0.1, 0.1]]
