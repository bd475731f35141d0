"""The command line as a user runs it: ``python -m solver ...`` in a subprocess from the repository root.

The result file is checked from the JSON alone: balance, joint ranges, targets, contacts (push, friction, COP
inside the sole). Bad input exits 2 with one line naming the file; an unreachable target exits 3 and still
writes its best compromise.
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[3]
BOX_LIFT = REPO / "presets" / "scenarios" / "box_lift.toml"
FRAME_KEYS = {
    "frame",
    "converged",
    "iterations",
    "time_s",
    "joints",
    "tcps",
    "links",
    "contacts",
    "loads",
    "com",
    "gravity",
    "comfort",
    "residuals",
}

FEET = """\
[manikin]
preset = "male_50"

[[targets]]
tcp = "foot_r"
position = [-0.083, 0.0, 0.0]
lock = ["z", "rx", "ry"]
support = true

[[targets]]
tcp = "foot_l"
position = [0.083, 0.0, 0.0]
lock = ["z", "rx", "ry"]
support = true
"""


def run_cli(*args: str, cwd: Path = REPO, timeout: float = 120) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "solver", *args], cwd=cwd, capture_output=True, text=True, timeout=timeout
    )


def _no_constants(name: str):
    raise ValueError(f"non-finite JSON constant {name}")


def load_strict(path: Path) -> dict:
    """Parse JSON refusing NaN, Infinity and -Infinity."""
    return json.loads(path.read_text(encoding="utf-8"), parse_constant=_no_constants)


def _all_numbers_finite(value, where="") -> list[str]:
    if isinstance(value, bool) or value is None or isinstance(value, str):
        return []
    if isinstance(value, (int, float)):
        return [] if math.isfinite(value) else [where]
    if isinstance(value, dict):
        return [p for k, v in value.items() for p in _all_numbers_finite(v, f"{where}.{k}")]
    if isinstance(value, list):
        return [p for i, v in enumerate(value) for p in _all_numbers_finite(v, f"{where}[{i}]")]
    return [f"{where} (unexpected {type(value).__name__})"]


def quat_matrix(q) -> np.ndarray:
    """Rotation matrix of a unit quaternion (w, x, y, z)."""
    w, x, y, z = np.asarray(q, float) / np.linalg.norm(q)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def rotation_vector(r: np.ndarray) -> np.ndarray:
    """log of a rotation matrix as a rotation vector (rad); fine away from 180 degrees."""
    angle = math.acos(max(-1.0, min(1.0, (np.trace(r) - 1) / 2)))
    v = np.array([r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]])
    return v * (0.5 if angle < 1e-9 else angle / (2 * math.sin(angle)))


# --------------------------------------------------------------------------------------------- box lift


@pytest.fixture(scope="module")
def box_lift_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("cli") / "tmp" / "result.json"
    proc = run_cli("solve", "presets/scenarios/box_lift.toml", "-o", str(out))
    return proc, out


def test_box_lift_exit_summary_and_file(box_lift_run):
    proc, out = box_lift_run
    assert proc.returncode == 0, proc.stderr
    assert "Traceback" not in proc.stderr
    assert "converged" in proc.stdout and "hand_r" in proc.stdout and "contact" in proc.stdout
    assert out.is_file()
    data = load_strict(out)
    assert isinstance(data["frames"], list) and len(data["frames"]) == 1
    assert not _all_numbers_finite(data), _all_numbers_finite(data)


def test_box_lift_frame_layout(box_lift_run):
    _, out = box_lift_run
    frame = load_strict(out)["frames"][0]
    assert FRAME_KEYS <= set(frame), FRAME_KEYS - set(frame)
    assert frame["converged"] is True and frame["unmet"] == []
    assert isinstance(frame["iterations"], int) and frame["iterations"] > 0
    assert frame["time_s"] > 0
    assert len(frame["joints"]) > 100
    for name, joint in frame["joints"].items():
        assert {"value", "min", "max", "link", "position", "axis"} <= set(joint), name
        assert len(joint["position"]) == 3 and len(joint["axis"]) == 3
        assert np.linalg.norm(joint["axis"]) == pytest.approx(1.0, abs=1e-9), name
    for name, tcp in frame["tcps"].items():
        assert {"position", "rotation", "link"} <= set(tcp), name
        assert len(tcp["position"]) == 3 and len(tcp["rotation"]) == 4
        assert np.linalg.norm(tcp["rotation"]) == pytest.approx(1.0, abs=1e-9), name
    link_names = {link["name"] for link in frame["links"]}
    for link in frame["links"]:
        assert {"name", "parent", "mass", "com"} <= set(link)
        assert link["parent"] is None or link["parent"] in link_names
        assert link["mass"] >= 0 and len(link["com"]) == 3
    assert {j["link"] for j in frame["joints"].values()} <= link_names
    assert {t["link"] for t in frame["tcps"].values()} <= link_names
    assert set(frame["contacts"]) == {"foot_r", "foot_l"}
    for contact in frame["contacts"].values():
        assert {"point", "force", "moment"} <= set(contact)
    assert [ld["tcp"] for ld in frame["loads"]] == ["hand_r", "hand_l"]
    for load in frame["loads"]:
        assert {"tcp", "point", "force"} <= set(load)
    assert frame["gravity"] == pytest.approx([0.0, 0.0, -9.81])
    assert math.isfinite(frame["comfort"])
    assert all(math.isfinite(v) for v in frame["residuals"].values())
    total_mass = sum(link["mass"] for link in frame["links"])
    com = sum(np.multiply(link["mass"], link["com"]) for link in frame["links"]) / total_mass
    np.testing.assert_allclose(frame["com"], com, atol=1e-6)


def test_box_lift_balance_from_json_alone(box_lift_run):
    _, out = box_lift_run
    frame = load_strict(out)["frames"][0]
    g = np.asarray(frame["gravity"], float)
    force = np.zeros(3)
    moment = np.zeros(3)
    for link in frame["links"]:
        weight = link["mass"] * g
        force += weight
        moment += np.cross(link["com"], weight)
    for contact in frame["contacts"].values():
        force += contact["force"]
        moment += np.cross(contact["point"], contact["force"]) + np.asarray(contact["moment"])
    for load in frame["loads"]:
        force += load["force"]
        moment += np.cross(load["point"], load["force"])
    assert np.linalg.norm(force) <= 1.0, f"total force {force} N"
    assert np.linalg.norm(moment) <= 0.1, f"total moment about the origin {moment} N*m"
    # the loads are the box's 2 x 5 kg at the hands
    for load in frame["loads"]:
        np.testing.assert_allclose(load["force"], [0.0, 0.0, -49.05], atol=1e-9)
        np.testing.assert_allclose(load["point"], frame["tcps"][load["tcp"]]["position"], atol=1e-9)


def test_box_lift_joint_ranges_from_json(box_lift_run):
    _, out = box_lift_run
    frame = load_strict(out)["frames"][0]
    outside = []
    for name, joint in frame["joints"].items():
        lo = -math.inf if joint["min"] is None else joint["min"]
        hi = math.inf if joint["max"] is None else joint["max"]
        if not lo - 1e-9 <= joint["value"] <= hi + 1e-9:
            outside.append(f"{name}={joint['value']} not in [{lo}, {hi}]")
    assert not outside, outside


def test_box_lift_targets_from_json(box_lift_run):
    _, out = box_lift_run
    frame = load_strict(out)["frames"][0]
    scenario = tomllib.loads(BOX_LIFT.read_text(encoding="utf-8"))
    for target in scenario["targets"]:
        if not target["tcp"].startswith("hand"):
            continue
        tcp = frame["tcps"][target["tcp"]]
        r_target = quat_matrix(target["rotation"])
        local = r_target.T @ (np.asarray(tcp["position"]) - np.asarray(target["position"]))
        turn = rotation_vector(r_target.T @ quat_matrix(tcp["rotation"]))
        errors = dict(zip(("x", "y", "z", "rx", "ry", "rz"), [*local, *turn], strict=True))
        for axis in target["lock"]:
            tol = 1e-3 if axis in ("x", "y", "z") else math.radians(0.2)
            assert abs(errors[axis]) <= tol * (1 + 1e-6), f"{target['tcp']}.{axis} off by {errors[axis]}"


def test_box_lift_contacts_from_json(box_lift_run):
    from solver.io.scenario.bodies import load_body

    _, out = box_lift_run
    frame = load_strict(out)["frames"][0]
    scenario = tomllib.loads(BOX_LIFT.read_text(encoding="utf-8"))
    friction = {t["tcp"]: t.get("friction", 0.6) for t in scenario["targets"] if t.get("support")}
    model = load_body(preset="male_50")
    assert set(frame["contacts"]) == set(friction)
    for name, contact in frame["contacts"].items():
        f = np.asarray(contact["force"], float)
        assert f[2] > 0.0, f"{name}: the floor pulls ({f} N)"
        assert math.hypot(f[0], f[1]) <= friction[name] * f[2] * (1 + 1e-6), f"{name}: outside the friction cone"
        sole = np.asarray(model.tcps[name].sole, float)
        half_x, half_y = np.abs(sole[:, 0]).max(), np.abs(sole[:, 1]).max()
        tcp = frame["tcps"][name]
        local = quat_matrix(tcp["rotation"]).T @ (np.asarray(contact["point"]) - np.asarray(tcp["position"]))
        assert abs(local[0]) <= half_x + 1e-6 and abs(local[1]) <= half_y + 1e-6, (
            f"{name}: COP {local[:2]} outside the sole +-[{half_x}, {half_y}]"
        )
        assert abs(local[2]) <= 1e-3, f"{name}: COP {local[2]} m off the sole plane"


# --------------------------------------------------------------------------------------------- bad input

HAND = '\n[[targets]]\ntcp = "hand_r"\nposition = [-0.2, -0.3, 1.2]\nlock = ["x", "y", "z"]\n'

BAD_INPUTS = {
    # case: (file text or None for a missing file, words the message must contain)
    "malformed_toml": ("[manikin\npreset = 'male_50'\n", ["malformed TOML"]),
    "empty_file": ("", ["empty"]),
    "whitespace_only": ("\n  \n", ["empty"]),
    "unknown_tcp": (FEET + HAND.replace("hand_r", "hand_x"), ["tcp", "hand_x"]),
    "nan_position": (FEET + HAND.replace("[-0.2, -0.3, 1.2]", "[nan, 0, 0]"), ["position", "finite"]),
    "inf_position": (FEET + HAND.replace("[-0.2, -0.3, 1.2]", "[inf, 0, 0]"), ["position", "finite"]),
    "position_two_numbers": (FEET + HAND.replace("[-0.2, -0.3, 1.2]", "[0.1, 0.2]"), ["position", "3"]),
    "unknown_preset": (FEET.replace("male_50", "male_51"), ["preset", "male_51"]),
    "unknown_top_level_key": ("colour = 'red'\n" + FEET, ["colour", "unknown"]),
    "unknown_lock_axis": (FEET + HAND.replace('["x", "y", "z"]', '["x", "q"]'), ["lock", "q"]),
    "missing_file": (None, ["not found"]),
    "balance_without_support": (
        '[manikin]\npreset = "male_50"\n[solver]\nbalance = true\n' + HAND,
        ["support", "balance"],
    ),
    "negative_load_mass": (FEET + HAND + '\n[[loads]]\ntcp = "hand_r"\nmass = -5.0\n', ["mass", "-5"]),
    "zero_quaternion": (FEET + HAND + "rotation = [0, 0, 0, 0]\n", ["rotation"]),
    "non_numeric_sole": (FEET + HAND + 'support = true\nsole = [[0.1, 0.1], [0.1, "a"]]\n', ["sole"]),
}


def _check_bad_input(proc: subprocess.CompletedProcess, scenario: Path, words: list[str]) -> None:
    assert proc.returncode == 2, f"exit {proc.returncode}, stderr:\n{proc.stderr}"
    assert "Traceback" not in proc.stderr, proc.stderr
    lines = proc.stderr.strip("\n").splitlines()
    assert len(lines) == 1, f"expected one line on stderr, got {len(lines)}:\n{proc.stderr}"
    line = lines[0]
    assert str(scenario) in line or scenario.name in line, f"the message does not name the file: {line}"
    for word in words:
        assert word.lower() in line.lower(), f"the message does not say {word!r}: {line}"


@pytest.mark.parametrize("case", sorted(BAD_INPUTS))
def test_bad_input_exits_2_with_one_line(tmp_path, case):
    text, words = BAD_INPUTS[case]
    scenario = tmp_path / f"{case}.toml"
    if text is not None:
        scenario.write_text(text, encoding="utf-8")
    out = tmp_path / "result.json"
    out.write_text("keep me", encoding="utf-8")
    proc = run_cli("solve", str(scenario), "-o", str(out))
    _check_bad_input(proc, scenario, words)
    assert out.read_text(encoding="utf-8") == "keep me", "a bad input clobbered the existing output file"
    stray = {p.name for p in tmp_path.iterdir()} - {scenario.name, out.name}
    assert not stray, f"stray files left next to the output: {stray}"


# --------------------------------------------------------------------------------------------- good input elsewhere


def test_scenario_in_another_directory_solves(tmp_path):
    scenario = tmp_path / "stand.toml"
    scenario.write_text(FEET, encoding="utf-8")
    out = tmp_path / "deep" / "er" / "stand.json"
    proc = run_cli("solve", str(scenario), "-o", str(out))
    assert proc.returncode == 0, proc.stdout + proc.stderr
    frame = load_strict(out)["frames"][0]
    assert frame["converged"] is True
    assert not list(out.parent.glob("*.tmp")), "temporary file left behind"


def test_solves_from_another_working_directory(tmp_path):
    """``preset = "male_50"`` is found from any working directory (relative scenario and output paths)."""
    (tmp_path / "stand.toml").write_text(FEET, encoding="utf-8")
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(REPO), env.get("PYTHONPATH")]))
    proc = subprocess.run(
        [sys.executable, "-m", "solver", "solve", "stand.toml", "-o", "out/stand.json"],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert load_strict(tmp_path / "out" / "stand.json")["frames"][0]["converged"] is True


# --------------------------------------------------------------------------------------------- unreachable


def test_unreachable_target_exits_3_and_writes_json(tmp_path):
    scenario = tmp_path / "unreachable.toml"
    # feet held on all six axes: with sliding feet (z, rx, ry) the manikin could walk to the target
    fixed_feet = FEET.replace('["z", "rx", "ry"]', '["x", "y", "z", "rx", "ry", "rz"]')
    scenario.write_text(fixed_feet + HAND.replace("[-0.2, -0.3, 1.2]", "[0.0, -3.0, 1.0]"), encoding="utf-8")
    out = tmp_path / "unreachable.json"
    proc = run_cli("solve", str(scenario), "-o", str(out))
    assert proc.returncode == 3, f"exit {proc.returncode}\n{proc.stdout}\n{proc.stderr}"
    assert "Traceback" not in proc.stderr
    assert "NOT converged" in proc.stdout
    data = load_strict(out)
    assert not _all_numbers_finite(data), _all_numbers_finite(data)
    frame = data["frames"][0]
    assert frame["converged"] is False
    assert "hand_r" in frame["unmet"], frame["unmet"]
    # the best compromise still keeps every joint in its range
    for name, joint in frame["joints"].items():
        lo = -math.inf if joint["min"] is None else joint["min"]
        hi = math.inf if joint["max"] is None else joint["max"]
        assert lo - 1e-9 <= joint["value"] <= hi + 1e-9, name


def test_hand_target_below_the_floor_exits_3_with_the_body_standing(tmp_path):
    """Issue 20: a hand target 1 m below the floor once "converged" with the manikin upside down, its head at
    z = -0.53 m. With the floor (on by default) the solve exits 3 with the hand short, the feet and balance held,
    the pelvis and head well above the floor and no body part in it (recomputed from the result JSON alone). The
    standard model (trunk 0), which stoops: the behaviour model squats as low as it goes (pelvis at 0.22 m)."""
    from collision_check import result_problems

    scenario = tmp_path / "below.toml"
    scenario.write_text(FEET + HAND.replace("[-0.2, -0.3, 1.2]", "[-0.2, -0.4, -1.0]") + "\n[comfort]\ntrunk = 0.0\n",
                        encoding="utf-8")  # fmt: skip
    out = tmp_path / "below.json"
    proc = run_cli("solve", str(scenario), "-o", str(out))
    assert proc.returncode == 3, f"exit {proc.returncode}\n{proc.stdout}\n{proc.stderr}"
    assert "NOT converged" in proc.stdout and "Traceback" not in proc.stderr
    data = load_strict(out)
    frame = data["frames"][0]
    assert frame["unmet"] == ["hand_r"] and frame["broken"] == []
    assert frame["shortfall"]["hand_r"]["position_m"] > 1.0
    assert frame["tcps"]["pelvis"]["position"][2] > 0.5
    head = next(s for s in frame["collision_shapes"] if s["link"] == "head")
    assert min(head["start"][2], head["end"][2]) - head["radius"] > 0.3
    assert result_problems(data, scenario) == []


@pytest.mark.parametrize(
    "extra",
    [
        HAND.replace("[-0.2, -0.3, 1.2]", "[1e308, 0.0, 1.0]"),
        HAND + '\n[[loads]]\ntcp = "hand_r"\nforce = [0.0, 0.0, 1e300]\n',
    ],
    ids=["target_1e308_m_away", "load_1e300_N"],
)
def test_extreme_finite_values_never_give_nan_or_inf(tmp_path, extra):
    """Results are never NaN or inf: absurd (but finite) values are refused (exit 2) or solved finitely."""
    scenario = tmp_path / "extreme.toml"
    scenario.write_text(FEET + extra, encoding="utf-8")
    out = tmp_path / "extreme.json"
    proc = run_cli("solve", "-q", str(scenario), "-o", str(out))
    assert "Traceback" not in proc.stderr, proc.stderr
    if proc.returncode == 2:
        _check_bad_input(proc, scenario, [])
        return
    assert proc.returncode == 3, f"exit {proc.returncode}\n{proc.stderr}"
    data = json.loads(out.read_text(encoding="utf-8"))
    bad = _all_numbers_finite(data)
    assert not bad, f"non-finite values in the result file: {bad}"


# --------------------------------------------------------------------------------------------- presets


def test_presets_lists_manikins_and_scenarios():
    proc = run_cli("presets")
    assert proc.returncode == 0, proc.stderr
    assert "male_50" in proc.stdout
    assert "box_lift.toml" in proc.stdout


def test_a_reader_that_stops_early_ends_the_output_quietly():
    """``solve ... -o - | head -c 100`` (a motion: megabytes of JSON): the output stops at the closed pipe, no error
    line, exit 141."""
    command = [sys.executable, "-m", "solver", "solve", "presets/scenarios/box_lift_motion.toml", "-o", "-"]
    solve = subprocess.Popen(command, cwd=REPO, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    assert solve.stdout is not None and solve.stdout.read(100)
    solve.stdout.close()  # as head does once it has its bytes
    _, err = solve.communicate(timeout=120)
    assert solve.returncode == 141 and err == b""
