"""Everything Manikin registers with Blender, and the one place that registers it.

Each user-facing feature is a folder (``pose``, ``scenario``, ``motion``, ``study``, ``envelope``, ``retarget``)
whose registered modules each give one ``classes`` tuple and, where they need them, ``attach()`` / ``detach()``
(settings groups on Blender's types), ``MENUS`` ((menu type name, draw function) pairs) and ``register()`` /
``unregister()`` (handlers: live mode, the overlay). :data:`MODULES` lists them in registration order: the settings
groups before anything that reads them, panels after their operators. These modules import only bpy, the scene
schema and registries and the solver's light ``errors``, ``options`` and ``presets``; registering reads the obstacle
kinds' and comfort terms' registries (NumPy, no scipy: the settings are made from them); the solver's solve, scipy
and the scene code load inside ``execute``, so enabling the add-on stays fast.
"""

from __future__ import annotations

import importlib
import sys
from types import ModuleType

import bpy

MODULES = (  # relative to this package, in registration order
    "pose.properties", "retarget.properties", "study.properties", "envelope.properties",
    "operations.properties", "operations.operators",
    "pose.operators", "scenario.operators", "envelope.operators", "motion.operators", "retarget.operators",
    "motion.export_operator",
    "study.operators",
    "pose.manikins",
    "pose.panels", "motion.panel", "motion.ergonomics_panel", "retarget.panel", "study.panel", "envelope.panel",
    "operations.panel",
    "pose.live", "pose.overlay",
    "motion.job_panel",
)  # fmt: skip


def modules() -> list[ModuleType]:
    """The registered modules, imported now.

    Imported here, not at module level: with the submodules imported by this module's own body, bpy 4.2 (the wheel)
    segfaults at exit after unregistering (tests/blender/matrix.py caught it; 4.5 and 5.0 do not)."""
    return [importlib.import_module(f".{name}", __package__) for name in MODULES]


def classes() -> tuple[type, ...]:
    """Every class the add-on registers, in registration order."""
    return tuple(cls for module in modules() for cls in module.classes)


def panels() -> list[type]:
    """The add-on's panels (the sidebar tab and its subpanels), in registration order."""
    return [cls for cls in classes() if issubclass(cls, bpy.types.Panel)]


def register() -> None:
    """Register the classes, then the settings groups, the menu entries and the handlers of each module."""
    found = modules()
    for cls in classes():
        bpy.utils.register_class(cls)
    for module in found:
        if hasattr(module, "attach"):
            module.attach()
    for module in found:
        for menu, draw in getattr(module, "MENUS", ()):
            getattr(bpy.types, menu).append(draw)
    for module in found:
        if hasattr(module, "register"):
            module.register()
    from .scene import kernel_warmup  # standard library only; numba loads in the process it starts

    kernel_warmup.start_if_cold()  # the first solve after installing loads the kernels instead of compiling them


def unregister() -> None:
    """Remove everything :func:`register` added, in reverse order, and drop the cached models (if any loaded)."""
    found = modules()
    for module in reversed(found):
        if hasattr(module, "unregister"):
            module.unregister()
    for module in reversed(found):
        for menu, draw in getattr(module, "MENUS", ()):
            getattr(bpy.types, menu).remove(draw)
    for module in reversed(found):
        if hasattr(module, "detach"):
            module.detach()
    for cls in reversed(classes()):
        bpy.utils.unregister_class(cls)
    armature = sys.modules.get(f"{__package__}.scene.armature")
    if armature is not None:  # never imported in this session: no caches, and no reason to load the solver now
        armature.clear_caches()
