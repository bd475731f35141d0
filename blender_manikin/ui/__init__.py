"""Everything Manikin registers with Blender, and the one place that registers it.

``properties`` (the settings groups on objects), ``operators`` (add a manikin, targets, loops, loads; solve;
reset), ``scenario_operators`` (import/export scenario TOML), ``envelope_operators`` (import a reach envelope),
``motion_operators`` (Bake Motion), ``panels`` (the sidebar tab and menu entries), ``live`` (re-solve while targets
move), ``overlay`` (viewport drawing), ``study_panel`` / ``study_operators`` (a population study in the background,
its table, a row loaded) and ``..retarget``'s settings, operators and panel. They import only bpy, the scene schema
and the solver's light ``errors``, ``options`` and ``presets``: the solver's numerics, scipy and the scene code
load inside ``execute``, so enabling the add-on stays fast.
"""

from __future__ import annotations

import importlib
import sys
from types import SimpleNamespace

import bpy

_MODULES = {  # name -> module, relative to this package
    name: f".{name}"
    for name in ("properties", "operators", "scenario_operators", "envelope_operators", "motion_operators", "panels",
                 "live", "overlay", "study_panel")
} | {f"retarget_{name}": f"..retarget.{name}" for name in ("properties", "operators", "panel")}  # fmt: skip


def _modules() -> SimpleNamespace:
    # Imported here, not at module level: with the submodules imported by this module's own body, bpy 4.2 (the
    # wheel) segfaults at exit after unregistering (tests/blender/matrix.py caught it; 4.5 and 5.0 do not).
    return SimpleNamespace(**{name: importlib.import_module(path, __package__) for name, path in _MODULES.items()})


def classes() -> tuple[type, ...]:
    """Every class the add-on registers, in registration order: the property groups before anything that reads
    them, panels after their operators."""
    m = _modules()
    return (
        *m.properties.classes,
        *m.retarget_properties.classes,
        *m.operators.classes,
        *m.scenario_operators.classes,
        *m.envelope_operators.classes,
        *m.motion_operators.classes,
        *m.retarget_operators.classes,
        *m.panels.classes,
        *m.retarget_panel.classes,
        *m.study_panel.classes,
    )


def register() -> None:
    """Register the classes, the object settings, the menu entries, the live-mode handler and the overlay."""
    m = _modules()
    for cls in classes():
        bpy.utils.register_class(cls)
    m.properties.attach()
    m.retarget_properties.attach()
    m.study_panel.attach()
    for menu, draw in m.panels.MENUS:
        getattr(bpy.types, menu).append(draw)
    m.live.register()
    m.overlay.register()


def unregister() -> None:
    """Remove everything :func:`register` added, in reverse order, and drop the cached models (if any loaded)."""
    m = _modules()
    m.study_panel.detach()
    m.overlay.unregister()
    m.live.unregister()
    for menu, draw in m.panels.MENUS:
        getattr(bpy.types, menu).remove(draw)
    m.retarget_properties.detach()
    m.properties.detach()
    for cls in reversed(classes()):
        bpy.utils.unregister_class(cls)
    armature = sys.modules.get(__package__.rpartition(".")[0] + ".scene.armature")
    if armature is not None:  # never imported in this session: no caches, and no reason to load the solver now
        armature.clear_caches()
