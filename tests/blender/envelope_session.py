"""Reach envelopes in a Blender session, run by tests/blender/test_envelope_import.py in a subprocess:

    BLENDER_USER_RESOURCES=<empty dir> python tests/blender/envelope_session.py <zip> <out.json> <work dir>

envelope files written with the installed extension's own writer (numpy only), imported onto a turned manikin away
from the origin (twice: the second import replaces the first), into the world with no manikin active, as another
body's envelope (a warning), and as a broken or missing file (one-line errors). Writes what it saw to JSON; bpy is
imported here only.
"""

from __future__ import annotations

import importlib
import json
import math
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from session_tools import draw_panels, error_of, install  # noqa: E402

from blender_manikin.batch import exit_process  # noqa: E402

ZIP, OUT, WORK = Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3])
seen: dict = {}

import bpy  # noqa: E402

module = install(ZIP)
mesh_files = importlib.import_module(module + ".solver.envelope.mesh_files")
directions = importlib.import_module(module + ".solver.envelope.directions")
heavy = ("scipy", "matplotlib")


def write_files() -> None:
    """env.glb and env.obj (the same envelope: a lopsided ball and a larger sphere), other.glb (another body's)."""
    sphere = directions.direction_sphere(2)
    shoulder = [-0.19, 0.066, 1.42]
    d = sphere.directions
    balanced = mesh_files.EnvelopeMesh("balanced", shoulder + d * (0.7 + 0.2 * d[:, 1:2]), sphere.faces)
    kinematic = mesh_files.EnvelopeMesh("kinematic", shoulder + d * 1.1, sphere.faces)
    envelope = mesh_files.EnvelopeFile([balanced, kinematic], balanced.vertices[0] * 0 + shoulder,
                                       {"manikin": "male_50", "hand": "right"})  # fmt: skip
    (WORK / "env.glb").write_bytes(mesh_files.glb_bytes(envelope))
    (WORK / "env.obj").write_text(mesh_files.obj_text(envelope), encoding="utf-8")
    envelope.info["manikin"] = "female_5"
    (WORK / "other.glb").write_bytes(mesh_files.glb_bytes(envelope))
    (WORK / "bad.glb").write_bytes(b"glTF" + bytes(40))


def record(prefix: str) -> dict:
    """Every object an envelope import made whose name starts with ``prefix``: parent, display, world vertices."""
    out = {}
    for ob in bpy.data.objects:
        if ob.name.startswith(prefix) and "manikin_envelope" in ob:
            out[ob.name] = dict(
                parent=ob.parent.name if ob.parent else None, display=ob.display_type,
                vertices=[list(ob.matrix_world @ v.co) for v in ob.data.vertices],
                faces=[list(p.vertices) for p in ob.data.polygons], origin=list(ob.matrix_world.translation),
            )  # fmt: skip
    return out


write_files()
bpy.ops.object.select_all(action="DESELECT")
bpy.context.scene.cursor.location = (1.0, 0.5, 0.0)
bpy.ops.manikin.add_manikin(preset="male_50")
arm = bpy.context.active_object
arm.rotation_euler.z = math.radians(90.0)
bpy.context.view_layer.update()
seen["matrix"] = [list(row) for row in arm.matrix_world]
# what importing an envelope loads beyond a manikin in the scene (whose forward kinematics load the compiled
# kernels, and Numba's own linear algebra loads scipy's)
loaded_before = {m for m in sys.modules if m.startswith(heavy)}

seen["import"] = sorted(bpy.ops.manikin.import_envelope(filepath=str(WORK / "env.glb")))
seen["onto"] = record("env.")
bpy.context.view_layer.objects.active = arm
seen["again"] = sorted(bpy.ops.manikin.import_envelope(filepath=str(WORK / "env.glb")))
seen["after_again"] = sorted(ob.name for ob in bpy.data.objects if "manikin_envelope" in ob)
seen["heavy_loaded"] = sorted({m for m in sys.modules if m.startswith(heavy)} - loaded_before)

for ob in list(bpy.data.objects):
    if "manikin_envelope" in ob:
        bpy.data.objects.remove(ob, do_unlink=True)
bpy.ops.object.select_all(action="DESELECT")
bpy.context.view_layer.objects.active = None
seen["world_import"] = sorted(bpy.ops.manikin.import_envelope(filepath=str(WORK / "env.obj")))
seen["world"] = record("env.")

bpy.context.view_layer.objects.active = arm
seen["other"] = sorted(bpy.ops.manikin.import_envelope(filepath=str(WORK / "other.glb")))
seen["bad"] = error_of(lambda: bpy.ops.manikin.import_envelope(filepath=str(WORK / "bad.glb")))
seen["missing"] = error_of(lambda: bpy.ops.manikin.import_envelope(filepath=str(WORK / "nowhere.glb")))
seen["panel"] = []
draw_panels(importlib.import_module(module + ".blender_manikin.addon").panels(), seen["panel"])

OUT.write_text(json.dumps(seen), encoding="utf-8")
exit_process(0)
