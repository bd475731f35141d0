"""``batch.py --operations FILE.toml`` as a user runs it (the bpy module in a subprocess, the extension installed):
a tiny get/place at 12 frames/s (the box pushed forward on the table; placed to the side, a forearm pinched between
the box and the trunk cut into it between two frames on Blender 4.2) generated headlessly from its operations
alone, keyed (the armature and the box) and written (.blend, glTF, report, result, picture); a bad file or a flag it
takes no part in is one line, exit 2.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from environments import copy_user, run_python
from test_batch import BATCH

from solver import read_result

OPS = """
name = "tiny get and place"
[manikin]
preset = "male_50"
[operate]
fps = 12
[motion]
max_joint_change = 0.6
max_root_shift = 0.15
[[obstacles]]
name = "table"
kind = "box"
center = [0.0, -0.55, 0.73]
size = [1.2, 0.5, 0.04]
[[objects]]
name = "box"
kind = "box"
center = [0.0, -0.45, 0.871]
size = [0.30, 0.22, 0.24]
mass = 4.0
[[operations]]
do = "get"
object = "box"
[[operations]]
do = "place"
object = "box"
to = [0.0, -0.62, 0.871]
"""

SCENE = """
import bpy, json, sys
blend, out = sys.argv[1], sys.argv[2]
bpy.ops.wm.open_mainfile(filepath=blend, load_ui=False)
scene = bpy.context.scene
box = bpy.data.objects["box"]
arm = next(ob for ob in bpy.data.objects if ob.type == "ARMATURE")
at = {}
for frame in (scene.frame_start, scene.frame_end):
    scene.frame_set(frame)
    corners = [box.matrix_world @ __import__("mathutils").Vector(c) for c in box.bound_box]
    at[frame] = [sum(c[k] for c in corners) / 8 for k in range(3)]
seen = dict(start=scene.frame_start, end=scene.frame_end, box_animated=box.animation_data is not None,
            arm_action=arm.animation_data is not None and arm.animation_data.action is not None,
            at=at)
with open(out, "w", encoding="utf-8") as fh:
    json.dump(seen, fh)
"""


@pytest.fixture(scope="module")
def user(installed_user: Path, tmp_path_factory) -> Path:
    """A Blender user folder with the extension installed (a copy of conftest's)."""
    return copy_user(installed_user, tmp_path_factory.mktemp("user") / "user")


def test_batch_generates_operations_and_writes_every_output(tmp_path: Path, blender_python: Path, user: Path,
                                                            monkeypatch):  # fmt: skip
    monkeypatch.setenv("MANIKIN_RENDER_DRAFT", "1")  # a picture is written: a draft will do (test_batch renders one)
    (tmp_path / "ops.toml").write_text(OPS, encoding="utf-8")
    args = [BATCH, "--operations", "ops.toml", "--out", "o.blend", "--export", "o.glb", "--report", "r.json",
            "--result", "res.json", "--picture", "p.png"]  # fmt: skip
    done = run_python(blender_python, args, user, cwd=tmp_path)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    assert "Traceback" not in done.stdout + done.stderr and "generating" in done.stdout
    assert "operations[1] (place box)" in done.stdout and "keyed box with the hands" in done.stdout
    for name in ("o.blend", "o.glb", "r.json", "res.json", "p.png"):
        assert (tmp_path / name).stat().st_size > 1000, name
    report = json.loads((tmp_path / "r.json").read_text(encoding="utf-8"))
    assert report["converged"] and report["source"] == {"operations": "ops.toml"}
    frames = [f["frame"] for f in report["frames"]]
    assert frames == list(range(1, len(frames) + 1)) and len(frames) > 10
    assert [f.number for f in read_result(tmp_path / "res.json").frames] == frames  # manikin ergo reads it
    lift = report["niosh"]  # the lift from the grasp to the release, with the box's weight in the hands
    assert lift["load_kg"] == pytest.approx(4.0) and 1 < lift["origin"]["frame"] < lift["destination"]["frame"]
    seen_path = tmp_path / "seen.json"
    done = run_python(blender_python, ["-c", SCENE, tmp_path / "o.blend", seen_path], user, cwd=tmp_path)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    seen = json.loads(seen_path.read_text(encoding="utf-8"))
    assert seen["arm_action"] and seen["box_animated"]
    assert (seen["start"], seen["end"]) == (1, frames[-1])
    assert np.allclose(seen["at"]["1"], [0.0, -0.45, 0.871], atol=2e-3)  # where it lay
    assert np.allclose(seen["at"][str(frames[-1])], [0.0, -0.62, 0.871], atol=1e-2)  # where it was placed


@pytest.mark.parametrize(
    "extra, args, says",
    [
        ('[[operations]]\ndo = "get"\nobject = "crate"\n', [], "crate"),
        ("", ["--frames", 1, 3], "--operations makes its own manikin and frames from the file: leave out --frames"),
        ("", ["--scenario", "ops.toml"], "leave out --scenario"),
    ],
    ids=["unknown_object", "frames", "scenario"],
)
def test_batch_operations_bad_input_is_one_line(tmp_path: Path, blender_python: Path, user: Path, extra: str,
                                                args: list, says: str) -> None:  # fmt: skip
    (tmp_path / "ops.toml").write_text(OPS + extra, encoding="utf-8")
    done = run_python(blender_python, [BATCH, "--operations", "ops.toml", "--out", "o.blend", *args], user,
                      cwd=tmp_path)  # fmt: skip
    assert done.returncode == 2, done.stdout[-3000:] + done.stderr[-3000:]
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and says in lines[0], done.stderr
    assert not (tmp_path / "o.blend").exists()
