"""The headless batch script as a user runs it (``python blender_manikin/batch.py ...`` with the bpy module, each
in a subprocess): every output written, exit codes 0 / 3 / 2, one line for bad input (found before bpy is imported
when it needs no scene), and the copy inside an installed extension running from its own folder.
"""

from __future__ import annotations

import json
import re
import subprocess
from pathlib import Path

import numpy as np
import pytest
from environments import ROOT, copy_user, run_python

from solver import read_result
from solver.ergonomics import ErgoOptions, checked
from solver.ergonomics.registry import in_frame_order
from solver.ergonomics.report import frame_report, sources

BATCH = ROOT / "blender_manikin" / "batch.py"
SNAKE = ROOT / "presets" / "scenarios" / "snake_motion.toml"
LIFT = ROOT / "presets" / "scenarios" / "box_lift_motion.toml"


def numbers(value: object, path: str = "") -> dict:
    """{path: leaf} of a report part: every number, string and null by where it is."""
    if isinstance(value, dict):
        return {k: v for key, item in value.items() for k, v in numbers(item, f"{path}.{key}").items()}
    if isinstance(value, list):
        return {k: v for i, item in enumerate(value) for k, v in numbers(item, f"{path}[{i}]").items()}
    return {path: value}


@pytest.fixture(scope="module")
def user(installed_user: Path, tmp_path_factory) -> Path:
    """A Blender user folder with the extension installed (a copy of conftest's): a checkout's batch.py then finds
    scipy and matplotlib on Blender's path, as in a Blender that has the extension."""
    return copy_user(installed_user, tmp_path_factory.mktemp("user") / "user")


# The script as __main__ in a Python where ``import bpy`` fails: what it finds before it imports bpy (no Blender start).
NO_BPY = (
    "import runpy, sys; sys.modules['bpy'] = None; sys.argv.pop(0); runpy.run_path(sys.argv[0], run_name='__main__')"
)


@pytest.fixture
def run(blender_python: Path, user: Path):
    """``batch.py ARGS`` (or another script) by the Blender environment's Python in ``cwd``; ``bpy=False``: with
    ``import bpy`` failing (:data:`NO_BPY`)."""

    def batch(args: list, cwd: Path, script: Path = BATCH, bpy: bool = True) -> subprocess.CompletedProcess:
        head = [script] if bpy else ["-c", NO_BPY, script]
        return run_python(blender_python, [*head, *args], user, cwd=cwd)

    return batch


BLENDER_SAYS = ("Info:", "INFO", "Exported", "export", "bpy.data", "Saved", "Read blend", "Draco", "| ")
OUR_LINES = re.compile(
    r"(baking |  frame |baked |wrote |  \S|rendering frames |exporting \S+ \(\d+ frames\) \.\.\.$|done in )"
)


def test_batch_writes_every_output(tmp_path: Path, run) -> None:
    """Every output written; Blender's exporters, saving and rendering print their own lines (glTF log, FBX debug
    tuple, "Info: Saved copy", "BVH Exported", "Saved: ...png"): a normal run shows only what we did and wrote (-q:
    :func:`test_batch_prints_only_its_own_lines`)."""
    out = tmp_path / "out"
    done = run(
        ["--scenario", SNAKE, "--frames", 1, 6, "--out", out / "snake.blend", "--export", out / "snake.bvh",
         "--export", out / "snake.glb", "--export", out / "snake.gltf", "--export", out / "snake.fbx",
         "--report", out / "report.json", "--result", out / "result.json", "--picture", out / "poses.png",
         "--plots", out / "ergo"],
        tmp_path,
    )  # fmt: skip
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    assert "Traceback" not in done.stdout + done.stderr and done.stderr == ""
    names = ["snake.blend", "snake.bvh", "snake.glb", "snake.gltf", "snake.fbx", "report.json", "result.json",
             "poses.png", "ergo_loads.png", "ergo_scores.png", "ergo_back.png"]  # fmt: skip
    for name in names:
        assert (out / name).stat().st_size > 1000, name
    lines = done.stdout.splitlines()
    assert [line for line in lines if not OUR_LINES.match(line)] == [], done.stdout
    theirs = [line for line in lines if not line.startswith("exporting ")]
    assert [line for line in theirs if any(s in line for s in BLENDER_SAYS)] == [], done.stdout
    assert {Path(line.removeprefix("wrote ")).name for line in lines if line.startswith("wrote ")} == set(names)
    report = json.loads((out / "report.json").read_text(encoding="utf-8"))
    assert report["converged"] and report["not_converged"] == [] and report["manikin"] == "snake"
    assert [f["frame"] for f in report["frames"]] == list(range(1, 7))
    for frame in report["frames"]:
        assert frame["converged"] and frame["iterations"] >= 0 and 0 < frame["time_s"] <= frame["wall_s"]
        # each locked axis within 1 mm (so the 3-axis norm within sqrt(3) mm); force balance within 1 N
        assert frame["residuals"]["top.position"] < 3**0.5 * 1e-3 and frame["residuals"]["balance.force"] < 1.0
        assert list(frame["ergonomics"]) == ["posture", "joint_loads", *(s.name for s in in_frame_order())]
    assert report["niosh"]["reason"] and "niosh_lift" not in report  # the lift under its score's name, as ergo's
    assert list(report["ergonomics_sources"]) == list(sources())
    frames = read_result(out / "result.json").frames
    assert len(frames) == 6  # python -m solver ergo reads it
    for f, written in zip(frames, report["frames"], strict=True):  # the joint loads, written from arrays: as ergo's
        loads = json.loads(json.dumps(frame_report(f, checked(ErgoOptions()), None, None, None)[0]["joint_loads"]))
        mine, theirs = numbers(written["ergonomics"]["joint_loads"]), numbers(loads)
        assert mine.keys() == theirs.keys() and len(mine) > 100  # the file's axes differ in the last bit (read back)
        assert all(mine[k] == theirs[k] or abs(mine[k] - theirs[k]) <= 1e-9 * abs(theirs[k]) + 1e-12 for k in mine)
    import matplotlib.image

    picture = matplotlib.image.imread(out / "poses.png")
    assert picture.shape[1] > 2 * picture.shape[0] and np.std(picture[:, :, :3]) > 0.05  # tiles side by side


def test_batch_reports_frames_that_do_not_converge(tmp_path: Path, run) -> None:
    """A target that jumps between two frames: exit 3, the report still written, the jump named."""
    text = SNAKE.read_text(encoding="utf-8").replace("frame = 48", "frame = 2").replace("end = 48", "end = 3")
    (tmp_path / "jump.toml").write_text(text, encoding="utf-8")
    done = run(["--scenario", "jump.toml", "--report", "report.json", "--out", "jump.blend"], tmp_path)
    assert done.returncode == 3, done.stdout[-3000:] + done.stderr[-3000:]
    assert "moved too far" in done.stdout and "Traceback" not in done.stderr
    report = json.loads((tmp_path / "report.json").read_text(encoding="utf-8"))
    assert report["not_converged"] and not report["converged"] and (tmp_path / "jump.blend").is_file()
    assert all(any("moved too far" in note for note in f["notes"]) for f in report["frames"] if not f["converged"])


@pytest.mark.parametrize(
    "args, says, scene",
    [
        (["--scenario", "missing.toml"], "missing.toml: file not found", False),
        (["--scenario", "broken.toml"], "malformed TOML", False),
        (["--scenario", SNAKE, "--export", "motion.obj"], "cannot export .obj", False),
        (["--scenario", SNAKE, "--frames", 5, 2], "end comes before the start", False),
        (["--scenario", SNAKE, "--frames", "one", 2], "invalid int value", False),
        (["--bogus"], "unrecognized arguments: --bogus", False),
        (["--blend", "missing.blend"], "missing.blend: file not found", False),
        ([], "no manikin in the scene", True),
        (
            ["--scenario", LIFT, "--retarget", "nosuch"],
            "--retarget nosuch: no shipped rig or object of that name",
            True,
        ),
        (["--scenario", SNAKE, "--retarget", "mixamo"], "--retarget mixamo: 'snake' is not a human manikin", True),
    ],
)
def test_batch_bad_input_is_one_line_and_exit_2(tmp_path: Path, args: list, says: str, scene: bool, run) -> None:
    """Bad input is one line and exit 2; what needs no scene (``scene`` False) is found before bpy is imported
    (run where ``import bpy`` fails: it costs no Blender start)."""
    (tmp_path / "broken.toml").write_text("[manikin\npreset = 1", encoding="utf-8")
    done = run(args, tmp_path, bpy=scene)
    assert done.returncode == 2, done.stdout[-3000:] + done.stderr[-3000:]
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and says in lines[0], done.stderr


LONG = "a" * 300 + ".json"  # longer than any file system's names


@pytest.mark.parametrize(
    "args, says",
    [
        (["--report", "adir"], "--report adir: is a directory"),
        (["--export", "adir.fbx"], "--export adir.fbx: is a directory"),
        (["--result", LONG], "file name too long (305 bytes, at most 255)"),
        (["--report", "r.json", "--result", "r.json"], "--result r.json: the same file as --report r.json"),
        (["--report", "s.toml"], "--report s.toml: the same file as the input --scenario s.toml"),
        (["--picture", "/proc/poses.png"], "cannot write in /proc"),
        (["--plots", "adir/" + "b" * 250], "--plots"),
        (["--report", "-"], "cannot write to standard output"),
        (["--frames", 1, 2000000], "at most 100000"),
    ],
    ids=["report_dir", "export_dir", "long_name", "same_twice", "onto_input", "proc", "plots_long", "stdout", "frames"],
)
def test_batch_refuses_bad_output_paths_before_the_bake(tmp_path: Path, args: list, says: str, run) -> None:
    """A bad output path is one line and exit 2 before anything is baked, before bpy is even imported (run where
    ``import bpy`` fails); the .blend the run would have replaced and every input stay as they were (the issue:
    --report to a bad path failed after the bake and lost the .blend)."""
    (tmp_path / "adir").mkdir()
    (tmp_path / "adir.fbx").mkdir()
    (tmp_path / "s.toml").write_bytes(SNAKE.read_bytes())
    (tmp_path / "keep.blend").write_bytes(b"keep me")
    before = {p.name: p.read_bytes() if p.is_file() else None for p in tmp_path.iterdir()}
    done = run(["--scenario", "s.toml", "--frames", 1, 3, "--out", "keep.blend", *args], tmp_path, bpy=False)
    assert done.returncode == 2, done.stdout[-3000:] + done.stderr[-3000:]
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and says in lines[0], done.stderr
    assert "baking" not in done.stdout, "the bad path was found only after the bake"
    after = {p.name: p.read_bytes() if p.is_file() else None for p in tmp_path.iterdir() if p.name != "user"}
    assert after == before


def test_batch_runs_from_an_installed_extension(tmp_path: Path, run, user: Path) -> None:
    """The batch script inside the installed extension's folder loads that copy:
    ``blender --background --python <extension>/blender_manikin/batch.py -- ...``."""
    installed = next(user.rglob("manikin/blender_manikin/batch.py"))
    done = run(["--scenario", SNAKE, "--frames", 1, 3, "--report", "report.json"], tmp_path, installed)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    report = json.loads((tmp_path / "report.json").read_text(encoding="utf-8"))
    assert report["converged"] and len(report["frames"]) == 3


def test_batch_prints_only_its_own_lines(tmp_path: Path, run, monkeypatch) -> None:
    """With -q, not a line from us nor from Blender's exporters, saving and rendering (a normal run's lines:
    :func:`test_batch_writes_every_output`, which renders at the default quality: here a draft does)."""
    monkeypatch.setenv("MANIKIN_RENDER_DRAFT", "1")
    names = ["s.glb", "s.gltf", "s.bvh", "s.fbx"]
    args = ["--scenario", SNAKE, "--frames", 1, 3, "--out", "s.blend", "--report", "r.json", "--picture", "p.png"]
    done = run(args + [a for name in names for a in ("--export", name)] + ["-q"], tmp_path)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    assert all((tmp_path / name).is_file() for name in [*names, "s.blend", "r.json", "p.png"])
    assert (done.stdout, done.stderr) == ("", "")


def test_demo_quiet_prints_nothing(tmp_path: Path, blender_python: Path, user: Path, monkeypatch) -> None:
    """``python -m blender_manikin.demo -q``: every file written, not a line printed. The box lift is generated
    from presets/operations/box_lift.toml alone (issues 35, 36): the knees bend at the low shelf, the worker steps
    toward the table, the box is keyed from the shelf onto the table. Its pictures are drafts (~10 s less)."""
    monkeypatch.setenv("MANIKIN_RENDER_DRAFT", "1")
    args = ["-m", "blender_manikin.demo", "--out-dir", tmp_path, "-q"]
    done = run_python(blender_python, args, user, cwd=ROOT)
    assert (done.returncode, done.stdout, done.stderr) == (0, "", "")
    written = sorted(p.name for p in tmp_path.iterdir())
    assert written == ["box_lift.blend", "box_lift.bvh", "box_lift.glb", "box_lift_key_poses.png",
                       "box_lift_report.json", "cabinet_reach.blend", "cabinet_reach.png"]  # fmt: skip
    report = json.loads((tmp_path / "box_lift_report.json").read_text(encoding="utf-8"))
    assert report["converged"] and report["source"]["operations"].endswith("box_lift.toml")
    grasp = report["niosh"]["origin"]["frame"]  # the first frame the hands hold the box (on the shelf)
    knees = report["frames"][grasp - 1]["ergonomics"]["posture"]
    assert min(knees["l"]["knee_flexion"], knees["r"]["knee_flexion"]) > 60, knees
    assert report["niosh"]["load_kg"] == pytest.approx(10.0)
    seen = tmp_path / "seen.json"
    done = run_python(blender_python, ["-c", SCENE, tmp_path / "box_lift.blend", seen], user, cwd=tmp_path)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    scene = json.loads(seen.read_text(encoding="utf-8"))
    assert {"shelf", "table"} <= set(scene["obstacles"])  # the file's obstacles are objects in the .blend
    assert scene["box"]["animated"]
    first, last = scene["box"]["at"][str(scene["start"])], scene["box"]["at"][str(scene["end"])]
    assert np.allclose(first, [0.0, -0.40, 0.40], atol=2e-3)  # on the shelf
    assert abs(last[1] + 0.87) < 0.02 and abs(last[2] - 0.872) < 0.01  # on the table (its top at 0.75 m)
    feet = scene["feet_y"]  # the manikin faces -y: it stepped toward the table
    assert feet[str(scene["end"])] < feet[str(scene["start"])] - 0.05, feet


SCENE = """
import bpy, json, sys
from mathutils import Vector
blend, out = sys.argv[1], sys.argv[2]
bpy.ops.wm.open_mainfile(filepath=blend, load_ui=False)
scene = bpy.context.scene
box = bpy.data.objects["box"]
at, feet = {}, {}
for frame in (scene.frame_start, scene.frame_end):
    scene.frame_set(frame)
    at[frame] = list(sum((box.matrix_world @ Vector(c) for c in box.bound_box), Vector()) / 8)
    feet[frame] = sum(bpy.data.objects["tcp." + t].matrix_world.translation.y for t in ("foot_r", "foot_l")) / 2
obstacles = [ob.name for ob in bpy.data.collections["Obstacles"].objects]
seen = dict(obstacles=obstacles, start=scene.frame_start, end=scene.frame_end, feet_y=feet,
            box=dict(animated=box.animation_data is not None, at=at))
with open(out, "w", encoding="utf-8") as fh:
    json.dump(seen, fh)
"""


def test_batch_without_the_wheels_says_what_is_missing(tmp_path: Path, blender_python: Path) -> None:
    """A checkout's batch.py in a Blender without the extension: one line naming scipy and the way to get it."""
    done = run_python(blender_python, [BATCH, "--scenario", SNAKE, "--frames", 1, 2], tmp_path / "user")
    assert done.returncode == 2, done.stdout[-3000:] + done.stderr[-3000:]
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and "scipy is missing: install the Manikin extension zip" in lines[0], done.stderr


def test_batch_as_blender_runs_it_on_an_open_blend(tmp_path: Path, run, blender_python: Path, user: Path) -> None:
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
    done = run_python(blender_python, ["-c", emulate], user, cwd=tmp_path)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    report = json.loads((tmp_path / "again.json").read_text(encoding="utf-8"))
    assert report["converged"] and [f["frame"] for f in report["frames"]] == [1, 2, 3, 4]
    assert report["source"]["blend"] is None and report["source"]["scenario"] is None


KEYED = """
import bpy, json, sys
bpy.ops.wm.open_mainfile(filepath=sys.argv[1], load_ui=False)
rig = bpy.data.objects["male_50.mixamo"]
done = json.loads(rig["manikin_retargeted"])
print(done["source"], done["bones"], *rig.animation_data.action.frame_range)
"""


def test_batch_retargets_onto_a_shipped_rig_and_exports_it(
    tmp_path: Path, run, blender_python: Path, user: Path
) -> None:
    """``--retarget mixamo``: the Mixamo rig is built beside the manikin, keyed over the baked frames and saved in
    the .blend, and it (not the manikin) is what the FBX holds."""
    done = run(["--scenario", LIFT, "--frames", 1, 6, "--retarget", "mixamo", "--out", "lift.blend", "--export",
                "lift.fbx"], tmp_path)  # fmt: skip
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    assert "retargeted frames 1-6 onto male_50.mixamo: 52 bones keyed, leg-length ratio 1.000" in done.stdout
    fbx = (tmp_path / "lift.fbx").read_bytes()
    assert b"mixamorig:LeftHand" in fbx and b"upper_arm_l" not in fbx
    done = run_python(blender_python, ["-c", KEYED, tmp_path / "lift.blend"], user, cwd=tmp_path)
    assert done.returncode == 0, done.stderr[-3000:]
    assert done.stdout.strip().splitlines()[-1] == "male_50 52 1.0 6.0"


POSE = """
import bpy, json, sys
blend, frames, out = sys.argv[1], json.loads(sys.argv[2]), sys.argv[3]
bpy.ops.wm.open_mainfile(filepath=blend, load_ui=False)
arm = next(ob for ob in bpy.data.objects if ob.type == "ARMATURE")
seen = {}
for frame in frames:
    bpy.context.scene.frame_set(frame)
    seen[frame] = {f'{b.name}.{p}[{i}]': getattr(b, p)[i] for b in arm.pose.bones
                   for p in ("location", "rotation_euler") for i in range(3)}
with open(out, "w", encoding="utf-8") as fh:
    json.dump(seen, fh)
"""


def test_batch_ctrl_c_keys_and_keeps_the_solved_frames(tmp_path: Path, blender_python: Path, user: Path) -> None:
    """Ctrl-C during a long bake: one line, exit 130, and the frames solved so far in the result (valid, marked
    interrupted), the report and the saved .blend, whose keys give the solved joint values at every frame."""
    import os
    import signal
    import time

    from bench.long_motion import write_long_motion
    from blender_manikin.rigging.bones import RigLayout
    from solver.io.scenario.bodies import load_body

    scenario = write_long_motion(tmp_path / "long.toml", 20000)
    args = [str(blender_python), str(BATCH), "--scenario", str(scenario), "--result", "r.jsonl", "--report",
            "report.json", "--out", "cut.blend", "--export", "never.bvh"]  # fmt: skip
    env = dict(os.environ, BLENDER_USER_RESOURCES=str(user))
    proc = subprocess.Popen(args, cwd=tmp_path, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 300
    while proc.poll() is None and time.monotonic() < deadline:
        try:  # the result file before it is renamed (a folder's write probe, also .manikin-*.tmp, comes and goes)
            if max((p.read_bytes().count(b"\n") for p in tmp_path.glob(".manikin-*.tmp")), default=0) >= 4:
                break  # its header line and three frames
        except FileNotFoundError:
            pass
        time.sleep(0.05)
    assert proc.poll() is None, "finished before it could be interrupted"
    proc.send_signal(signal.SIGINT)
    stdout, stderr = proc.communicate(timeout=300)
    assert proc.returncode == 130, stdout[-3000:] + stderr[-3000:]
    assert "Traceback" not in stdout + stderr and len(stderr.strip().splitlines()) == 1, stderr
    result = read_result(tmp_path / "r.jsonl")
    kept = len(result.frames)
    assert kept >= 3 and result.interrupted["at_frame"] == kept + 1
    written = ", ".join(str(tmp_path / name) for name in ("r.jsonl", "report.json", "cut.blend"))
    assert stderr.strip() == f"interrupted at frame {kept + 1}; kept {kept} solved frames in {written}"
    report = json.loads((tmp_path / "report.json").read_text(encoding="utf-8"))
    assert [f["frame"] for f in report["frames"]] == list(range(1, kept + 1))
    assert report["interrupted"]["solved"] == kept
    assert all(f["ergonomics"]["niosh"] is not None for f in report["frames"])
    assert not (tmp_path / "never.bvh").exists() and not list(tmp_path.glob("*.tmp"))
    seen = tmp_path / "pose.json"
    done = run_python(blender_python, ["-c", POSE, tmp_path / "cut.blend", json.dumps(list(range(1, kept + 1))), seen],
                      user)  # fmt: skip
    assert done.returncode == 0, done.stderr[-3000:]
    pose = json.loads(seen.read_text(encoding="utf-8"))
    layout = RigLayout(load_body(preset="male_50"))
    for frame in result.frames:
        values = pose[str(frame.number)]
        for bone in layout.bones:
            for c in bone.channels:
                keyed = c.sign * values[f"{bone.name}.{c.prop}[{c.index}]"]
                assert keyed == pytest.approx(frame.joint_value[c.joint], abs=2e-5), (frame.number, bone.name)


SEE_THROUGH = """
import sys
from pathlib import Path
from blender_manikin.batch import load_extension
extension, _ = load_extension()
import bpy
from mathutils import Vector
picture = __import__("importlib").import_module(extension.__name__ + ".blender_manikin.motion.picture")
bpy.ops.wm.open_mainfile(filepath=sys.argv[1], load_ui=False)
hand = next(ob for ob in bpy.data.objects if ob.name == "tcp.hand_r").matrix_world.translation.copy()
inside = sorted(ob.name for ob in picture.obstacles_hiding([hand]))
open_air = [ob.name for ob in picture.obstacles_hiding([Vector((0.0, 0.6, 1.0))])]
arm = next(ob for ob in bpy.data.objects if ob.type == "ARMATURE")
picture.render_key_poses(arm, [1], Path(sys.argv[2]), size=(60, 80), samples=1)
import os
qualities = []
for draft in ("1", ""):  # what MANIKIN_RENDER_DRAFT makes of the batch's default tiles
    os.environ["MANIKIN_RENDER_DRAFT"] = draft
    qualities.append(picture.quality((300, 400), 8))
left = [ob.name for ob in bpy.data.objects if ob.name.startswith("picture.")]
hidden = [ob.name for ob in bpy.data.objects if ob.hide_render]
import json
print("RESULT", json.dumps([inside, open_air, left, hidden, qualities]))
from blender_manikin.batch import exit_process
exit_process(0)  # as batch.py ends: bpy 4.2 / 4.5 modules crash at a normal exit after a render
"""


def test_an_obstacle_hiding_a_hand_is_drawn_see_through(tmp_path: Path, blender_python: Path, user: Path) -> None:
    """The cabinet reach's picture: the right side wall stands between the camera and the hand in the compartment
    (it is drawn see-through), nothing hides a point in the open; the staging is gone after the render."""
    reach = ROOT / "presets" / "scenarios" / "cabinet_reach.toml"
    done = run_python(blender_python, [BATCH, "--scenario", reach, "--out", tmp_path / "c.blend", "-q"], user, cwd=ROOT)
    assert done.returncode == 0, done.stderr[-3000:]
    done = run_python(blender_python, ["-c", SEE_THROUGH, tmp_path / "c.blend", tmp_path / "c.png"], user, cwd=ROOT)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    line = next(line for line in done.stdout.splitlines() if line.startswith("RESULT"))
    inside, open_air, left, hidden, qualities = json.loads(line.removeprefix("RESULT"))
    assert "cabinet side right" in inside and "cabinet shelf" not in inside
    assert (open_air, left, hidden) == ([], [], [])
    assert qualities == [[[75, 100], 1], [[300, 400], 8]]  # a draft: a quarter of each side, one sample
    assert (tmp_path / "c.png").is_file()
