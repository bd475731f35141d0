"""The Blender layer of Manikin (bpy only: scene <-> solver translation, operators, panels, handlers).

Modules: ``schema`` (every custom property key and object prefix, and the lookups that find a manikin's parts),
``compat`` (every difference between Blender 4.2, 4.5 and 5.0), ``rig`` and ``body_mesh`` (how a solver model maps
onto bones and a visible body, plain NumPy),
``armature`` (building the rig, writing and reading poses), ``targets`` (the empties a user moves),
``scene_io`` (empties -> solver Problem, Result -> pose), ``props``, ``operators``, ``io_operators``,
``panels`` (UI), ``live`` (re-solve on change) and ``overlay`` (viewport drawing); motions: ``keyframes`` (bulk
F-curves), ``bake`` and ``motion_operators`` (Bake Motion), ``motion_io`` (keyed targets <-> scenario keys),
``exports``, ``picture``, ``motion_report`` and ``job`` (the headless pipeline behind ``batch.py`` and ``demo``);
``build`` packages the extension (one zip per platform with its wheels), ``snapshot`` renders a picture headless
and ``bench`` times a bake. This file imports nothing at module level, so ``python -m blender_manikin.build`` runs
without bpy; the registered modules import only bpy, ``schema`` and the solver's light ``errors``, ``options`` and
``presets``, so enabling loads neither the solver nor scipy.
"""

from __future__ import annotations

from types import ModuleType


def _modules() -> tuple[ModuleType, ...]:
    from . import io_operators, live, motion_operators, operators, overlay, panels, props

    return props, operators, io_operators, motion_operators, panels, live, overlay


def register() -> None:
    """Register properties, operators, panels, the live-mode handler and the viewport overlay."""
    import bpy

    props, operators, io_operators, motion_operators, panels, live, overlay = _modules()
    props.register()
    for cls in operators.classes + io_operators.classes + motion_operators.classes + panels.classes:
        bpy.utils.register_class(cls)
    for menu, draw in panels.MENUS:
        getattr(bpy.types, menu).append(draw)
    live.register()
    overlay.register()


def unregister() -> None:
    """Remove everything :func:`register` added, in reverse order."""
    import bpy

    from . import armature

    props, operators, io_operators, motion_operators, panels, live, overlay = _modules()
    overlay.unregister()
    live.unregister()
    for menu, draw in panels.MENUS:
        getattr(bpy.types, menu).remove(draw)
    for cls in reversed(operators.classes + io_operators.classes + motion_operators.classes + panels.classes):
        bpy.utils.unregister_class(cls)
    props.unregister()
    armature.clear_caches()
