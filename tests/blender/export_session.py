"""Export Motion as a user meets it, run by tests/blender/test_export.py in a subprocess:

    BLENDER_USER_RESOURCES=<empty dir> python tests/blender/export_session.py <zip> <out.json> <work dir>

installs the extension zip, imports the box-lift motion (a manikin carrying a box), tries Export Motion before any
bake, bakes frames 3-8 with Bake Motion, exports them with Export Motion to FBX (by extension), glTF (by the Format
choice) and BVH, then re-imports each file into a fresh, empty file with the settings docs/guide/exports.md gives,
draws the panels' help buttons, and writes what it saw to JSON for test_export.py. bpy is imported here only.
"""

from __future__ import annotations

import importlib
import json
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from session_tools import error_of, install  # noqa: E402

from blender_manikin.batch import exit_process  # noqa: E402

ZIP, OUT, WORK = Path(sys.argv[1]), Path(sys.argv[2]), Path(sys.argv[3])
MOTION = ROOT / "presets" / "scenarios" / "box_lift_motion.toml"
START, END = 3, 8  # the baked range: not starting at 1, so a one-frame shift or a slide to frame 1 shows
seen: dict = {"seconds": {}}
began = time.perf_counter()

import bpy  # noqa: E402

module = install(ZIP)
addon = importlib.import_module(module + ".blender_manikin.addon")


def world(arm, box_name: str | None) -> dict[str, dict]:
    """Per baked frame: each bone head's world position, and the carried box's world position."""
    out = {}
    for frame in range(START, END + 1):
        bpy.context.scene.frame_set(frame)
        heads = {pb.name: list((arm.matrix_world @ pb.matrix).translation) for pb in arm.pose.bones}
        box = bpy.data.objects.get(box_name) if box_name else None
        out[str(frame)] = {"bones": heads, "box": list(box.matrix_world.translation) if box else None}
    return out


def key_range(ob) -> list[float]:
    """First and last keyed frame of ``ob``'s action (object and bone channels)."""
    action = ob.animation_data.action if ob.animation_data else None
    return list(action.frame_range) if action else []


class HelpLayout:
    """Records the help buttons a panel header draws (the URL each one opens)."""

    def __init__(self, urls: list) -> None:
        self.urls = urls

    def operator(self, idname: str, **kw):
        assert idname == "wm.url_open" and kw.get("icon") == "HELP", (idname, kw)
        urls = self.urls
        return type("Props", (), {"__setattr__": lambda self, name, value: urls.append(value)})()


bpy.ops.object.select_all(action="DESELECT")
bpy.ops.manikin.import_scenario(filepath=str(MOTION))
arm = bpy.context.active_object
box = next(ob for ob in bpy.data.objects if "manikin_carried" in ob)
seen["help"] = {}
for panel in addon.panels():
    urls: list = []
    if hasattr(panel, "draw_header_preset"):
        panel.draw_header_preset(type(panel.__name__, (), {"layout": HelpLayout(urls)})(), bpy.context)
    seen["help"][panel.__name__] = urls
seen["unbaked"] = error_of(lambda: bpy.ops.manikin.export_motion(filepath=str(WORK / "early.fbx")))
t = time.perf_counter()
seen["bake"] = sorted(bpy.ops.manikin.bake_motion(frame_start=START, frame_end=END))
seen["seconds"]["bake"] = time.perf_counter() - t
seen["box"] = box.name
seen["original"] = world(arm, box.name)
seen["keys_before"] = {ob.name: key_range(ob) for ob in (arm, box)}
bpy.context.scene.frame_set(20)
state = lambda: [bpy.context.scene.frame_start, bpy.context.scene.frame_end, bpy.context.scene.frame_current,  # noqa: E731
                 sorted(ob.name for ob in bpy.context.selected_objects)]  # fmt: skip
seen["state_before"] = state()
t = time.perf_counter()
calls = {
    "fbx": dict(filepath=str(WORK / "motion.fbx")),
    "glb": dict(filepath=str(WORK / "motion"), format="GLB"),  # no extension: the Format choice
    "bvh": dict(filepath=str(WORK / "motion.bvh"), format="GLB"),  # the extension wins over the Format
}
seen["export"] = {fmt: sorted(bpy.ops.manikin.export_motion(**kw)) for fmt, kw in calls.items()}
seen["seconds"]["export"] = time.perf_counter() - t
seen["files"] = sorted(p.name for p in WORK.glob("motion*"))
seen["state_after"] = state()
seen["keys_after"] = {ob.name: key_range(ob) for ob in (arm, box)}

# Each file into a fresh, empty file, imported with the settings docs/guide/exports.md gives.
IMPORTS = {
    "fbx": lambda: bpy.ops.import_scene.fbx(filepath=str(WORK / "motion.fbx")),  # Blender's defaults
    "glb": lambda: bpy.ops.import_scene.gltf(filepath=str(WORK / "motion.glb")),  # Blender's defaults
    "bvh": lambda: bpy.ops.import_anim.bvh(
        filepath=str(WORK / "motion.bvh"),
        axis_forward="Y",
        axis_up="Z",
        frame_start=START,
        use_fps_scale=False,
        update_scene_fps=False,
        update_scene_duration=False,
        rotate_mode="NATIVE",
    ),  # fmt: skip
}
t = time.perf_counter()
for fmt, call in IMPORTS.items():
    bpy.ops.wm.read_homefile(use_empty=True)
    seen[f"{fmt}_import"] = sorted(call())
    again = next(ob for ob in bpy.data.objects if ob.type == "ARMATURE")
    seen[f"{fmt}_objects"] = sorted(ob.type for ob in bpy.data.objects)
    seen[f"{fmt}_range"] = key_range(again)
    seen[fmt] = world(again, seen["box"] if seen["box"] in bpy.data.objects else None)
    boxes = [ob for ob in bpy.data.objects if ob.name == seen["box"]]
    seen[f"{fmt}_box_range"] = key_range(boxes[0]) if boxes else []
seen["seconds"]["imports"] = time.perf_counter() - t
seen["seconds"]["session"] = time.perf_counter() - began
OUT.write_text(json.dumps(seen), encoding="utf-8")
print("export session done")
exit_process(0)  # bpy 4.2 would segfault at exit after the glTF export
