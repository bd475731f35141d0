"""Every picture and plot the add-on makes, drawn in a Blender-equivalent Python with only the extension's wheels
(run by tests/blender/test_wheels.py in a subprocess):

    BLENDER_USER_RESOURCES=<empty dir> python tests/blender/wheels_session.py <zip> <out.json> <work dir>

a bake of three frames of the box lift with its ergonomics plots and key-pose picture (what batch.py runs), and a
small study (the box lift and a coarse reach envelope, one manikin) run as the sidebar runs it, with its summary
plots and its envelope picture. Records which wheels Blender installed and where matplotlib and its helpers came
from; bpy is imported here only.
"""

from __future__ import annotations

import importlib
import importlib.util
import json
import os
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from blender_manikin.batch import exit_process  # noqa: E402
from blender_manikin.dev.build import install  # noqa: E402

ZIP, OUT, WORK = Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3])
LIFT = ROOT / "presets" / "scenarios" / "box_lift_motion.toml"
STUDY = f"""
manikins = ["female_5"]

[study]
name = "wheels"

[[scenarios]]
file = "{(ROOT / "presets" / "scenarios" / "box_lift.toml").as_posix()}"
name = "lift"

[envelope]
name = "reach"
hand = "right"
load_kg = 0.0
feet = ["planted"]
frequency = 1
hemisphere = "front"
"""
seen: dict = {}

import bpy  # noqa: E402, F401

module = install(ZIP)
job = importlib.import_module(module + ".blender_manikin.motion.job")
study_job = importlib.import_module(module + ".blender_manikin.study.job")
wheels = Path(bpy.utils.user_resource("EXTENSIONS"), ".local", "lib", "python3.11", "site-packages")
seen["installed"] = sorted(p.name.split("-")[0].lower() for p in wheels.glob("*.dist-info"))
seen["found"] = {name: (spec.origin if (spec := importlib.util.find_spec(name)) else None)
                 for name in ("matplotlib", "PIL", "dateutil", "fontTools", "tzdata")}  # fmt: skip

t0 = time.perf_counter()
os.environ["MANIKIN_RENDER_DRAFT"] = "1"  # the picture is drawn with matplotlib either way: a draft's tiles will do
done = job.run(job.Job(scenario=LIFT, frames=(1, 3), picture=WORK / "poses.png", plots=WORK / "ergo", quiet=True))
seen["bake"], seen["bake_s"] = done, time.perf_counter() - t0

# The study as the sidebar's Run starts it: python -m solver study in a subprocess, on the extension's wheels.
t0 = time.perf_counter()
(WORK / "study.toml").write_text(STUDY, encoding="utf-8")
command = study_job.study_command(WORK / "study.toml", WORK / "study", 1)
done = subprocess.run(command, cwd=WORK, env=study_job.child_env(), capture_output=True, text=True, timeout=300)
seen["study"] = dict(code=done.returncode, log=done.stdout[-2000:] + done.stderr[-2000:],
                     pictures=sorted(str(p) for p in (WORK / "study").rglob("*.png")))  # fmt: skip
seen["study_s"] = time.perf_counter() - t0
HELPERS = ("matplotlib", "PIL", "dateutil", "fontTools", "tzdata", "kiwisolver", "contourpy")
seen["loaded"] = sorted(m for m in sys.modules if m in HELPERS)

OUT.write_text(json.dumps(seen), encoding="utf-8")
exit_process(0)
