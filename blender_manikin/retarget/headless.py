"""The batch script's ``--retarget NAME`` (bpy): a shipped rig built beside the baked manikin, or an armature of
the opened .blend, keyed with the baked motion; checked before the bake, so a bad name never costs one."""

from __future__ import annotations

import bpy

from ...solver.errors import UsageError
from ...solver.retarget.bone_map import REQUIRED, SHIPPED_RIGS
from .motion import Summary, check_target, retarget


def check_name(name: str, manikin: bpy.types.Object) -> None:
    """UsageError unless ``name`` is a shipped rig or an armature (not a manikin) in the scene and the manikin is
    a human (has the bones a bone map needs)."""
    missing = [b for b in REQUIRED if b not in manikin.data.bones]
    if missing:
        raise UsageError(f"--retarget {name}: '{manikin.name}' is not a human manikin (no bone {missing[0]})")
    if name in SHIPPED_RIGS:
        return
    target = bpy.context.scene.objects.get(name)
    if target is None:
        raise UsageError(f"--retarget {name}: no shipped rig or object of that name in the scene "
                         f"(shipped rigs: {', '.join(SHIPPED_RIGS)})")  # fmt: skip
    try:
        check_target(target)
    except UsageError as exc:
        raise UsageError(f"--retarget {name}: {exc}") from None


def retarget_named(name: str, manikin: bpy.types.Object, frames: tuple[int, int]) -> tuple[bpy.types.Object, Summary]:
    """Build the shipped rig ``name`` (or take the scene's armature of that name), retarget ``manikin``'s baked
    ``frames`` onto it; (the target, what was done)."""
    if name in SHIPPED_RIGS:
        from .armatures import add_shipped_rig

        target = add_shipped_rig(bpy.context, manikin, name)
    else:
        target = bpy.context.scene.objects[name]
        target.manikin_retarget.source = manikin
    return target, retarget(bpy.context.scene, target, frames)
