"""Viewport drawing from each manikin's last result: center of mass and its floor projection, the support
polygon, contact forces and loads as arrows (FORCE_SCALE m per N). Not registered in background mode."""

from __future__ import annotations

import bpy
import gpu
from gpu_extras.batch import batch_for_shader
from mathutils import Matrix, Vector

from ..scene.schema import RESULT_KEY, is_manikin, last_result, tcp_empty

FORCE_SCALE = 0.001  # m of arrow per N: body weight (~700 N) draws about 0.7 m
COM_COLOR = (1.0, 0.85, 0.1, 1.0)
POLYGON_COLOR = (0.2, 0.9, 0.4, 1.0)
CONTACT_COLOR = (0.2, 0.6, 1.0, 1.0)
LOAD_COLOR = (1.0, 0.3, 0.2, 1.0)
MARK_SIZE = 0.03  # m, half the span of the crosses at the center of mass and below it

_handle = None
_parsed: dict[str, tuple[str, dict]] = {}  # armature name -> (JSON text, parsed), so redraws do not re-parse


def _result(arm: bpy.types.Object) -> dict | None:
    text = arm.get(RESULT_KEY)
    if not text:
        return None
    cached = _parsed.get(arm.name)
    if cached is None or cached[0] != text:
        data = last_result(arm)
        if data is None:
            return None
        _parsed[arm.name] = cached = (text, data)
    return cached[1]


def _arrow(start: Vector, vec: Vector) -> list[Vector]:
    """Line segments of an arrow from ``start`` along ``vec``: shaft and two head strokes."""
    end = start + vec
    if vec.length < 1e-6:
        return []
    side = vec.cross(Vector((1.0, 0.0, 0.0)) if abs(vec.x) < 0.9 * vec.length else Vector((0.0, 1.0, 0.0)))
    side = side.normalized() * 0.15 * vec.length
    back = -vec * 0.25
    return [start, end, end, end + back + side, end, end + back - side]


def _cross(center: Vector) -> list[Vector]:
    """Three line segments crossing at ``center``: a point mark that every Blender version's line shader draws."""
    out = []
    for axis in ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)):
        half = Vector(axis) * MARK_SIZE
        out += [center - half, center + half]
    return out


def geometry(arm: bpy.types.Object, data: dict) -> dict[str, list[Vector]]:
    """World-space line pairs to draw for a result summary: keys com, polygon, contact and load."""
    m: Matrix = arm.matrix_world
    com = Vector(data["com"])
    floor = Vector((com.x, com.y, 0.0))
    com_lines = [m @ com, m @ floor, *_cross(m @ com), *_cross(m @ floor)]
    lines: dict[str, list[Vector]] = {"com": com_lines, "polygon": [], "contact": [], "load": []}
    poly = [m @ Vector((p[0], p[1], 0.0)) for p in data.get("support_polygon", [])]
    for a, b in zip(poly, poly[1:] + poly[:1], strict=True):
        lines["polygon"] += [a, b]
    rot = m.to_3x3()
    for c in data.get("contacts", []):
        lines["contact"] += _arrow(m @ Vector(c["point"]), rot @ Vector(c["force"]) * FORCE_SCALE)
    points = {ld["tcp"]: ld for ld in data.get("loads", [])}
    for tcp, ld in points.items():
        empty = tcp_empty(arm, tcp)
        if empty is not None:
            lines["load"] += _arrow(empty.matrix_world.translation, rot @ Vector(ld["force"]) * FORCE_SCALE)
    return lines


def draw() -> None:
    """POST_VIEW draw callback: one pass over the visible manikins with the overlay on."""
    lines_shader = gpu.shader.from_builtin("POLYLINE_UNIFORM_COLOR")
    viewport = gpu.state.viewport_get()
    gpu.state.blend_set("ALPHA")
    gpu.state.depth_test_set("NONE")
    for arm in bpy.context.view_layer.objects:
        if not is_manikin(arm) or not arm.manikin.show_overlay or not arm.visible_get():
            continue
        data = _result(arm)
        if data is None:
            continue
        geo = geometry(arm, data)
        lines_shader.uniform_float("viewportSize", (viewport[2], viewport[3]))
        lines_shader.uniform_float("lineWidth", 2.0)
        for key, color in (("com", COM_COLOR), ("polygon", POLYGON_COLOR), ("contact", CONTACT_COLOR),
                           ("load", LOAD_COLOR)):  # fmt: skip
            if geo[key]:
                lines_shader.uniform_float("color", color)
                batch_for_shader(lines_shader, "LINES", {"pos": geo[key]}).draw(lines_shader)
    gpu.state.blend_set("NONE")


def register() -> None:
    global _handle
    if bpy.app.background or _handle is not None:
        return
    _handle = bpy.types.SpaceView3D.draw_handler_add(draw, (), "WINDOW", "POST_VIEW")


def unregister() -> None:
    global _handle
    if _handle is not None:
        bpy.types.SpaceView3D.draw_handler_remove(_handle, "WINDOW")
        _handle = None
    _parsed.clear()
