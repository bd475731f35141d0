"""Motions: keyed targets, interpolation, warm-started frames, the per-frame change bound, the CLI."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from solver import load_scenario
from solver.body.spatial import exp_so3, log_so3
from solver.iteration import solve
from solver.motion.frames import MotionLimits, solve_frames
from solver.problem.tracks import Key, Track

ROOT = Path(__file__).resolve().parents[3]
SNAKE_MOTION = ROOT / "presets" / "scenarios" / "snake_motion.toml"


def test_track_interpolates_and_holds_its_ends():
    r0, r1 = np.eye(3), exp_so3([0.0, 0.0, np.pi / 2])
    track = Track(0, (Key(10, np.zeros(3), r0), Key(20, np.array([1.0, 2.0, 3.0]), r1)))
    np.testing.assert_allclose(track.pose_at(0)[0], 0.0)
    np.testing.assert_allclose(track.pose_at(25)[0], [1, 2, 3])
    position, rotation = track.pose_at(15)
    np.testing.assert_allclose(position, [0.5, 1.0, 1.5])
    np.testing.assert_allclose(log_so3(rotation), [0.0, 0.0, np.pi / 4], atol=1e-9)


def test_scenario_frames_come_from_motion_table():
    sc = load_scenario(SNAKE_MOTION)
    assert sc.frames == list(range(1, 49))
    assert len(sc.tracks) == 1
    top_start = sc.problem_at(1).targets[1].position
    top_end = sc.problem_at(48).targets[1].position
    np.testing.assert_allclose(top_start, [0.45, 0.0, 1.25])
    np.testing.assert_allclose(top_end, [0.0, -0.35, 0.9])


def test_snake_motion_converges_smoothly():
    sc = load_scenario(SNAKE_MOTION)
    frames = sc.frames[::4]
    limits = MotionLimits(max_joint_change=0.35, max_root_shift=0.1)
    results = list(solve_frames(sc.problem_at, frames, sc.start, sc.options, limits))
    assert [f for f, _ in results] == frames
    assert all(r.converged for _, r in results), [r.unmet for _, r in results]
    thetas = np.array([r.theta for _, r in results])
    n = sc.model.n
    step = np.where(sc.model.prismatic, limits.max_root_shift, limits.max_joint_change)
    assert np.all(np.abs(np.diff(thetas, axis=0)) <= step[None, :n] + 1e-9)
    for frame, result in results:
        target = sc.problem_at(frame).targets[1]
        rot, pos = result.state.kin.tcp_frame(sc.model.tcp("top"))
        np.testing.assert_allclose(pos, target.position, atol=1.5e-3)


def test_a_target_that_jumps_is_reported(tmp_path):
    text = SNAKE_MOTION.read_text().replace("frame = 48", "frame = 2").replace("end = 48", "end = 2")
    text = text.replace("[motion]", "[motion]\nmax_joint_change = 0.02")
    path = tmp_path / "jump.toml"
    path.write_text(text)
    sc = load_scenario(path)
    results = list(solve_frames(sc.problem_at, sc.frames, sc.start, sc.options, sc.limits))
    last = results[-1][1]
    assert not last.converged
    assert any("moved too far" in note for note in last.notes)
    assert np.isfinite(last.x).all()


@pytest.mark.parametrize(
    "keys, message",
    [
        (
            "[[targets.keys]]\nframe = 3\nposition = [0, 0, 1]\n[[targets.keys]]\nframe = 3\nposition = [0, 0, 1.1]\n",
            "distinct frame numbers",
        ),
        ("[[targets.keys]]\nframe = 2.5\nposition = [0, 0, 1]\n", "whole frame number"),
        ("[[targets.keys]]\nframe = 1\nposition = [0, 0]\n", "position"),
    ],
)
def test_bad_keys_exit_2(tmp_path, keys, message):
    base = SNAKE_MOTION.read_text()
    head = base[: base.index('[[targets]]\ntcp = "top"')]
    path = tmp_path / "bad.toml"
    path.write_text(head + '[[targets]]\ntcp = "top"\n' + keys)
    proc = subprocess.run(
        [sys.executable, "-m", "solver", "solve", str(path)], cwd=ROOT, capture_output=True, text=True
    )
    assert proc.returncode == 2, proc.stderr
    assert message in proc.stderr and "Traceback" not in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1


def test_cli_writes_every_frame(tmp_path):
    text = SNAKE_MOTION.read_text().replace("end = 48", "end = 6").replace("frame = 48", "frame = 6")
    path = tmp_path / "short.toml"
    path.write_text(text)
    out = tmp_path / "motion.json"
    proc = subprocess.run(
        [sys.executable, "-m", "solver", "solve", "-q", str(path), "-o", str(out)],
        cwd=ROOT,
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 0, proc.stderr
    data = json.loads(out.read_text())
    assert [f["frame"] for f in data["frames"]] == [1, 2, 3, 4, 5, 6]
    assert all(f["converged"] for f in data["frames"])
    assert "top" in data["frames"][0]["targets"]


def test_static_scenario_is_one_frame():
    sc = load_scenario(ROOT / "presets" / "scenarios" / "snake_pose_a.toml")
    assert sc.frames == [1] and sc.tracks == []
    assert sc.problem_at(1) is sc.problem
    assert solve(sc.problem, sc.start, sc.options).converged
