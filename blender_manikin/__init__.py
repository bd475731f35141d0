"""The Blender layer of Manikin: the solver's problems and results in a Blender scene, and the UI around them.

One folder per user-facing feature, each with its settings, operators, panel and the functions its operators and
the headless scripts call alike: ``pose/`` (add a manikin, targets, solve, live mode, the overlay), ``scenario/``
(scenario files in and out), ``motion/`` (bake, exports, and the headless pipeline behind ``batch.py`` and
``demo.py``), ``study/`` (a population study in the background), ``envelope/`` (reach envelopes as objects),
``retarget/`` (a baked motion onto other armatures). ``scene/`` holds the bpy adapters they share (``schema``:
every custom property key and object name; ``compat``: every difference between Blender 4.2, 4.5 and 5.0;
armature, targets, scene <-> Problem/Result, keyframes, obstacles); ``rigging/`` how a solver model maps onto bones
and a body mesh (NumPy, no bpy). ``addon.py`` is the one place that registers everything. ``batch.py`` (run by
Blender or the bpy module) and ``demo.py`` (``python -m blender_manikin.demo``) run the headless pipeline; ``dev/``
holds developer tools (build the zips, render a snapshot, prepare the body mesh), not shipped. Imports point down:
features -> ``scene`` -> ``rigging`` (pyproject.toml's import contract).

This file imports nothing at module level, so ``python -m blender_manikin.dev.build`` runs without bpy; enabling
the add-on loads only the registered modules and the registries they read (see ``addon.py``), not scipy.
"""

from __future__ import annotations


def register() -> None:
    """Register the add-on (:func:`.addon.register`)."""
    from . import addon

    addon.register()


def unregister() -> None:
    """Unregister the add-on (:func:`.addon.unregister`)."""
    from . import addon

    addon.unregister()
