"""The compiled kernels inside a Blender process, on the extension's own numba and llvmlite wheels (run by
tests/blender/test_kernels.py in a subprocess):

    BLENDER_USER_RESOURCES=<empty dir> python tests/blender/kernels_session.py <zip> <out.json> <work dir> [mode]

``first`` (the default) installs the zip, imports numba after bpy and solves a moved hand through Solve Pose twice
(the first solve compiles the kernels into the cache folder), then runs itself again as three more Blender processes
on the installed extension: ``again`` (loads the cached kernels), ``numpy`` (MANIKIN_KERNELS=numpy) and ``blocked``
(numba cannot import: the add-on falls back to NumPy and says so once). The kernels' cache goes to <work>/cache
(XDG_CACHE_HOME), so the first process compiles whatever the user's own cache holds. bpy is imported here only.
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
os.environ["XDG_CACHE_HOME"] = str(WORK / "cache")  # read when the kernels decide (the first solve)
seen: dict = {"mode": MODE}


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
print("== first solve ==", flush=True)
seen["solves"] = [solve(-0.25)]
print("== second solve ==", flush=True)
seen["solves"].append(solve(-0.05))
bpy.context.view_layer.objects.active = arm
seen["panel"] = []
draw_panels([panels.MANIKIN_PT_result], seen["panel"])
seen["cached"] = {p.name: p.stat().st_mtime_ns for p in Path(seen["cache"]).rglob("*") if p.is_file()}

if MODE == "first":  # three later Blender starts on the installed extension, the same cache folder
    seen["later"] = {}
    for mode in ("again", "numpy", "blocked"):
        env = dict(os.environ, MANIKIN_KERNELS="numpy" if mode == "numpy" else "auto")
        out = WORK / f"seen_{mode}.json"
        t0 = time.perf_counter()
        done = subprocess.run([sys.executable, __file__, ZIP, out, WORK, mode], env=env, capture_output=True,
                              text=True, timeout=300)  # fmt: skip
        later = json.loads(out.read_text(encoding="utf-8")) if done.returncode == 0 else {}
        later.update(code=done.returncode, log=done.stdout[-4000:] + done.stderr[-4000:])
        later["process_s"] = time.perf_counter() - t0
        seen["later"][mode] = later

OUT.write_text(json.dumps(seen), encoding="utf-8")
exit_process(0)
