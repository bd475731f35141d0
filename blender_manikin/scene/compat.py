"""Every difference between the Blender versions we support (4.2 LTS, 4.5 LTS, 5.0), in one place (bpy).

Each function tests for the feature it uses, not for a version number:

- Animation: 4.2-4.3 keep F-curves in ``Action.fcurves``; 4.4+ keep them in a channelbag per action slot, reached
  with ``Action.fcurve_ensure_for_datablock``, which takes ``group_name`` only from 5.0 on (4.4-4.5 set the group
  on the channelbag); 5.0 dropped ``Action.fcurves``.
- Operators such as the exporters gain and rename options between versions: only the known ones are passed.
- Materials: before 5.0 a new material has no node tree until ``use_nodes`` is set.
- Cycles' denoiser (OpenImageDenoise) is in the official builds and the bpy wheels of 4.2-5.0 (x86-64 and Apple
  Silicon), but a build may lack it: ``denoiser_available`` asks Cycles.
- The viewport overlay draws with ``POLYLINE_UNIFORM_COLOR`` only, the one line shader every version has
  (``POINT_UNIFORM_COLOR`` is missing in 4.2), so it needs no fallback.
"""

from __future__ import annotations

from functools import cache

import bpy


@cache  # the running Blender does not change: one look per session, not one per keyed channel
def _ensure_parameters() -> tuple[str, ...] | None:
    """Parameter names of ``Action.fcurve_ensure_for_datablock``, or None where it does not exist (4.2-4.3)."""
    function = bpy.types.Action.bl_rna.functions.get("fcurve_ensure_for_datablock")
    return None if function is None else tuple(function.parameters.keys())


def _channelbag(obj: bpy.types.ID, action: bpy.types.Action):
    """The channelbag of the object's slot in ``action`` (4.4+), or None."""
    slot = getattr(obj.animation_data, "action_slot", None)
    if slot is None or not hasattr(action, "layers"):
        return None
    for layer in action.layers:
        for strip in layer.strips:
            bag = strip.channelbag(slot) if hasattr(strip, "channelbag") else None
            if bag is not None:
                return bag
    return None


def ensure_fcurve(obj: bpy.types.ID, action: bpy.types.Action, data_path: str, index: int, group: str):
    """The F-curve of ``obj.<data_path>[index]`` in ``action`` (assigned to ``obj``), made in ``group`` if missing."""
    parameters = _ensure_parameters()
    if parameters is None:
        found = action.fcurves.find(data_path, index=index)
        return found or action.fcurves.new(data_path, index=index, action_group=group)
    if "group_name" in parameters:
        return action.fcurve_ensure_for_datablock(obj, data_path, index=index, group_name=group)
    fc = action.fcurve_ensure_for_datablock(obj, data_path, index=index)
    if group and (fc.group is None or fc.group.name != group):
        bag = _channelbag(obj, action)
        if bag is not None:
            fc.group = bag.groups.get(group) or bag.groups.new(group)
    return fc


def object_fcurves(obj: bpy.types.ID) -> list:
    """The F-curves animating ``obj``: its slot's channelbag (4.4+), or the action's list (4.2-4.3)."""
    anim = obj.animation_data
    if anim is None or anim.action is None:
        return []
    bag = _channelbag(obj, anim.action)
    if bag is not None:
        return list(bag.fcurves)
    return list(getattr(anim.action, "fcurves", ()))


def call_known(operator, **settings) -> set[str]:
    """Call ``operator`` with those of ``settings`` this Blender version knows (names change between versions)."""
    known = operator.get_rna_type().properties.keys()
    return operator(**{k: v for k, v in settings.items() if k in known})


def node_tree(material: bpy.types.Material) -> bpy.types.NodeTree:
    """The material's node tree (created with the Principled BSDF where Blender < 5 made the material without)."""
    if material.node_tree is None:
        material.use_nodes = True
    return material.node_tree


@cache
def denoiser_available() -> bool:
    """Whether this Blender's Cycles has OpenImageDenoise (renders then take few samples and are denoised)."""
    try:
        import _cycles  # Cycles' own module, there once the add-on is loaded (at startup)
    except ImportError:
        return False
    return bool(getattr(_cycles, "with_openimagedenoise", False))
