"""F-curves in bulk (bpy): one action per object, keys replaced over a frame range with ``foreach_set``.

Where the F-curves live differs between Blender versions (:mod:`.compat`). Writing keys never calls
``keyframe_insert``: the existing keys are read with ``foreach_get``, the ones inside the new range dropped, and
all of them written back at once.
"""

from __future__ import annotations

import bpy
import numpy as np

from .compat import ensure_fcurve, object_fcurves

# Per-key attributes kept for the keys outside the replaced range: name -> (values per key, dtype).
_FLOATS = {"co": 2, "handle_left": 2, "handle_right": 2, "back": 1, "amplitude": 1, "period": 1}
_ENUMS = ("interpolation", "handle_left_type", "handle_right_type", "easing", "type")
_BOOLS = ("select_control_point", "select_left_handle", "select_right_handle")
_NEW_KEY = dict(interpolation="LINEAR", handle_left_type="AUTO_CLAMPED", handle_right_type="AUTO_CLAMPED",
                easing="AUTO", type="KEYFRAME")  # fmt: skip


def _enum_value(prop: str, identifier: str) -> int:
    return bpy.types.Keyframe.bl_rna.properties[prop].enum_items[identifier].value


def ensure_action(obj: bpy.types.ID, name: str | None = None) -> bpy.types.Action:
    """The object's action, created (``<name>Action``) and assigned if it has none."""
    anim = obj.animation_data or obj.animation_data_create()
    if anim.action is None:
        anim.action = bpy.data.actions.new(name or f"{obj.name}Action")
    return anim.action


def fcurve(obj: bpy.types.ID, data_path: str, index: int = 0, group: str = "") -> bpy.types.FCurve:
    """The F-curve animating ``obj.<data_path>[index]`` in the object's action (both made when missing)."""
    return ensure_fcurve(obj, ensure_action(obj), data_path, index, group)


def key_frames(obj: bpy.types.ID) -> list[float]:
    """Sorted frames at which any of the object's F-curves has a key."""
    frames: set[float] = set()
    for fc in object_fcurves(obj):
        co = np.empty(2 * len(fc.keyframe_points))
        fc.keyframe_points.foreach_get("co", co)
        frames.update(co[0::2].tolist())
    return sorted(frames)


def _read_keys(points: bpy.types.FCurveKeyframePoints) -> dict[str, np.ndarray]:
    n = len(points)
    data: dict[str, np.ndarray] = {}
    for name, size in _FLOATS.items():
        data[name] = np.empty(n * size, dtype=np.float32)
        points.foreach_get(name, data[name])
    for name in _ENUMS:
        data[name] = np.empty(n, dtype=np.int32)
        points.foreach_get(name, data[name])
    for name in _BOOLS:
        data[name] = np.empty(n, dtype=bool)
        points.foreach_get(name, data[name])
    return data


def without_flat_runs(frames: np.ndarray, values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The keys left when the inner keys of each run of equal values are dropped: linear interpolation between the
    run's first and last key gives exactly the same curve (the values are compared as stored, single precision)."""
    values = np.asarray(values, dtype=np.float32)
    keep = np.ones(len(values), dtype=bool)
    keep[1:-1] = (values[1:-1] != values[:-2]) | (values[1:-1] != values[2:])
    return np.asarray(frames)[keep], values[keep]


def replace_keys(fc: bpy.types.FCurve, frames: np.ndarray, values: np.ndarray, thin: bool = False) -> None:
    """Key ``values`` at ``frames`` (linear interpolation); keys between the first and last frame are replaced,
    keys outside that range keep everything (value, handles, interpolation, easing, selection). ``thin``: leave
    out the inner keys of runs of equal values (:func:`without_flat_runs`; the same curve with fewer keys)."""
    frames = np.asarray(frames, dtype=np.float32)
    span = (frames.min(), frames.max())
    if thin:
        frames, values = without_flat_runs(frames, values)
    co = np.column_stack([frames, np.asarray(values, dtype=np.float32)]).ravel()
    points = fc.keyframe_points
    kept: dict[str, np.ndarray] = {}
    if len(points):
        old = _read_keys(points)
        x = old["co"][0::2]
        keep = (x < span[0] - 1e-4) | (x > span[1] + 1e-4)
        kept = {k: v.reshape(len(x), -1)[keep].ravel() for k, v in old.items()}
        points.clear()
    n_old = len(kept["co"]) // 2 if kept else 0
    points.add(n_old + len(frames))
    if not kept:  # new keys only: Blender's defaults stay as they are, only ours are written
        for name in ("co", "handle_left", "handle_right"):
            points.foreach_set(name, co)
        for name, identifier in _NEW_KEY.items():
            points.foreach_set(name, np.full(len(frames), _enum_value(name, identifier), dtype=np.int32))
        fc.update()
        return
    data = _read_keys(points)  # Blender's defaults for new keys (easing amplitude, period, ...)
    for name, array in data.items():
        size = len(array) // (n_old + len(frames))
        if kept:
            array[: n_old * size] = kept[name]
        if name in ("co", "handle_left", "handle_right"):
            array[n_old * size :] = co
        elif name in _NEW_KEY:
            array[n_old:] = _enum_value(name, _NEW_KEY[name])
        points.foreach_set(name, array)
    fc.update()  # sorts the keys by frame and recomputes automatic handles
