"""A human body from measurements: each optional measurement changes the segments it determines and no other,
the stature and the masses stay; a bad value is one ModelError line naming the file, the key and the range."""

from __future__ import annotations

import numpy as np
import pytest

from solver.body.humans import anthropometry as A
from solver.body.humans.measurements import MEASUREMENTS, nominal
from solver.errors import ModelError
from solver.io.scenario.bodies import build_human, load_body

SEX, H, M = "male", 1.74, 72.7


def zero(model, link: str) -> np.ndarray:
    """World position (m) of ``link``'s origin (its joint) in the zero pose."""
    return model.forward(model.zero_pose()).position[model.link_index(link)]


def tcp(model, name: str) -> np.ndarray:
    """World position (m) of TCP ``name`` in the zero pose."""
    return model.forward(model.zero_pose()).tcp_frame(model.tcp(name))[1]


def lengths(model) -> dict[str, float]:
    """Segment lengths (m) between joint centres in the zero pose, and the hip joints' height."""
    dist = lambda a, b: float(np.linalg.norm(zero(model, a) - zero(model, b)))  # noqa: E731
    return {
        "hip_height": float(zero(model, "thigh_r")[2]),
        "thigh": dist("thigh_r", "shank_r"),
        "shank": dist("shank_r", "foot_r"),
        "trunk": float(zero(model, "upper_arm_r")[2] - zero(model, "thigh_r")[2]),
        "spine": float(zero(model, "head")[2] - zero(model, "pelvis")[2]),
        "upper_arm": dist("upper_arm_r", "forearm_r"),
        "forearm": dist("forearm_r", "hand_r"),
        "shoulders": float(zero(model, "upper_arm_l")[0] - zero(model, "upper_arm_r")[0]),
        "hips": float(zero(model, "thigh_l")[0] - zero(model, "thigh_r")[0]),
        "foot": float(np.linalg.norm(tcp(model, "heel_r") - tcp(model, "toe_r"))),
    }


@pytest.fixture(scope="module")
def plain():
    return build_human(SEX, H, M)


def changed(plain, **measures) -> dict[str, float]:
    """The lengths that differ (by more than 0.1 mm) from the body without measurements, and by how much (m)."""
    body = build_human(SEX, H, M, measurements=measures)
    before, after = lengths(plain), lengths(body)
    return {k: after[k] - before[k] for k in before if abs(after[k] - before[k]) > 1e-4}


def test_nominal_values_give_the_plain_body(plain):
    measures = {k: nominal(k, SEX, H) for k in ("sitting_height", "shoulder_breadth", "upper_arm_length")}
    assert changed(plain, **measures) == {}


def test_sitting_height_lengthens_the_trunk_and_shortens_the_legs_by_the_same(plain):
    excess = 0.04
    delta = changed(plain, sitting_height=nominal("sitting_height", SEX, H) + excess)
    assert set(delta) == {"hip_height", "thigh", "shank", "trunk", "spine"}
    assert delta["hip_height"] == pytest.approx(-excess, abs=1e-9)
    assert delta["thigh"] < 0 and delta["shank"] < 0 and delta["trunk"] > 0 and delta["spine"] > 0
    body = build_human(SEX, H, M, measurements={"sitting_height": nominal("sitting_height", SEX, H) + excess})
    hip, eyes = lengths(plain)["hip_height"], tcp(plain, "eyes")[2]
    stretch = (H - (hip - excess)) / (H - hip)  # everything above the hips fills the same stature
    assert tcp(body, "eyes")[2] == pytest.approx(hip - excess + (eyes - hip) * stretch, abs=1e-9)
    assert delta["spine"] == pytest.approx(lengths(plain)["spine"] * (stretch - 1.0), abs=1e-9)


@pytest.mark.parametrize(
    ("key", "value", "moved"),
    [
        ("shoulder_breadth", 0.45, "shoulders"),
        ("upper_arm_length", 0.36, "upper_arm"),
        ("forearm_length", 0.25, "forearm"),
        ("hip_breadth", 0.40, "hips"),
        ("foot_length", 0.29, "foot"),
    ],
)
def test_each_measurement_changes_its_own_segment_only(plain, key, value, moved):
    delta = changed(plain, **{key: value})
    assert set(delta) == {moved}
    # hip breadth and foot length replace Winter's; the others scale the model by the measurement over its nominal
    winter = {"hip_breadth": "hip_width", "foot_length": "foot_length"}
    reference = A.WINTER_H[winter[key]] * H if key in winter else nominal(key, SEX, H)
    assert 1.0 + delta[moved] / lengths(plain)[moved] == pytest.approx(value / reference, rel=1e-9)


def test_shoulder_breadth_scales_the_joints_lateral_offsets(plain):
    k = 0.45 / nominal("shoulder_breadth", SEX, H)
    body = build_human(SEX, H, M, measurements={"shoulder_breadth": 0.45})
    for link in ("upper_arm_r", "scapula_r"):
        assert zero(body, link)[0] == pytest.approx(k * zero(plain, link)[0], rel=1e-9)
    assert zero(body, "clavicle_r")[0] == pytest.approx(zero(plain, "clavicle_r")[0])  # the sternoclavicular joint


def test_masses_stay_de_leva_fractions_of_body_mass(plain):
    every = {k: 0.5 * (lo + hi) * H for k, (lo, hi) in MEASUREMENTS.items()}
    body = build_human(SEX, H, M, measurements=every)
    assert np.allclose(body.mass, plain.mass)
    assert body.info["measurements"] == every


def write_body(tmp_path, extra: str):
    path = tmp_path / "body.toml"
    path.write_text(f'[body]\nkind = "human"\nsex = "male"\nstature = 1.74\nmass = 72.7\n{extra}\n')
    return path


def test_a_body_file_takes_measurements(tmp_path, plain):
    body = load_body(file=write_body(tmp_path, "sitting_height = 0.95\nforearm_length = 0.25"))
    assert body.info["measurements"] == {"sitting_height": 0.95, "forearm_length": 0.25}
    assert lengths(body)["hip_height"] < lengths(plain)["hip_height"]


@pytest.mark.parametrize(
    ("extra", "words"),
    [
        ("sitting_height = 1.5", ["body.toml", "sitting_height", "[0.766, 1.079] m", "got 1.5"]),
        ('upper_arm_length = "long"', ["body.toml", "upper_arm_length", "got 'long'"]),
        ("hip_breadth = nan", ["body.toml", "hip_breadth", "got nan"]),
        ("arm_length = 0.6", ["body.toml", "unknown key 'arm_length'", "forearm_length"]),
    ],
)
def test_bad_measurements_are_one_line_errors(tmp_path, extra, words):
    with pytest.raises(ModelError) as info:
        load_body(file=write_body(tmp_path, extra))
    message = str(info.value)
    assert "\n" not in message
    for word in words:
        assert word in message
