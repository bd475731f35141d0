"""The headless batch script as a user runs it (``python blender_manikin/batch.py ...`` with the bpy module, each
in a subprocess): every output written, exit codes 0 / 3 / 2, one line for bad input, and the copy inside an
installed extension running from its own folder.
"""

from __future__ import annotations

import importlib.util
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from blender_manikin.build import build
from solver.ergonomics import read_result

ROOT = Path(__file__).resolve().parents[1]
BATCH = ROOT / "blender_manikin" / "batch.py"
SNAKE = ROOT / "presets" / "scenarios" / "snake_motion.toml"
pytestmark = pytest.mark.skipif(importlib.util.find_spec("bpy") is None, reason="bpy (Blender as a module) missing")


def run(args: list, cwd: Path, script: Path = BATCH, env: dict | None = None) -> subprocess.CompletedProcess:
    user = cwd / "user"
    user.mkdir(exist_ok=True)
    env = env or dict(os.environ, BLENDER_USER_RESOURCES=str(user))
    return subprocess.run(
        [sys.executable, str(script), *map(str, args)], cwd=cwd, env=env, capture_output=True, text=True, timeout=600
    )


def test_batch_writes_every_output(tmp_path: Path) -> None:
    out = tmp_path / "out"
    done = run(
        ["--scenario", SNAKE, "--frames", 1, 6, "--out", out / "snake.blend", "--export", out / "snake.bvh",
         "--export", out / "snake.glb", "--export", out / "snake.fbx", "--report", out / "report.json",
         "--result", out / "result.json", "--picture", out / "poses.png"],
        tmp_path,
    )  # fmt: skip
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    assert "Traceback" not in done.stdout + done.stderr
    for name in ("snake.blend", "snake.bvh", "snake.glb", "snake.fbx", "report.json", "result.json", "poses.png"):
        assert (out / name).stat().st_size > 1000, name
    report = json.loads((out / "report.json").read_text(encoding="utf-8"))
    assert report["converged"] and report["not_converged"] == [] and report["manikin"] == "snake"
    assert [f["frame"] for f in report["frames"]] == list(range(1, 7))
    for frame in report["frames"]:
        assert frame["converged"] and frame["iterations"] >= 0 and 0 < frame["time_s"] <= frame["wall_s"]
        # each locked axis within 1 mm (so the 3-axis norm within sqrt(3) mm); force balance within 1 N
        assert frame["residuals"]["top.position"] < 3**0.5 * 1e-3 and frame["residuals"]["balance.force"] < 1.0
        assert set(frame["ergonomics"]) >= {"rula", "reba", "owas", "worksheet", "niosh", "joint_loads", "posture"}
    assert len(read_result(out / "result.json")["frames"]) == 6  # python -m solver ergo reads it
    import matplotlib.image

    picture = matplotlib.image.imread(out / "poses.png")
    assert picture.shape[1] > 2 * picture.shape[0] and np.std(picture[:, :, :3]) > 0.05  # tiles side by side


def test_batch_reports_frames_that_do_not_converge(tmp_path: Path) -> None:
    """A target that jumps between two frames: exit 3, the report still written, the jump named."""
    text = SNAKE.read_text(encoding="utf-8").replace("frame = 48", "frame = 2").replace("end = 48", "end = 3")
    (tmp_path / "jump.toml").write_text(text, encoding="utf-8")
    done = run(["--scenario", "jump.toml", "--report", "report.json", "--out", "jump.blend"], tmp_path)
    assert done.returncode == 3, done.stdout[-3000:] + done.stderr[-3000:]
    assert "moved too far" in done.stdout and "Traceback" not in done.stderr
    report = json.loads((tmp_path / "report.json").read_text(encoding="utf-8"))
    assert report["not_converged"] and not report["converged"] and (tmp_path / "jump.blend").is_file()
    assert all("moved too far" in note for f in report["frames"] if not f["converged"] for note in f["notes"])


@pytest.mark.parametrize(
    "args, says",
    [
        (["--scenario", "missing.toml"], "missing.toml: file not found"),
        (["--scenario", "broken.toml"], "malformed TOML"),
        (["--scenario", SNAKE, "--export", "motion.obj"], "cannot export .obj"),
        (["--scenario", SNAKE, "--frames", 5, 2], "end comes before the start"),
        (["--scenario", SNAKE, "--frames", "one", 2], "invalid int value"),
        (["--bogus"], "unrecognized arguments: --bogus"),
        (["--blend", "missing.blend"], "missing.blend: file not found"),
        ([], "no manikin in the scene"),
    ],
)
def test_batch_bad_input_is_one_line_and_exit_2(tmp_path: Path, args: list, says: str) -> None:
    (tmp_path / "broken.toml").write_text("[manikin\npreset = 1", encoding="utf-8")
    done = run(args, tmp_path)
    assert done.returncode == 2, done.stdout[-3000:] + done.stderr[-3000:]
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and says in lines[0], done.stderr


def test_batch_runs_from_an_installed_extension(tmp_path: Path) -> None:
    """Installed as a user installs it, the batch script inside the extension folder loads that copy."""
    user = tmp_path / "user"
    user.mkdir()
    env = dict(os.environ, BLENDER_USER_RESOURCES=str(user))
    zip_path = build(tmp_path / "dist")
    install = f"import sys; sys.path.insert(0, {str(ROOT)!r}); from blender_manikin.build import install; " \
              f"install(__import__('pathlib').Path({str(zip_path)!r}))"  # fmt: skip
    done = subprocess.run([sys.executable, "-c", install], env=env, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr[-3000:]
    installed = next(user.rglob("manikin/blender_manikin/batch.py"))
    done = run(["--scenario", SNAKE, "--frames", 1, 3, "--report", "report.json"], tmp_path, installed, env)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    report = json.loads((tmp_path / "report.json").read_text(encoding="utf-8"))
    assert report["converged"] and len(report["frames"]) == 3


def test_batch_as_blender_runs_it_on_an_open_blend(tmp_path: Path) -> None:
    """``blender --background scene.blend --python batch.py -- ARGS``, emulated with the bpy module: the .blend is
    opened first, sys.argv is Blender's, and the script runs as __main__; it bakes the open file's manikin."""
    done = run(["--scenario", SNAKE, "--frames", 1, 2, "--out", "scene.blend"], tmp_path)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    blend = tmp_path / "scene.blend"
    argv = ["blender", "--background", str(blend), "--python", str(BATCH), "--", "--frames", "1", "4",
            "--report", "again.json"]  # fmt: skip
    emulate = (
        f"import bpy, runpy, sys; bpy.ops.wm.open_mainfile(filepath={str(blend)!r}); sys.argv = {argv!r}\n"
        f"runpy.run_path({str(BATCH)!r}, run_name='__main__')"
    )
    env = dict(os.environ, BLENDER_USER_RESOURCES=str(tmp_path / "user"))
    done = subprocess.run([sys.executable, "-c", emulate], cwd=tmp_path, env=env, capture_output=True, text=True,
                          timeout=600)  # fmt: skip
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    report = json.loads((tmp_path / "again.json").read_text(encoding="utf-8"))
    assert report["converged"] and [f["frame"] for f in report["frames"]] == [1, 2, 3, 4]
    assert report["source"]["blend"] is None and report["source"]["scenario"] is None
