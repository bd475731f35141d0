"""Ergonomics (issue 6): hand-computed joint moments and disc compression, published NIOSH / RULA / REBA numbers,
posture angles on known poses, and the ``python -m solver ergo`` command on real results and bad input."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from solver.body.spatial import matrix_to_quat
from solver.ergonomics import ErgoOptions, evaluate, niosh, owas, reba, rula, run
from solver.ergonomics.loads import disc_compression, joint_moments, percent_of_strength
from solver.ergonomics.postures import measure
from solver.io.result.read import frame_from_dict, result_from_dict
from solver.io.scenario.bodies import load_body

REPO = Path(__file__).resolve().parents[3]
G = 9.81
# matplotlib 3.9 calls pyparsing names that newer pyparsing deprecates; not ours to fix
pytestmark = pytest.mark.filterwarnings("ignore:.*deprecated - use:DeprecationWarning")


def run_cli(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "solver", *args], cwd=REPO, capture_output=True, text=True, timeout=120
    )


def frame_dict(model, theta: np.ndarray, loads: tuple = ()) -> dict:
    """A result frame (README format) for joint values ``theta`` without contacts: ``loads`` = ((tcp, force), ...)."""
    kin = model.forward(theta)
    joints = {
        name: dict(value=float(theta[i]), min=float(model.lower[i]), max=float(model.upper[i]),
                   type="prismatic" if model.prismatic[i] else "revolute", link=model.link_names[i],
                   position=kin.position[i].tolist(), axis=kin.axis[i].tolist())
        for i, name in enumerate(model.joint_names)
    }  # fmt: skip
    tcps = {}
    for name, tcp in model.tcps.items():
        rot, pos = kin.tcp_frame(tcp)
        tcps[name] = dict(position=pos.tolist(), rotation=matrix_to_quat(rot).tolist(), link=model.link_names[tcp.link])
    links = [
        dict(name=model.link_names[i], parent=None if model.parent[i] < 0 else model.link_names[model.parent[i]],
             mass=float(model.mass[i]), com=kin.com[i].tolist())
        for i in range(model.n)
    ]  # fmt: skip
    return dict(frame=1, converged=True, gravity=[0.0, 0.0, -G], joints=joints, tcps=tcps, links=links, contacts={},
                loads=[dict(tcp=t, point=tcps[t]["position"], force=list(f)) for t, f in loads])  # fmt: skip


@pytest.fixture(scope="module")
def male() -> object:
    return load_body(preset="male_50")


def pose(model, **values: float) -> np.ndarray:
    theta = model.zero_pose()
    for name, v in values.items():
        theta[model.joint_index(name)] = v
    return theta


# ---------------- joint loads ----------------


def test_shoulder_moment_arm_horizontal_with_5kg_is_the_hand_calculation(male) -> None:
    """Right arm straight forward (shoulder flexion 90 deg), 5 kg in the palm: M = g * sum(m_i * lever_i).

    Levers and masses by hand from the published fractions the body is built from (Winter 2009 lengths as shares
    of stature H, de Leva 1996 male masses and CM positions): upper arm 0.186 H (CM 0.5772), forearm 0.146 H
    (CM 0.4574), hand CM 0.79 of wrist->knuckles (0.45 of the 0.108 H hand), palm centre 0.30 of the hand length.
    """
    h, m = 1.74, 72.7
    ua, fa, hand = 0.186 * h, 0.146 * h, 0.108 * h
    parts = [  # (kg, lever m)
        (0.0271 * m, 0.5772 * ua),
        (0.0162 * m, ua + 0.4574 * fa),
        (0.0061 * m, ua + fa + 0.79 * 0.45 * hand),
        (5.0, ua + fa + 0.30 * hand),
    ]
    expected = G * sum(kg * lever for kg, lever in parts)
    frame = frame_from_dict(frame_dict(male, pose(male, shoulder_r_flexion=math.pi / 2),
                                   loads=(("hand_r", (0.0, 0.0, -5.0 * G)),)), "test")  # fmt: skip
    _, tau, _ = joint_moments(frame)
    i = frame.index["shoulder_r_flexion"]
    # the load pulls the arm down = extension: negative about the flexion axis; muscles flex (capacity 91 N*m)
    assert tau[i] == pytest.approx(-expected, rel=2e-3)
    assert expected == pytest.approx(40.0, abs=3.0)  # about 5 kg * 0.6 m + the arm's own weight
    report = evaluate(result_from_dict({"frames": [frame_dict(male, pose(male, shoulder_r_flexion=math.pi / 2),
                                                               loads=(("hand_r", (0.0, 0.0, -5.0 * G)),))]}),
                      ErgoOptions(manikin="male_50"))  # fmt: skip
    load = report["frames"][0]["joint_loads"]["shoulder_r_flexion"]
    assert load["percent_strength"] == pytest.approx(expected / 91.0 * 100.0, rel=2e-3)


def test_percent_uses_the_capacity_of_the_direction_the_muscles_pull() -> None:
    strength = np.array([[20.0, 40.0], [20.0, 40.0], [np.inf, np.inf]])
    pct = percent_of_strength(np.array([-10.0, 10.0, 5.0]), strength)
    assert pct[0] == pytest.approx(25.0)  # external -10: muscles +10 against the positive capacity 40
    assert pct[1] == pytest.approx(50.0)  # external +10: muscles -10 against the negative capacity 20
    assert math.isnan(pct[2])  # unlimited: no percent


def tiny_trunk(load_kg: float = 10.0) -> dict:
    """Pelvis + L4/L5 joints at z = 1 m; 40 kg upper body 0.2 m in front, a load 0.4 m in front of the disc."""

    def joint(name, link, axis):
        return dict(value=0.0, type="revolute", link=link, position=[0.0, 0.0, 1.0], axis=axis)

    return dict(
        frame=1, gravity=[0.0, 0.0, -G], contacts={},
        joints={"l4_rx": joint("l4_rx", "l4_rx", [1, 0, 0]), "l4_ry": joint("l4_ry", "l4_ry", [0, 1, 0]),
                "l4_rz": joint("l4_rz", "l4", [0, 0, 1])},
        links=[dict(name="pelvis", parent=None, mass=10.0, com=[0, 0, 0.9]),
               dict(name="l4_rx", parent="pelvis", mass=0.0, com=[0, 0, 1]),
               dict(name="l4_ry", parent="l4_rx", mass=0.0, com=[0, 0, 1]),
               dict(name="l4", parent="l4_ry", mass=40.0, com=[0.0, -0.2, 1.3])],
        tcps={"hand": dict(position=[0.0, -0.4, 1.2], rotation=[1, 0, 0, 0], link="l4")},
        loads=[dict(tcp="hand", point=[0.0, -0.4, 1.2], force=[0.0, 0.0, -load_kg * G])],
    )  # fmt: skip


def test_l4_l5_moment_and_compression_by_hand() -> None:
    """M = g (40 kg * 0.2 m + 10 kg * 0.4 m) = 117.72 N*m; F = M / 0.05 m + g * 50 kg = 2844.9 N (Chaffin)."""
    assert disc_compression(100.0, 500.0) == pytest.approx(100.0 / 0.05 + 500.0)
    report = evaluate(result_from_dict({"frames": [tiny_trunk()]}), ErgoOptions())
    l45 = report["frames"][0]["joint_loads"]["l4_l5"]
    assert l45["flexion_moment"] == pytest.approx(G * (40 * 0.2 + 10 * 0.4))
    assert l45["moment"] == pytest.approx([G * 12.0, 0.0, 0.0])
    assert l45["axial_force"] == pytest.approx(G * 50.0)
    assert l45["compression"] == pytest.approx(G * 12.0 / 0.05 + G * 50.0)
    assert l45["level"] == "green"
    heavy = evaluate(result_from_dict({"frames": [tiny_trunk(60.0)]}), ErgoOptions())["frames"][0]
    assert heavy["joint_loads"]["l4_l5"]["compression"] > 6400 and heavy["joint_loads"]["l4_l5"]["level"] == "red"
    assert heavy["rula"]["score"] is None and "not a human" in heavy["rula"]["reason"]


# ---------------- NIOSH (Applications Manual, DHHS (NIOSH) Pub. 94-110) ----------------


def test_niosh_formula_example_and_ideal_lift() -> None:
    # the formula example of shared/reference/published_data.py: H 40, V 30, D 50 cm, A 0, FM .94, CM .95
    hand = 23 * (25 / 40) * (1 - 0.003 * 45) * (0.82 + 4.5 / 50) * 1.0 * 0.94 * 0.95
    assert niosh.rwl(40, 30, 50, 0, 0.94, 0.95) == pytest.approx(hand) == pytest.approx(10.10, abs=0.005)
    assert niosh.rwl(25, 75, 25, 0, 1.0, 1.0) == pytest.approx(23.0)  # the load constant
    assert niosh.rwl(70, 75, 25, 0, 1.0, 1.0) == 0.0  # H beyond 63 cm
    assert niosh.rwl(25, 75, 25, 140, 1.0, 1.0) == 0.0  # A beyond 135 deg


def test_niosh_manual_example_4_origin() -> None:
    """Example 4 (package inspection), origin, U.S. units: HM 1.0, VM .94 (V 22 in), DM .87 (D 37 in), AM 1.0,
    FM .88, CM .95 (fair, V < 30 in): worksheet RWL 34.9 lb from rounded multipliers, 34.8 lb at full precision;
    CM at the destination (V 59 in, fair) 1.0."""
    m = niosh.multipliers(8.0, 22.0, 37.0, 0.0, units="us")
    assert (round(m["HM"], 2), round(m["VM"], 2), round(m["DM"], 2), round(m["AM"], 2)) == (1.0, 0.94, 0.87, 1.0)
    assert niosh.coupling_multiplier("fair", 22 * 2.54) == 0.95
    assert niosh.coupling_multiplier("fair", 59 * 2.54) == 1.0
    assert round(niosh.rwl(8.0, 22.0, 37.0, 0.0, 0.88, 0.95, units="us"), 1) == 34.8
    assert round(51 * 1.0 * 0.94 * 0.87 * 1.0 * 0.88 * 0.95, 1) == 34.9


def test_niosh_frequency_multiplier_table_5() -> None:
    assert niosh.frequency_multiplier(1.0, "short", 40) == 0.94
    assert niosh.frequency_multiplier(0.1, "long", 40) == 0.85  # below 0.2 lifts/min counts as 0.2
    assert niosh.frequency_multiplier(2.4, "short", 40) == pytest.approx(0.91 - 0.4 * 0.03)  # interpolated
    assert niosh.frequency_multiplier(13, "short", 40) == 0.0 and niosh.frequency_multiplier(13, "short", 80) == 0.34
    assert niosh.frequency_multiplier(16, "short", 80) == 0.0


# ---------------- RULA and REBA ----------------


def test_rula_tables_published_extremes_and_grand_score_rule() -> None:
    assert rula.grand_score(rula.TABLE_A[0][0][0], rula.TABLE_B[0][0]) == 1  # best posture
    assert rula.grand_score(rula.TABLE_A[5][2][7] + 4, rula.TABLE_B[5][11] + 4) == 7  # worst
    # McAtamney & Corlett 1993: a grand score of 1 or 2 means scores C and D of 2 or less
    for c in range(1, 9):
        for d in range(1, 8):
            assert (rula.grand_score(c, d) <= 2) == (c <= 2 and d <= 2)
    assert [
        rula.force_score(kg, a, False)
        for kg, a in ((1, "static"), (5, "intermittent"), (5, "static"), (12, "intermittent"), (12, "repeated"))
    ] == [0, 1, 2, 2, 3]


def human_posture(trunk=0.0, neck=0.0, elevation=0.0, elbow=0.0, wrist=0.0, deviation=0.0, knee=0.0) -> dict:
    side = dict(upper_arm_elevation=elevation, upper_arm_flexion=elevation, upper_arm_abduction=0.0,
                shoulder_elevation=0.0, elbow_flexion=elbow, wrist_flexion=wrist, wrist_deviation=deviation,
                forearm_rotation=0.0, forearm_rotation_share=0.0, hand_lateral=0.1, shoulder_width_half=0.2,
                hand_above_shoulder=False, knee_flexion=knee, weight_share=0.5)  # fmt: skip
    return dict(trunk_flexion=trunk, trunk_side_bend=0.0, trunk_twist=0.0, head_tilt=trunk + neck, neck_flexion=neck,
                neck_side_bend=0.0, neck_twist=0.0, l=dict(side), r=dict(side), supported_feet=2)  # fmt: skip


def test_rula_published_worked_examples() -> None:
    """Two published solved RULA exercises.

    1. "EJERCICIO resuelto Metodo RULA" (https://deploy.studylib.es/doc/9445509/rula): cardboard piece of 250 g
       handled every 10 s, shoulder flexed 20-45 deg and not abducted, elbow flexed under 60 deg, wrist neutral,
       forearm mid-turn (2 2 1 1 -> table A 3); neck, trunk and legs 1 (table B 1); force 0, muscle use +1
       (repeated): "Puntuacion C = 3 + 0 + 1 = 4", "Puntuacion D = 1 + 0 + 1 = 2", grand score 3, action level 2.
    2. "Metodo Rula" worksheet (https://es.scribd.com/document/525897941/Metodo-Rula): arm 4, forearm 3, wrist 3,
       twist 1 -> A 5, C 6; neck 3, trunk 4, legs 2 -> B 6, D 7; final score 7.
    """
    p = human_posture(elevation=35, elbow=40)
    out = rula.rula(p, 0.25, ErgoOptions(activity="repeated"))
    right = out["right"]
    assert (right["upper_arm"], right["lower_arm"], right["wrist"], right["wrist_twist"]) == (2, 2, 1, 1)
    assert (right["score_a"], out["muscle_use"], out["force_load"], right["score_c"]) == (3, 1, 0, 4)
    assert (out["neck"], out["trunk"], out["legs"], out["score_b"], out["score_d"]) == (1, 1, 1, 1, 2)
    assert (out["score"], out["action_level"]) == (3, 2)
    # example 2 gives only the sums of muscle use and force (+1 on each side), so it checks the tables
    score_a, score_b = rula.TABLE_A[4 - 1][3 - 1][(3 - 1) * 2 + 1 - 1], rula.TABLE_B[3 - 1][(4 - 1) * 2 + 2 - 1]
    assert (score_a, score_b, rula.grand_score(score_a + 1, score_b + 1)) == (5, 6, 7)


def test_reba_published_solved_exercise() -> None:
    """ "Metodo REBA Ejemplos Reales", example 1 (https://es.scribd.com/document/587736423): neck 1, trunk 2
    (about 20 deg flexion), legs 2 (both feet down, knees 30-60 deg), load over 10 kg (+2), upper arm 2 (about
    20 deg, abducted), lower arm 1, wrist 1 -> final score 4, medium risk (table A 3 + 2 = 5, table B 1, C 4)."""
    p = human_posture(trunk=15, neck=10, elevation=15, elbow=80, knee=45)
    for side in ("l", "r"):
        p[side]["upper_arm_abduction"] = 30.0
    out = reba.reba(p, 12.0, ErgoOptions(coupling="good"))
    assert (out["neck"], out["trunk"], out["legs"], out["load"], out["score_a"]) == (1, 2, 2, 2, 5)
    right = out["right"]
    assert (right["upper_arm"], right["lower_arm"], right["wrist"], right["score_b"]) == (2, 1, 1, 1)
    assert (out["score"], out["risk"]) == (4, "medium")


def test_owas_action_categories() -> None:
    """The OWAS table: four categories, never lower for a heavier load, and the cells every compared copy of the
    published table shares (straight back standing = 1, squatting = 2, bent back with both arms up and a heavy load
    while squatting = 4)."""
    assert owas.action_category(1, 1, 2, 1) == 1 and owas.action_category(1, 1, 4, 1) == 2
    assert owas.action_category(2, 1, 4, 1) == 3 and owas.action_category(2, 3, 5, 3) == 4
    cells = [(b, a, lg) for b in range(1, 5) for a in range(1, 4) for lg in range(1, 8)]
    assert len(cells) * 3 == 252
    for b, a, lg in cells:
        by_load = [owas.action_category(b, a, lg, ld) for ld in (1, 2, 3)]
        assert by_load == sorted(by_load) and set(by_load) <= {1, 2, 3, 4}
    for code, other in owas.DISPUTED.items():
        assert owas.action_category(*map(int, code)) != other


def test_reba_example_neck2_trunk2_legs2_arm1_forearm2_wrist3() -> None:
    """The example of shared/reference/published_data.py (rs9000/ergonomics README, "Pose Left"): neck 2, trunk 2,
    legs 2, upper arm 1, lower arm 2, wrist 3 -> score A 4, score B 3, table C 4, REBA 4 ("Pose Right", wrist 2:
    B 2, C 4)."""
    assert reba.TABLE_A[2][2][1] == 4 and reba.TABLE_B[1][2][2] == 3 and reba.table_c(4, 3) == 4
    assert reba.TABLE_B[1][2][1] == 2 and reba.table_c(4, 2) == 4
    p = human_posture(trunk=10, neck=25, elevation=10, elbow=30, wrist=20, deviation=10, knee=45)
    out = reba.reba(p, 0.0, ErgoOptions(coupling="good"))
    assert (out["neck"], out["trunk"], out["legs"]) == (2, 2, 2)
    assert (out["right"]["upper_arm"], out["right"]["lower_arm"], out["right"]["wrist"]) == (1, 2, 3)
    assert (out["score_a"], out["right"]["score_b"], out["score"], out["risk"]) == (4, 3, 4, "medium")
    assert reba.reba(human_posture(elbow=80), 0.0, ErgoOptions(coupling="good"))["score"] == 1  # negligible
    heavy = reba.reba(human_posture(trunk=70, neck=30, elevation=100, elbow=120, wrist=30), 12.0,
                      ErgoOptions(coupling="poor", activity="static"))  # fmt: skip
    assert heavy["score"] >= 11 and heavy["risk"] == "very high"


def test_rula_and_reba_of_the_zero_pose(male) -> None:
    """Standing upright, arms hanging: RULA lower arm 2 (elbow straight), everything else 1 -> grand score 2;
    REBA 1 (negligible)."""
    frame = frame_from_dict(frame_dict(male, male.zero_pose()), "zero")
    p = measure(frame)
    for key in ("trunk_flexion", "trunk_side_bend", "trunk_twist", "neck_flexion", "head_tilt"):
        assert p[key] == pytest.approx(0.0, abs=1e-6)
    assert p["r"]["upper_arm_elevation"] == pytest.approx(0.0, abs=1e-6)
    assert p["r"]["elbow_flexion"] == pytest.approx(0.0, abs=1e-6)
    out = rula.rula(p, 0.0, ErgoOptions())
    assert (out["score"], out["right"]["upper_arm"], out["right"]["lower_arm"], out["trunk"]) == (2, 1, 2, 1)
    assert reba.reba(p, 0.0, ErgoOptions())["score"] == 1


def test_body_angles_on_known_poses(male) -> None:
    lean = measure(frame_from_dict(frame_dict(male, pose(male, root_rx=math.radians(30))), "lean"))
    assert lean["trunk_flexion"] == pytest.approx(30.0, abs=1e-6)  # whole body tipped forward 30 deg
    assert lean["neck_flexion"] == pytest.approx(0.0, abs=1e-6) and lean["head_tilt"] == pytest.approx(30.0)
    arm = measure(frame_from_dict(frame_dict(male, pose(male, shoulder_r_flexion=math.pi / 2,
                                                     elbow_l_flexion=math.pi / 2)), "arm"))  # fmt: skip
    assert arm["r"]["upper_arm_elevation"] == pytest.approx(90.0) and arm["r"]["upper_arm_flexion"] == pytest.approx(90)
    assert arm["l"]["elbow_flexion"] == pytest.approx(90.0)
    side = measure(frame_from_dict(frame_dict(male, pose(male, shoulder_l_abduction=math.radians(60))), "abd"))
    assert side["l"]["upper_arm_abduction"] == pytest.approx(60.0)
    assert side["l"]["upper_arm_flexion"] == pytest.approx(0.0, abs=1e-9)


def test_motion_lift_from_hanging_arms_to_shoulder_height(male, tmp_path: Path) -> None:
    """Three frames, 10 kg in the hands: arms hanging -> elbows 45 deg -> arms straight forward at shoulder height.

    By hand (Winter 2009 shares of H = 1.74 m): knuckles hang at 0.818 H - 0.186 H - 0.146 H - 0.45 * 0.108 H =
    0.4374 H = 76.1 cm above the floor, right above the ankles (H = 0, so HM = 1); at the end they are at shoulder
    height 0.818 H = 142.3 cm, (0.186 + 0.146 + 0.0486) H = 66.2 cm in front (beyond 63 cm: HM = 0).
    """
    hands = (("hand_l", (0.0, 0.0, -5 * G)), ("hand_r", (0.0, 0.0, -5 * G)))
    poses = [male.zero_pose(), pose(male, elbow_l_flexion=math.pi / 4, elbow_r_flexion=math.pi / 4),
             pose(male, shoulder_l_flexion=math.pi / 2, shoulder_r_flexion=math.pi / 2)]  # fmt: skip
    frames = []
    for k, theta in enumerate(poses):
        frames.append(frame_dict(male, theta, loads=hands) | {"frame": k + 1})
    result = tmp_path / "motion.json"
    result.write_text(json.dumps({"scenario": "presets/scenarios/box_lift.toml", "frames": frames}))
    report = run(result, tmp_path / "m_ergo.json", ErgoOptions(coupling="good", frequency=0.2))
    assert [Path(p).name for p in report["written"][2:]] == ["m_ergo_loads.png", "m_ergo_scores.png", "m_ergo_back.png"]
    lift = report["niosh"]
    h = 1.74
    assert lift["origin"]["frame"] == 1 and lift["destination"]["frame"] == 3 and lift["load_kg"] == pytest.approx(10)
    assert lift["origin"]["V"] == pytest.approx(100 * 0.4374 * h, abs=0.1)
    assert lift["origin"]["H"] == pytest.approx(0.0, abs=1e-6) and lift["origin"]["HM"] == 1.0
    assert lift["destination"]["V"] == pytest.approx(100 * 0.818 * h, abs=0.1)
    assert lift["destination"]["H"] == pytest.approx(100 * 0.3806 * h, abs=0.1) and lift["destination"]["RWL"] == 0
    assert lift["origin"]["D"] == pytest.approx(100 * (0.818 - 0.4374) * h, abs=0.1)
    assert lift["origin"]["RWL"] == pytest.approx(23 * (1 - 0.003 * abs(0.4374 * h * 100 - 75)) * (0.82 + 4.5 / 66.22),
                                                  rel=1e-3)  # fmt: skip
    assert [f["worksheet"]["shoulder_r"]["level"] for f in report["frames"]] == ["green", "green", "red"]
    assert [f["rula"]["right"]["upper_arm"] for f in report["frames"]] == [1, 1, 4]


# ---------------- the command ----------------


@pytest.fixture(scope="module")
def box_lift(tmp_path_factory) -> Path:
    """The box lift solved with the standard model (trunk 0): the stoop whose trunk bend (over 60 deg) the report's
    levels are checked against."""
    folder = tmp_path_factory.mktemp("ergo")
    out, scenario = folder / "box_lift.json", folder / "box_lift.toml"
    text = (Path(__file__).resolve().parents[3] / "presets/scenarios/box_lift.toml").read_text(encoding="utf-8")
    scenario.write_text(text + "\n[comfort]\ntrunk = 0.0\n", encoding="utf-8")
    proc = run_cli("solve", str(scenario), "-o", str(out), "-q")
    assert proc.returncode == 0, proc.stderr
    return out


def test_cli_ergo_writes_json_csv_and_plots(box_lift: Path, tmp_path: Path) -> None:
    out = tmp_path / "report" / "ergo.json"
    proc = run_cli("ergo", str(box_lift), "-o", str(out), "--frequency", "2", "--coupling", "good")
    assert proc.returncode == 0, proc.stderr
    for path in (
        out,
        out.with_suffix(".csv"),
        *(tmp_path / "report" / f"ergo_{k}.png" for k in ("loads", "scores", "back")),
    ):
        assert path.is_file() and path.stat().st_size > 0, path
    assert (tmp_path / "report" / "ergo_loads.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    report = json.loads(out.read_text())
    frame = report["frames"][0]
    result = json.loads(box_lift.read_text())["frames"][0]
    assert set(frame["joint_loads"]) == set(result["joints"]) | {"l4_l5"}
    for load in frame["joint_loads"].values():
        assert {"moment", "compression"} <= set(load) or {"moment", "axis_moment", "percent_strength"} <= set(load)
    # static balance: the whole body's moment about the exterior root is ~0 (the file's contacts hold it), within
    # the balance rows' tolerance of 0.1 N*m per axis
    assert np.linalg.norm(frame["joint_loads"]["root_tx"]["moment"]) < 0.1 * np.sqrt(3.0)
    assert 1000 < frame["joint_loads"]["l4_l5"]["compression"] < 6400
    assert 1 <= frame["rula"]["score"] <= 7 and 1 <= frame["reba"]["score"] <= 15 and len(frame["owas"]["code"]) == 4
    assert frame["owas"]["action_category"] == owas.action_category(*map(int, frame["owas"]["code"]))
    for item in ("back_bend", "neck", "shoulder_l", "hands_working_area", "l4_l5_compression", "joint_strength"):
        assert frame["worksheet"][item]["level"] in ("green", "yellow", "red") and frame["worksheet"][item]["threshold"]
    assert frame["worksheet"]["back_bend"]["level"] == "red"  # the box sits low: trunk bent beyond 60 deg
    assert frame["worksheet"]["hands_working_area"]["level"] == "red"  # below the knuckle height of the zero pose
    lift = report["niosh"]
    assert lift["load_kg"] == pytest.approx(10.0) and lift["origin"]["FM"] == 0.91 and lift["origin"]["CM"] == 1.0
    assert lift["LI"] == pytest.approx(10.0 / lift["RWL"])
    header = out.with_suffix(".csv").read_text().splitlines()[0].split(",")
    assert header[:5] == ["frame", "converged", "status", "rula", "reba"] and "pct_shoulder_r_flexion" in header


def test_cli_ergo_snake_has_loads_but_no_posture(tmp_path: Path) -> None:
    result = tmp_path / "snake.json"
    assert run_cli("solve", "presets/scenarios/snake_pose_a.toml", "-o", str(result), "-q").returncode == 0
    proc = run_cli("ergo", str(result), "-o", str(tmp_path / "e.json"), "--no-plots", "-q")
    assert proc.returncode == 0, proc.stderr
    frame = json.loads((tmp_path / "e.json").read_text())["frames"][0]
    assert frame["rula"]["score"] is None and frame["rula"]["reason"]
    assert frame["reba"]["score"] is None and frame["owas"]["code"] is None
    assert frame["joint_loads"]["l4_l5"]["compression"] is None and frame["joint_loads"]["l4_l5"]["reason"]
    assert frame["joint_loads"]["seg1_rx"]["percent_strength"] is not None
    assert frame["worksheet"]["back_bend"]["level"] is None and frame["worksheet"]["joint_strength"]["level"]


@pytest.mark.parametrize("content", [None, "{not json", '{"frames": []}', '{"result": 1}'])
def test_cli_ergo_bad_input_is_one_line_exit_2(tmp_path: Path, content: str | None) -> None:
    path = tmp_path / "bad.json"
    if content is not None:
        path.write_text(content)
    proc = run_cli("ergo", str(path), "-o", str(tmp_path / "out.json"))
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error:") and "bad.json" in lines[0]
    assert not (tmp_path / "out.json").exists()
