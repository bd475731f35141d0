"""The Export Motion operator (Motion panel, File > Export): the baked motion of the manikin to FBX, glTF or BVH.

It writes the manikin's armature with its body and, where the format holds more than one skeleton (FBX, glTF), the
carried box as its own object and animation, over the frame range of the last bake, with the settings of
:mod:`.exports`, and nothing else of the scene (targets, obstacles, cameras). The format comes from the file's
extension when it names one, else from the Format choice of the file browser.
"""

from __future__ import annotations

import os

import bpy
from bpy.props import EnumProperty, StringProperty

from ...solver.errors import ManikinError
from ..scene.schema import last_bake, rig_of

SUFFIXES = {"FBX": ".fbx", "GLB": ".glb", "GLTF": ".gltf", "BVH": ".bvh"}
FORMAT_ITEMS = (
    ("FBX", "FBX (.fbx)", "Armature, body and carried box; Blender, Unity, Unreal, MotionBuilder"),
    ("GLB", "glTF binary (.glb)", "Armature, body and carried box in one file; Blender, three.js, Unity, Unreal"),
    ("GLTF", "glTF separate (.gltf + .bin)", "As .glb, the data in a .bin beside the .gltf"),
    ("BVH", "BVH (.bvh)", "The skeleton only (one skeleton per file: no body, no box); motion-capture tools"),
)


class MANIKIN_OT_export_motion(bpy.types.Operator):
    """Export the baked motion of the manikin (armature, body, carried box) to FBX, glTF or BVH"""

    bl_idname = "manikin.export_motion"
    bl_label = "Export Motion"
    bl_options = {"REGISTER"}

    filepath: StringProperty(name="File", subtype="FILE_PATH", description="File to write (.fbx, .glb, .gltf, .bvh)")
    filter_glob: StringProperty(default="*.fbx;*.glb;*.gltf;*.bvh", options={"HIDDEN"})
    check_existing: bpy.props.BoolProperty(default=True, options={"HIDDEN"})
    format: EnumProperty(name="Format", items=FORMAT_ITEMS, default="FBX",
                         description="Used when the file name has no export extension")  # fmt: skip

    @classmethod
    def poll(cls, context: bpy.types.Context) -> bool:
        if rig_of(context.active_object) is None:
            cls.poll_message_set("Select a manikin, or one of its targets")
            return False
        if context.mode != "OBJECT":
            cls.poll_message_set("Switch to Object Mode")
            return False
        return True

    def chosen_path(self) -> str:
        """The file path, with the Format's extension added when its own names no export format."""
        path = bpy.path.abspath(self.filepath)
        return path if os.path.splitext(path)[1].lower() in SUFFIXES.values() else path + SUFFIXES[self.format]

    def check(self, context: bpy.types.Context) -> bool:
        """Keep the file name's extension in step with the Format choice (file browser)."""
        base, suffix = os.path.splitext(self.filepath)
        if suffix.lower() not in SUFFIXES.values():
            base = self.filepath
        wanted = base + SUFFIXES[self.format]
        if not base or wanted == self.filepath:
            return False
        self.filepath = wanted
        return True

    def invoke(self, context: bpy.types.Context, event: bpy.types.Event) -> set[str]:
        if not self.filepath:
            arm = rig_of(context.active_object)
            blend = bpy.data.filepath.rpartition(".")[0] if bpy.data.filepath else "//"
            self.filepath = f"{blend}_{arm.name}_motion{SUFFIXES[self.format]}".replace("//_", "//")
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}

    def execute(self, context: bpy.types.Context) -> set[str]:
        arm = rig_of(context.active_object)
        bake = last_bake(arm)
        if bake is None:
            self.report({"ERROR"}, f"{arm.name} has no baked motion: Bake Motion first")
            return {"CANCELLED"}
        if not self.filepath:
            self.report({"ERROR"}, "No file chosen")
            return {"CANCELLED"}
        from . import exports

        start, end = int(bake["frame_start"]), int(bake["frame_end"])
        try:
            path = exports.export(arm, self.chosen_path(), start, end)
        except ManikinError as exc:
            self.report({"ERROR"}, str(exc))
            return {"CANCELLED"}
        suffix = path.suffix.lower()
        box = exports.carried_box(arm) if suffix in exports.WITH_BOX else None
        what = "armature and body" + (f" and carried box {box.name}" if box is not None else "")
        self.report({"INFO"}, f"Exported frames {start}-{end} of {arm.name} ({what}) to {path.name}")
        return {"FINISHED"}


def menu_entry(menu: bpy.types.Menu, context: bpy.types.Context) -> None:
    """File > Export > Manikin Motion."""
    menu.layout.operator(MANIKIN_OT_export_motion.bl_idname, text="Manikin Motion (.fbx, .glb, .bvh)")


classes = (MANIKIN_OT_export_motion,)
MENUS = (("TOPBAR_MT_file_export", menu_entry),)
