"""Helpers of the session scripts (run by Blender-equivalent Pythons, next to this file on their path)."""

from __future__ import annotations

from functools import cache
from pathlib import Path


def install(zip_path: Path, repo: str = "user_default") -> str:
    """The add-on enabled as ``blender_manikin.dev.build.install`` leaves it; its module name. The test's user
    folder is a copy of one the zip was installed into (tests/blender/conftest.py): enable it there, as Blender
    does at start-up for an enabled extension (its wheels are in place). In an empty user folder: install the zip."""
    import addon_utils
    import bpy

    manifest_id = zip_path.name.split("-")[0]
    if not Path(bpy.utils.user_resource("EXTENSIONS"), repo, manifest_id).is_dir():
        from blender_manikin.dev.build import install as install_zip

        return install_zip(zip_path, repo)
    module = f"bl_ext.{repo}.{manifest_id}"
    addon_utils.enable(module, default_set=True, handle_error=lambda exc: print(f"enabling {module}: {exc!r}"))
    if module not in bpy.context.preferences.addons:
        raise RuntimeError(f"{module} is installed in the user folder but did not enable")
    return module


def error_of(call) -> str:
    """The error an operator reported (a script sees an ERROR report as RuntimeError), or "" if none."""
    try:
        call()
    except RuntimeError as exc:
        return str(exc)
    return ""


@cache
def icons() -> frozenset[str]:
    """The icon names this Blender knows."""
    import bpy

    return frozenset(bpy.types.UILayout.bl_rna.functions["label"].parameters["icon"].enum_items.keys())


class Layout:
    """Stands in for UILayout; fails on unknown properties, operators or icons."""

    def __init__(self, log: list) -> None:
        self.log = log

    def _icon(self, kw: dict) -> None:
        assert kw.get("icon", "NONE") in icons(), kw["icon"]

    def row(self, **kw) -> Layout:
        return Layout(self.log)

    column = box = split = row

    def label(self, text: str = "", **kw) -> None:
        self._icon(kw)
        self.log.append(text)

    def prop(self, data, name: str, **kw) -> None:
        assert name in data.bl_rna.properties, name
        self._icon(kw)

    def operator(self, idname: str, **kw) -> object:
        import bpy

        group, name = idname.split(".")
        assert hasattr(getattr(bpy.ops, group), name), idname
        self._icon(kw)
        return type("OperatorProperties", (), {})()  # a panel may set the button's properties

    def separator(self, **kw) -> None:
        pass

    def operator_menu_enum(self, idname: str, prop: str, **kw) -> None:
        self.operator(idname, **kw)

    def prop_search(self, data, name: str, search_data, search_name: str, **kw) -> None:
        assert name in data.bl_rna.properties and search_name in search_data.bl_rna.properties, (name, search_name)
        self._icon(kw)

    def template_list(self, list_type: str, list_id: str, data, name: str, active_data, active_name: str, **kw) -> None:
        import bpy

        assert hasattr(bpy.types, list_type), list_type
        assert name in data.bl_rna.properties and active_name in active_data.bl_rna.properties, (name, active_name)


def draw_panels(panels, log: list) -> None:
    """Draw every panel whose poll passes in the current context into a recording :class:`Layout`."""
    import bpy

    for panel in panels:
        if not hasattr(panel, "poll") or panel.poll(bpy.context):
            panel.draw(type("Panel", (), {"layout": Layout(log)})(), bpy.context)


class GpuRecorder:
    """Stands in for the ``gpu`` module and ``batch_for_shader`` (background mode draws nothing): records the
    builtin shaders asked for (``asked``) and each batch drawn as (its colour uniform, its vertex count)."""

    def __init__(self) -> None:
        self.asked: list[str] = []
        self.drawn: list[tuple[tuple | None, int]] = []
        recorder = self

        class Shader:
            color: tuple | None = None

            def uniform_float(self, name: str, value) -> None:
                if name == "color":
                    self.color = tuple(value)

        class shader:  # noqa: N801  (mirrors gpu.shader)
            @staticmethod
            def from_builtin(name: str) -> Shader:
                recorder.asked.append(name)
                return Shader()

        class state:  # noqa: N801  (mirrors gpu.state)
            viewport_get = staticmethod(lambda: (0, 0, 800, 600))
            blend_set = depth_test_set = point_size_set = staticmethod(lambda value: None)

        self.gpu = type("gpu", (), {"shader": shader, "state": state})

    def batch_for_shader(self, shader, kind: str, data: dict):
        """A batch whose ``draw`` records the shader's colour and the vertex count."""
        recorder = self

        class Batch:
            def draw(self, used) -> None:
                recorder.drawn.append((used.color, len(data["pos"])))

        return Batch()
