"""The Blender extension as a user meets it: the built zip installed into a throwaway user directory and driven
through its operators (tests/blender/session.py, run once in a subprocess so bpy never enters this process).
The assertions recompute everything from the solver: poses by forward kinematics, balance from the forces.
"""

from __future__ import annotations

import re
import zipfile
from pathlib import Path

import numpy as np
import pytest
from environments import run_python

from blender_manikin.rigging.bones import RigLayout
from blender_manikin.rigging.skin import twist_bones
from solver import Problem, load_scenario
from solver.body.model import GRAVITY
from solver.ergonomics.registry import frame_scores
from solver.io.scenario.bodies import load_body

ROOT = Path(__file__).resolve().parents[2]
MM = 1e-3
FLOAT32 = 2e-5  # Blender stores matrices and channels in single precision


@pytest.fixture(scope="module")
def model():
    return load_body(preset="male_50")


@pytest.fixture(scope="module")
def session(tmp_path_factory, run_session) -> dict:
    return run_session(tmp_path_factory.mktemp("blender"), "session.py")


def _frames(pose: dict, key: str) -> dict[str, np.ndarray]:
    return {name: np.array(m) for name, m in pose[key].items()}


def test_zip_ships_the_extension_its_wheels_and_nothing_else(session: dict) -> None:
    names = zipfile.ZipFile(session["zip"]).namelist()
    for needed in ("__init__.py", "blender_manifest.toml", "blender_manikin/pose/operators.py",
                   "solver/iteration/phases.py", "presets/manikins/male_50.toml", "presets/scenarios/box_lift.toml",
                   "LICENSE"):  # fmt: skip
        assert needed in names
    wheels = [n.removeprefix("wheels/") for n in names if n.startswith("wheels/")]
    assert {w.split("-")[0] for w in wheels} >= {"scipy", "matplotlib", "pillow", "kiwisolver", "contourpy"}
    tags = [w.removesuffix(".whl").split("-")[-1] for w in wheels]
    assert all(tag == "any" or ("linux" in tag and tag.endswith("x86_64")) for tag in tags), tags  # this platform
    for name in names:  # no tests, docs, developer tools or benchmarks (the rule: tests/test_shipped_files.py)
        assert not name.startswith(("tests/", "docs/", "dist/", "out/", ".", "blender_manikin/dev/", "bench/"))
        assert "__pycache__" not in name and name not in ("pyproject.toml", "requirements.txt", "README.md")


def test_dependencies_come_from_the_extension_wheels(session: dict) -> None:
    """The solver's scipy and the pictures' matplotlib load from the extension's wheels, not from the environment
    (what enabling loads: test_flow.py)."""
    user = str(Path(session["work"]) / "user")
    assert session["modules"]["scipy"].startswith(user) and session["modules"]["matplotlib"].startswith(user)


def test_add_manikin_builds_rig_body_tcps_and_supports(session: dict, model) -> None:
    assert session["module"] == "bl_ext.user_default.manikin"
    layout = RigLayout(model)
    arm = session["armature"]
    assert arm["preset"] == "male_50" and arm["bones"] == len(layout.bones) + len(twist_bones(layout))  # + helpers
    feet = {"target.foot_l", "target.foot_r"}  # the supports ride on the armature object (it carries its targets)
    assert set(arm["objects"]) == {"male_50.body"} | {f"tcp.{t}" for t in model.tcps} | feet
    for bone in layout.bones:
        rest, length, parent = session["rest"][bone.name]
        np.testing.assert_allclose(np.array(rest), bone.matrix(), atol=FLOAT32)
        assert length == pytest.approx(bone.length, abs=FLOAT32)
        assert parent == (layout.bones[bone.parent].name if bone.parent >= 0 else None)
    assert session["rest"]["pelvis"][2] is None  # the exterior root is the root bone
    for support in session["supports"].values():
        assert support["support"] and support["rig"] == "male_50"
        assert support["lock"] == [True] * 6  # planted (Feet = May slide frees x, y, rz at solve time)


def test_solve_meets_the_moved_hand_target(session: dict) -> None:
    before = _frames(session["before"], "tcps")["hand_r"][:3, 3]
    target = np.array(session["target"])[:3, 3]
    np.testing.assert_allclose(target, before + [0.0, -0.3, 0.0], atol=1e-6)
    assert session["solve"] == ["FINISHED"] and session["result"]["converged"]
    words = session["result"]["scores"]  # the sidebar's ergonomics of this pose (issue 6): each score's words
    assert len(words) == len(frame_scores())  # the motion score (NIOSH) says nothing of one pose
    assert re.fullmatch(r"RULA \d", words[0]) and re.fullmatch(r"REBA \d+", words[1]), words
    assert re.fullmatch(r"OWAS \d{4}", words[2]), words
    assert re.fullmatch(r"L4/L5 \d+ N, worksheet (green|yellow|red)", words[3]), words
    assert all(w in session["sidebar"] for w in words)  # the Result panel draws them
    colors = session["bone_colors"]  # bones coloured by load percent
    assert any(palette == "CUSTOM" for palette, _ in colors.values())
    name, _, worst = session["result"]["joint_loads"][0]
    expected = (0.2, 0.75, 0.3) if worst <= 30 else ((0.95, 0.8, 0.15) if worst <= 60 else (0.9, 0.2, 0.15))
    custom = [rgb for palette, rgb in colors.values() if palette == "CUSTOM"]
    assert any(np.allclose(rgb, expected, atol=0.01) for rgb in custom)  # colours are stored with 8 bits
    hand = _frames(session["after"], "tcps")["hand_r"]
    assert np.linalg.norm(hand[:3, 3] - target) < MM


def test_armature_pose_equals_the_solver_pose(session: dict, model) -> None:
    after = session["after"]
    x = np.array(after["x"])
    assert len(x) > model.n and session["x_is_finite"]
    kin = model.forward(x[: model.n])
    layout = RigLayout(model)
    bones = _frames(after, "bones")
    for bone, expected in zip(layout.bones, layout.bone_matrices(kin), strict=True):
        np.testing.assert_allclose(bones[bone.name], expected, atol=FLOAT32 * 10, err_msg=bone.name)
    for name, frame in _frames(after, "tcps").items():
        rot, pos = kin.tcp_frame(model.tcp(name))
        np.testing.assert_allclose(frame[:3, 3], pos, atol=FLOAT32 * 10, err_msg=name)
        np.testing.assert_allclose(frame[:3, :3], rot, atol=FLOAT32 * 10, err_msg=name)
    loc, euler = layout.channel_values(x[: model.n])
    for b, bone in enumerate(layout.bones):  # each joint value is one bone channel
        mode, rot, location = after["channels"][bone.name]
        assert mode == bone.rotation_mode
        np.testing.assert_allclose(rot, euler[b], atol=FLOAT32)
        np.testing.assert_allclose(location, loc[b], atol=FLOAT32)


def _inside(point: np.ndarray, polygon: np.ndarray) -> bool:
    edges = np.roll(polygon, -1, axis=0) - polygon
    to_point = point[None, :2] - polygon
    return bool(np.all(edges[:, 0] * to_point[:, 1] - edges[:, 1] * to_point[:, 0] >= 0))


def test_feet_stay_on_the_floor_and_balance_holds(session: dict, model) -> None:
    tcps = _frames(session["after"], "tcps")
    for foot in ("foot_l", "foot_r"):
        assert abs(tcps[foot][2, 3]) < MM
        assert np.degrees(np.arccos(np.clip(tcps[foot][2, 2], -1, 1))) < 0.2  # sole flat: its z axis up
    result = session["result"]
    total = np.sum([c["force"] for c in result["contacts"]], axis=0)
    np.testing.assert_allclose(total, -model.total_mass * GRAVITY, atol=1.0)  # the floor carries the body
    assert _inside(np.array(result["com"]), np.array(result["support_polygon"]))


def test_undo_restores_the_previous_pose(session: dict) -> None:
    assert session["undo_flag"]
    before, undone = _frames(session["before"], "bones"), _frames(session["undone"], "bones")
    after = _frames(session["after"], "bones")
    assert max(np.abs(after[n] - before[n]).max() for n in before) > 0.1  # the solve did move the manikin
    for name in before:
        np.testing.assert_allclose(undone[name], before[name], atol=1e-6, err_msg=name)
    np.testing.assert_allclose(session["undone_target"], session["target"], atol=1e-6)  # the moved target stays


def test_errors_reach_the_user_as_reports(session: dict) -> None:
    assert "unknown TCP 'hand_x'" in session["bad_tcp"]
    assert "body file not found" in session["bad_preset"]
    assert "Traceback" not in session["log"]


def test_live_mode_resolves_once_and_settles(session: dict) -> None:
    assert session["live_armed"]  # the handler armed the timer
    hand = _frames(session["live"], "tcps")["hand_r"][:3, 3]
    assert np.linalg.norm(hand - np.array(session["live_target"])[:3, 3]) < MM
    assert session["live_quiet"]  # writing the pose did not trigger another solve
    assert session["live_timer_on_edit"] and "unknown TCP 'hand_x'" in session["live_error"]
    assert session["live_error_cleared"]
    # The loop holds the left hand at its offset from the right hand, as it was when the loop was added.
    before = {k: np.array(v) for k, v in session["loop_before"].items()}
    tcps = _frames(session["live"], "tcps")
    offset_before = np.linalg.solve(before["hand_r"], before["hand_l"])[:3, 3]
    offset_after = np.linalg.solve(tcps["hand_r"], tcps["hand_l"])[:3, 3]
    assert np.linalg.norm(offset_after - offset_before) < MM


def test_scenario_export_and_import(session: dict) -> None:
    assert session["export"] == ["FINISHED"]
    exported = load_scenario(Path(session["work"]) / "exported.toml")
    assert sorted(t.tcp for t in exported.problem.all_targets) == ["foot_l", "foot_r", "hand_r"]
    assert [(lp.tcp, lp.other) for lp in exported.problem.loops] == [("hand_l", "hand_r")]
    assert exported.options.restarts == 2
    hand = next(t for t in exported.problem.all_targets if t.tcp == "hand_r")
    np.testing.assert_allclose(hand.position, np.array(session["live_target"])[:3, 3], atol=1e-6)
    assert session["import"] == ["FINISHED"] and session["import_solve"] == ["FINISHED"]
    members = session["imported"]["members"]
    assert sum(m.startswith("target.") for m in members) == 4 and sum(m.startswith("load.") for m in members) == 2
    assert session["import_result"]["converged"]
    box = load_scenario(ROOT / "presets" / "scenarios" / "box_lift.toml")
    hand = _frames(session["import_pose"], "tcps")["hand_r"][:3, 3]
    target = next(t for t in box.problem.all_targets if t.tcp == "hand_r")
    assert np.linalg.norm(hand - target.position) < MM
    assert session["reduced_solve"] == ["FINISHED"] and session["reduced_result"]["converged"]  # spine as groups


def test_most_loaded_joints(session: dict, model) -> None:
    """The sidebar's joint loads are the solver's statics at the shown pose, ranked by percent of strength."""
    loads = session["import_result"]["joint_loads"]
    assert len(loads) == 5 and all(0 < percent for _, _, percent in loads)
    assert [p for _, _, p in loads] == sorted((p for _, _, p in loads), reverse=True)
    box = load_scenario(ROOT / "presets" / "scenarios" / "box_lift.toml").problem
    in_scene_order = sorted(box.all_targets, key=lambda t: t.tcp)  # the empties' name order sets the force order
    problem = Problem(model, in_scene_order, box.loops, box.load_specs, box.balance, box.comfort.weights)
    tau = problem.state_of_x(np.array(session["import_pose"]["x"])).statics.axis_loads()
    for name, value, _ in loads:
        assert value == pytest.approx(tau[model.joint_index(name)], rel=1e-3, abs=1e-3)


def test_overlay_geometry(session: dict) -> None:
    counts = session["overlay"]
    assert counts["com"] == 14 and counts["polygon"] >= 6 and counts["contact"] == 12


def test_disable_leaves_nothing_registered(session: dict) -> None:
    there, ours = session["registered"], session["ours"]  # before disabling, all of it was there
    assert there["classes"] == ours["classes"] and len(ours["classes"]) >= 37
    assert sorted(there["types"]) == ours["types"]  # every operator, panel, menu and list is in bpy.types
    assert there["object_props"] == ["manikin", "manikin_obstacle", "manikin_retarget", "manikin_target"]
    assert len(there["handlers"]) == 1 and there["timers"] and there["enabled"]
    features = [name.rpartition(".blender_manikin.")[2] for name in there["menus"]]  # one entry each, per menu
    assert sorted(features) == ours["menus"] and {"pose.panels", "scenario.operators"} <= set(features)
    left = session["left"]
    assert left == dict(types=[], classes=[], object_props=[], handlers=[], timers=False, menus=[], enabled=False)


def test_sidebar_draws(session: dict) -> None:
    lines = session["sidebar"]
    assert any(line.startswith("Converged") for line in lines)
    assert "Residuals" in lines and "Most loaded joints (% of strength)" in lines
    assert any(line.startswith("= 0.00 kg") for line in lines)  # the load panel


# python -m blender_manikin.dev.snapshot ARGS, its build() giving this run's zip (copied into the folder build() was
# given): the zips are built and checked once, by the extension_zip fixture (building them again took ~4 s).
SNAPSHOT = """
import shutil, sys
from pathlib import Path
from blender_manikin.dev import snapshot
snapshot.build = lambda out: {snapshot.this_platform(): Path(shutil.copy(sys.argv[1], out))}
sys.exit(snapshot.main(sys.argv[2:]))
"""


def test_headless_render(tmp_path: Path, blender_python: Path, extension_zip: Path, monkeypatch) -> None:
    """The snapshot script renders the solved box lift; the manikin's skin shows where the camera looks; its build
    and user folders (about 450 MB) are gone afterwards."""
    import matplotlib.image

    png = tmp_path / "manikin.png"
    (tmp_path / "tmp").mkdir()
    monkeypatch.setenv("TMPDIR", str(tmp_path / "tmp"))
    args = ["-c", SNAPSHOT, extension_zip, "-o", png, "--size", 96, "--samples", 2]
    done = run_python(blender_python, args, tmp_path / "user")
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    assert list((tmp_path / "tmp").glob("manikin-*")) == []
    image = matplotlib.image.imread(png)[:, :, :3]
    skin = (image[:, :, 0] - image[:, :, 2]) > 0.03  # reddish: the body; floor and sky are grey-blue
    assert image.shape[:2] == (96, 96) and 0.03 < skin.mean() < 0.5
    assert skin[20:80, 20:70].mean() > 3 * skin[:, 80:].mean()  # the manikin stands in the middle


def test_turned_manikin_away_from_the_origin(session: dict) -> None:
    turned = session["turned"]
    assert session["turned_solve"] == ["FINISHED"] and turned["result"]["converged"]
    matrix = np.array(turned["matrix"])
    np.testing.assert_allclose(matrix[:3, 3], [1.5, 0.5, 0.0], atol=1e-6)
    tcps = _frames(turned["pose"], "tcps")
    assert np.linalg.norm(tcps["hand_l"][:3, 3] - np.array(turned["target"])[:3, 3]) < MM
    for foot in ("foot_l", "foot_r"):
        assert abs(tcps[foot][2, 3]) < MM
    assert [ld["tcp"] for ld in turned["result"]["loads"]] == ["hand_l"]
    np.testing.assert_allclose(turned["result"]["loads"][0]["force"], [0.0, 0.0, -2.0 * 9.81], atol=1e-4)
