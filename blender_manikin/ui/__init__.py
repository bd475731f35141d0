"""Everything Manikin registers with Blender, and the one place that registers it.

``properties`` (the settings groups on objects), ``operators`` (add a manikin, targets, loops, loads; solve;
reset), ``scenario_operators`` (import/export scenario TOML), ``motion_operators`` (Bake Motion), ``panels`` (the
sidebar tab and menu entries), ``live`` (re-solve while targets move), ``overlay`` (viewport drawing) and
``..retarget``'s settings, operators and panel. They import only bpy, the scene schema and the solver's light
``errors``, ``options`` and ``presets``: the solver's numerics, scipy and the scene code load inside ``execute``, so
enabling the add-on stays fast.
"""

from __future__ import annotations

import sys
from types import ModuleType

import bpy


def _modules() -> tuple[ModuleType, ...]:
    # Imported here, not at module level: with the submodules imported by this module's own body, bpy 4.2 (the
    # wheel) segfaults at exit after unregistering (tests/blender/matrix.py caught it; 4.5 and 5.0 do not).
    from . import live, motion_operators, operators, overlay, panels, properties, scenario_operators

    return properties, operators, scenario_operators, motion_operators, panels, live, overlay


def _retarget() -> tuple[ModuleType, ModuleType, ModuleType]:
    from ..retarget import operators, panel, properties

    return properties, operators, panel


def classes() -> tuple[type, ...]:
    """Every class the add-on registers, in registration order: the property groups before anything that reads
    them, panels after their operators."""
    properties, operators, scenario_operators, motion_operators, panels, _, _ = _modules()
    retarget_properties, retarget_operators, retarget_panel = _retarget()
    return (
        *properties.classes,
        *retarget_properties.classes,
        *operators.classes,
        *scenario_operators.classes,
        *motion_operators.classes,
        *retarget_operators.classes,
        *panels.classes,
        *retarget_panel.classes,
    )


def register() -> None:
    """Register the classes, the object settings, the menu entries, the live-mode handler and the overlay."""
    properties, _, _, _, panels, live, overlay = _modules()
    for cls in classes():
        bpy.utils.register_class(cls)
    properties.attach()
    _retarget()[0].attach()
    for menu, draw in panels.MENUS:
        getattr(bpy.types, menu).append(draw)
    live.register()
    overlay.register()


def unregister() -> None:
    """Remove everything :func:`register` added, in reverse order, and drop the cached models (if any loaded)."""
    properties, _, _, _, panels, live, overlay = _modules()
    overlay.unregister()
    live.unregister()
    for menu, draw in panels.MENUS:
        getattr(bpy.types, menu).remove(draw)
    properties.detach()
    _retarget()[0].detach()
    for cls in reversed(classes()):
        bpy.utils.unregister_class(cls)
    armature = sys.modules.get(__package__.rpartition(".")[0] + ".scene.armature")
    if armature is not None:  # never imported in this session: no caches, and no reason to load the solver now
        armature.clear_caches()
