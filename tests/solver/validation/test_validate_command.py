"""``manikin validate`` on three key frames (a few seconds): the files it writes, what they say, the split filter and
its bad-input exits. The full run over every key frame is a benchmark-like command, not a test."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from solver import load_preset
from solver.validation.measures import measure
from solver.validation.skeleton import model_skeleton

REPO = Path(__file__).resolve().parents[3]
FRAMES = ("115_02_stand", "115_09_squat_low", "14_07_reach_up")


def _run(*args: str) -> subprocess.CompletedProcess:
    env = dict(os.environ, PYTHONPATH=str(REPO))
    return subprocess.run([sys.executable, "-m", "solver", "validate", *args], cwd=REPO, env=env,
                          capture_output=True, text=True, timeout=300)  # fmt: skip


@pytest.fixture(scope="module")
def report(tmp_path_factory) -> tuple[subprocess.CompletedProcess, Path]:
    out = tmp_path_factory.mktemp("validate")
    args = [a for name in FRAMES for a in ("--key-frame", name)]
    return _run("--out", str(out), *args), out


def test_writes_the_tables_and_the_picture(report) -> None:
    run, out = report
    assert run.returncode == 0, run.stderr
    for name in ("validation.json", "validation.csv", "validation.md", "validation.png"):
        assert (out / name).stat().st_size > 0, name
    assert "trunk_flexion" in run.stdout and "held-out" in run.stdout
    data = json.loads((out / "validation.json").read_text())
    assert [r["name"] for r in data["rows"]] == list(FRAMES)
    assert "mocap.cs.cmu.edu" in data["citation"]
    assert set(data["summary"]["split"]) == {"train", "held-out"}
    lines = (out / "validation.csv").read_text().splitlines()
    assert len(lines) == 1 + 3 * 12


def test_the_solved_wrists_are_where_the_person_held_them(report) -> None:
    _, out = report
    for r in json.loads((out / "validation.json").read_text())["rows"]:
        assert r["converged"], r["name"]
        for side in ("wrist_r", "wrist_l"):
            gap = np.subtract(r["skeletons"]["predicted"][side], r["skeletons"]["measured"][side])
            assert np.linalg.norm(gap) < 0.01, (r["name"], side)
        for side in ("ankle_r", "ankle_l"):  # the feet planted under the measured ankles
            gap = np.subtract(r["skeletons"]["predicted"][side], r["skeletons"]["measured"][side])[:2]
            assert np.linalg.norm(gap) < 0.01, (r["name"], side)


def test_the_measured_squat_is_a_squat(report) -> None:
    _, out = report
    rows = {r["name"]: r for r in json.loads((out / "validation.json").read_text())["rows"]}
    squat = rows["115_09_squat_low"]["measured"]
    assert squat["knee_flexion_r"] > 100 and squat["knee_flexion_l"] > 100
    assert squat["pelvis_height"] < 0.4
    stand = rows["115_02_stand"]["measured"]
    assert abs(stand["trunk_flexion"]) < 10  # zeroed at the subject's upright reference


def test_the_split_keeps_its_subjects(tmp_path) -> None:
    run = _run("--out", str(tmp_path), "--split", "held-out", "--key-frame", "14_07_reach_up",
               "--key-frame", "115_02_stand", "--no-picture", "-q")  # fmt: skip
    assert run.returncode == 0, run.stderr
    rows = json.loads((tmp_path / "validation.json").read_text())["rows"]
    assert [r["name"] for r in rows] == ["14_07_reach_up"]
    assert not (tmp_path / "validation.png").exists()


@pytest.mark.parametrize(
    "args, words",
    [(("--split", "test"), "--split"), (("--key-frame", "no_such_frame"), "no key frame")],
)
def test_bad_input_exits_2_with_one_line(tmp_path, args, words) -> None:
    run = _run("--out", str(tmp_path), *args)
    assert run.returncode == 2
    assert words in run.stderr and len(run.stderr.strip().splitlines()) == 1


def test_the_manikin_upright_reads_zero() -> None:
    model = load_preset("male_50")
    m = measure(model_skeleton(model, model.zero_pose(), 1.74), 1.74)
    for name in ("trunk_flexion", "lateral_bend", "knee_flexion_r", "knee_flexion_l", "elbow_flexion_r"):
        assert abs(m[name]) < 3.0, name


def test_the_behaviour_model_squats_where_the_standard_comfort_stoops(report, tmp_path) -> None:
    """115_09_squat_low (the person's knees at 120 deg): the behaviour model (the command's default) bends the knees
    past 60 deg and keeps the trunk within 20 deg of the person's; ``--model standard`` stoops with straight knees
    (the figures before the behaviour model). Each file says which model made it."""
    run, out = report
    assert run.returncode == 0, run.stderr
    rows = {r["name"]: r for r in json.loads((out / "validation.json").read_text())["rows"]}
    squat = rows["115_09_squat_low"]
    assert squat["measured"]["knee_flexion_r"] > 100.0
    assert squat["predicted"]["knee_flexion_r"] > 60.0 and abs(squat["error"]["trunk_flexion"]) < 20.0
    assert "behaviour model" in (out / "validation.md").read_text()
    standard = _run("--out", str(tmp_path), "--model", "standard", "--key-frame", "115_09_squat_low", "--no-picture")
    assert standard.returncode == 0, standard.stderr
    stooped = json.loads((tmp_path / "validation.json").read_text())["rows"][0]
    assert stooped["predicted"]["knee_flexion_r"] < 10.0 and stooped["error"]["trunk_flexion"] > 40.0
    assert "standard model" in (tmp_path / "validation.md").read_text()
