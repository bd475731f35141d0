"""The compiled kernels inside a Blender process, on the extension's own numba and llvmlite wheels (run by
tests/blender/test_kernels.py in a subprocess):

    BLENDER_USER_RESOURCES=<empty dir> python tests/blender/kernels_session.py <zip> <out.json> <work dir> [mode]

``first`` (the default) installs the zip with MANIKIN_WARMUP=0 (no background compile beside its own: every
kernel compiles once here), checks that enabling on this cold cache would start a warm-up and that the panels
say so while one runs (a live ``sleep`` child's id in the warm-up's marker), imports numba after bpy and solves a
moved hand through Solve Pose twice (the first solve compiles the kernels into the cache folder). It runs itself
again as four more Blender processes on the installed extension: ``warm`` (started before those solves, beside
them: an empty cache folder of its own; waits for the real warm-up enabling starts, then solves, then enables the
add-on again), and after them ``again`` (loads the cached kernels), ``numpy`` (MANIKIN_KERNELS=numpy) and
``blocked`` (numba cannot import: the add-on falls back to NumPy and says so once). The kernels' cache goes to
<work>/cache (XDG_CACHE_HOME; <work>/cache_warm for ``warm``), so the first process compiles whatever the user's
own cache holds. bpy is imported here only.
"""

from __future__ import annotations

import importlib
import importlib.abc
import json
import os
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from session_tools import draw_panels  # noqa: E402

from blender_manikin.batch import exit_process  # noqa: E402
from blender_manikin.dev.build import install  # noqa: E402

ZIP, OUT, WORK = Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3])
MODE = sys.argv[4] if len(sys.argv) > 4 else "first"
# read when the add-on is enabled (the background warm-up) and when the kernels decide (the first solve)
os.environ["XDG_CACHE_HOME"] = str(WORK / ("cache_warm" if MODE == "warm" else "cache"))
seen: dict = {"mode": MODE}
if MODE == "first":  # this process compiles in the foreground; the real warm-up is tested in ``warm``
    os.environ["MANIKIN_WARMUP"] = "0"


class NoNumba(importlib.abc.MetaPathFinder):
    """Numba (and its LLVM) fail to import, as they would where their libraries clash with Blender's."""

    def find_spec(self, name, path=None, target=None):
        if name.split(".")[0] in ("numba", "llvmlite"):
            raise ImportError(f"{name} blocked by kernels_session.py")


if MODE == "blocked":
    sys.meta_path.insert(0, NoNumba())

t0 = time.perf_counter()
import bpy  # noqa: E402

addon_utils = importlib.import_module("addon_utils")  # on the path once bpy is imported
seen["bpy_s"] = time.perf_counter() - t0
t0 = time.perf_counter()
if MODE == "first":
    module = install(ZIP)
else:  # a later Blender start: the extension is installed, its wheels extracted; enable it
    module = "bl_ext.user_default." + ZIP.name.split("-")[0]
    addon_utils.enable(module, default_set=True, refresh_handled=True)
seen["enable_s"] = time.perf_counter() - t0
kernels = importlib.import_module(module + ".solver.kernels")
panels = importlib.import_module(module + ".blender_manikin.pose.panels")
warmup = importlib.import_module(module + ".blender_manikin.scene.kernel_warmup")
seen["warmup"] = dict(decision=warmup.last_decision(), line=warmup.status_line())


def start_later(mode: str) -> tuple[str, subprocess.Popen, float]:
    """Start this script in ``mode`` as a later Blender (output to a file: a full pipe would stop it)."""
    env = dict(os.environ, MANIKIN_KERNELS="numpy" if mode == "numpy" else "auto")
    with open(WORK / f"log_{mode}.txt", "wb") as log:
        process = subprocess.Popen([sys.executable, __file__, ZIP, WORK / f"seen_{mode}.json", WORK, mode], env=env,
                                   stdout=log, stderr=subprocess.STDOUT)  # fmt: skip
    return mode, process, time.perf_counter()


def finish(mode: str, process: subprocess.Popen, t0: float) -> dict:
    """What the later Blender in ``mode`` saw, its exit code, log and wall time (s)."""
    code = process.wait(timeout=300)
    out = WORK / f"seen_{mode}.json"
    later = json.loads(out.read_text(encoding="utf-8")) if code == 0 else {}
    log = (WORK / f"log_{mode}.txt").read_text(encoding="utf-8", errors="replace")
    later.update(code=code, log=log[-8000:], process_s=time.perf_counter() - t0)
    return later


sleeper = None
if MODE == "first":  # the user's default again, for the checks below and the later processes
    del os.environ["MANIKIN_WARMUP"]
    seen["warmup"]["would"] = warmup.decide()  # "" on this cold cache: enabling would start one
    # a warm-up under way, as another Blender's: a live process's id in the marker; enabling finds it
    sleeper = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(300)"])
    marker = kernels.cache_folder() / warmup.MARKER
    marker.parent.mkdir(parents=True, exist_ok=True)
    marker.write_text(f"{sleeper.pid}\n", encoding="utf-8")
    seen["warmup"]["found"] = warmup.start_if_cold()
    # its own cache folder and its own compile (the warm-up's): beside this one's, on a second core if there is one
    warm = start_later("warm")


def wait_for_warmup() -> None:
    """Poll until the background warm-up the enabling started (if any) ends (at most 120 s); its time and log."""
    t0 = time.perf_counter()
    while warmup.running() and time.perf_counter() - t0 < 120:
        time.sleep(0.2)
    seen["warmup"].update(wait_s=time.perf_counter() - t0, running=warmup.running(), line_after=warmup.status_line())
    log = kernels.cache_folder() / warmup.LOG
    seen["warmup"]["log"] = log.read_text(encoding="utf-8", errors="replace") if log.is_file() else None


if MODE == "warm":  # wait before anything compiles a kernel here: then every kernel is loaded from the cache
    wait_for_warmup()
t0 = time.perf_counter()
seen["active"], seen["status"], seen["cache"] = kernels.active(), kernels.status(), str(kernels.cache_folder())
seen["decide_s"] = time.perf_counter() - t0  # numba imported (when it imports)
if MODE == "first":  # the add-on imported numba after bpy (Blender's own libraries loaded already): the wheel's
    import numba

    seen["numba_file"] = numba.__file__


def solve(y: float) -> dict:
    """Move the hand target ``y`` m and press Solve Pose; the summary, the wall time and the bones' channels."""
    bpy.data.objects["target.hand_r"].location.y += y
    bpy.context.view_layer.objects.active = arm
    t0 = time.perf_counter()
    done = sorted(bpy.ops.manikin.solve_pose())
    wall = time.perf_counter() - t0
    channels = [float(v) for pb in arm.pose.bones for v in (*pb.location, *pb.rotation_euler)]
    return dict(done=done, wall_s=wall, summary=json.loads(arm["manikin_result"]), channels=channels)


t0 = time.perf_counter()
bpy.ops.manikin.add_manikin(preset="male_50")  # the first forward kinematics: the kernel compiles or loads here
seen["add_s"] = time.perf_counter() - t0
arm = bpy.context.active_object
bpy.ops.manikin.add_target(tcp="hand_r")
if MODE == "first":  # the warm-up enabling found runs: the main panel says so below Solve Pose
    bpy.context.view_layer.objects.active = arm
    seen["main_panel"] = []
    draw_panels([panels.MANIKIN_PT_main], seen["main_panel"])
print("== first solve ==", flush=True)
seen["solves"] = [solve(-0.25)]
print("== second solve ==", flush=True)
seen["solves"].append(solve(-0.05))
bpy.context.view_layer.objects.active = arm
seen["panel"] = []
draw_panels([panels.MANIKIN_PT_result], seen["panel"])
seen["compile_s"] = kernels.compile_seconds()
if sleeper is not None:  # that warm-up ends (reaped: a zombie still answers kill 0); its marker stays behind
    sleeper.kill()
    sleeper.wait()
    seen["warmup"]["running"] = warmup.running()
    seen["main_panel_after"] = []
    draw_panels([panels.MANIKIN_PT_main], seen["main_panel_after"])
    marker.unlink()  # as the warm-up's own exit removes it
seen["cached"] = {p.name: p.stat().st_mtime_ns for p in Path(seen["cache"]).rglob("*") if p.is_file()}
if MODE == "warm":  # enabled again, the cache warm now: no second warm-up
    addon_utils.disable(module, default_set=True)
    addon_utils.enable(module, default_set=True, refresh_handled=True)
    again = importlib.import_module(module + ".blender_manikin.scene.kernel_warmup")
    seen["warmup"]["decision_again"] = again.last_decision()

if MODE == "first":  # three later Blender starts on the installed extension and its cache ("warm" runs already)
    seen["later"] = {mode: finish(*start_later(mode)) for mode in ("again", "numpy", "blocked")}
    seen["later"]["warm"] = finish(*warm)

OUT.write_text(json.dumps(seen), encoding="utf-8")
exit_process(0)
