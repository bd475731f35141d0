"""The Blender layer of Manikin: the solver's problems and results in a Blender scene, and the UI around them.

``ui/`` everything registered with Blender (operators, panels, live mode, overlay; one ``classes()`` list);
``scene/`` reading and writing the scene (``schema``: every custom property key and object name; ``compat``: every
difference between Blender 4.2, 4.5 and 5.0; armature, targets, scene <-> Problem/Result, keyframes, bake,
exports); ``rigging/`` how a solver model maps onto bones and a body mesh (NumPy, no bpy); ``headless/`` the
pipeline behind ``batch.py`` (run by Blender or the bpy module) and ``demo.py`` (``python -m
blender_manikin.demo``); ``dev/`` developer tools (build the zips, render a snapshot, time a bake), not shipped.

This file imports nothing at module level, so ``python -m blender_manikin.dev.build`` runs without bpy; enabling
the add-on loads only ``ui`` (see its docstring), neither the solver's numerics nor scipy.
"""

from __future__ import annotations


def register() -> None:
    """Register the add-on (:func:`.ui.register`)."""
    from . import ui

    ui.register()


def unregister() -> None:
    """Unregister the add-on (:func:`.ui.unregister`)."""
    from . import ui

    ui.unregister()
