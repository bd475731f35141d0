"""Viewport drawing from each manikin's last result: center of mass and its floor projection, the support
polygon, contact forces and loads as arrows (FORCE_SCALE m per N), and for each clearance pair within its margin a
line between the two nearest surface points with the distance in mm (red below its clearance) - all with the
manikin's Overlay toggle; its collision capsules as wire outlines with its Capsules toggle. Lines are drawn after
the scene (POST_VIEW), the distances as text over it (POST_PIXEL). Not registered in background mode."""

from __future__ import annotations

import math

import blf
import bpy
import gpu
from bpy_extras.view3d_utils import location_3d_to_region_2d
from gpu_extras.batch import batch_for_shader
from mathutils import Matrix, Vector

from ..scene.schema import RESULT_KEY, is_manikin, last_result, tcp_empty

classes: tuple[type, ...] = ()  # nothing registered as a class: draw handlers

FORCE_SCALE = 0.001  # m of arrow per N: body weight (~700 N) draws about 0.7 m
COM_COLOR = (1.0, 0.85, 0.1, 1.0)
POLYGON_COLOR = (0.2, 0.9, 0.4, 1.0)
CONTACT_COLOR = (0.2, 0.6, 1.0, 1.0)
LOAD_COLOR = (1.0, 0.3, 0.2, 1.0)
NEAR_COLOR = (0.95, 0.95, 0.95, 1.0)  # a clearance pair within its margin
BELOW_COLOR = (1.0, 0.15, 0.1, 1.0)  # a pair below its clearance
CAPSULE_COLOR = (0.3, 0.85, 1.0, 0.7)
MARK_SIZE = 0.03  # m, half the span of the crosses at the center of mass and below it
CIRCLE_STEPS = 16  # segments of a capsule's end circles (half as many on its end caps' arcs)
TEXT_SIZE = 12  # px at a UI scale of 1
FONT = 0  # Blender's default font
OVERLAY_KEYS = ("com", "polygon", "contact", "load", "near", "below")  # drawn with the Overlay toggle
COLORS = dict(com=COM_COLOR, polygon=POLYGON_COLOR, contact=CONTACT_COLOR, load=LOAD_COLOR, near=NEAR_COLOR,
              below=BELOW_COLOR, capsules=CAPSULE_COLOR)  # fmt: skip

_handles: list[tuple[object, str]] = []  # (draw handler, its region type)
_parsed: dict[str, tuple[str, dict]] = {}  # armature name -> (JSON text, parsed), so redraws do not re-parse
_wires: dict[str, tuple[dict, tuple, list]] = {}  # armature name -> (parsed result, its matrix, capsule wires)


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


def _arc(center: Vector, u: Vector, v: Vector, radius: float, turn: float, steps: int) -> list[Vector]:
    """Line pairs along the arc center + radius (cos t u + sin t v), t from 0 to ``turn`` rad."""
    points = [center + radius * (math.cos(turn * i / steps) * u + math.sin(turn * i / steps) * v)
              for i in range(steps + 1)]  # fmt: skip
    return [p for a, b in zip(points, points[1:], strict=False) for p in (a, b)]


def capsule_wire(start: Vector, end: Vector, radius: float) -> list[Vector]:
    """Line pairs outlining a capsule: a circle round each end, four lines along it and two half circles over each
    end cap."""
    axis = end - start
    z = axis.normalized() if axis.length > 1e-9 else Vector((0.0, 0.0, 1.0))
    x = z.orthogonal().normalized()
    y = z.cross(x)
    lines = []
    for center, out in ((start, -z), (end, z)):
        lines += _arc(center, x, y, radius, 2.0 * math.pi, CIRCLE_STEPS)
        lines += _arc(center, x, out, radius, math.pi, CIRCLE_STEPS // 2)
        lines += _arc(center, y, out, radius, math.pi, CIRCLE_STEPS // 2)
    for side in (x, y, -x, -y):
        lines += [start + radius * side, end + radius * side]
    return lines


def geometry(arm: bpy.types.Object, data: dict, capsules: bool = True) -> dict[str, list[Vector]]:
    """World-space line pairs to draw for a result summary: keys com, polygon, contact, load, near (clearance
    pairs within their margin), below (those below their clearance) and capsules (the body's, as wires; left
    empty without ``capsules``)."""
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
    lines["near"], lines["below"] = [], []
    for pair in drawn_pairs(data):
        lines["below" if pair.get("below") else "near"] += [m @ Vector(pair["point"]), m @ Vector(pair["other_point"])]
    lines["capsules"] = _capsule_lines(arm, data) if capsules else []
    return lines


def _capsule_lines(arm: bpy.types.Object, data: dict) -> list[Vector]:
    """The capsules' wires, remembered while the result and the armature's place stay (a few ms to make)."""
    m: Matrix = arm.matrix_world
    place = tuple(tuple(row) for row in m)
    cached = _wires.get(arm.name)
    if cached is not None and cached[0] is data and cached[1] == place:
        return cached[2]
    lines = []
    for c in data.get("capsules", []):
        lines += capsule_wire(m @ Vector(c["start"]), m @ Vector(c["end"]), c["radius"])
    _wires[arm.name] = (data, place, lines)  # holding ``data`` keeps its identity from being reused
    return lines


def drawn_pairs(data: dict) -> list[dict]:
    """The clearance pairs the overlay draws: every one with the floor, an obstacle or the carried box within the
    margin, and a pair of two body parts only when it is below its clearance (an arm resting on the trunk sits at
    its allowed, often negative, distance: drawn, it would crowd the hips with numbers that are no fault)."""
    return [pair for pair in data.get("closest", []) if pair.get("below") or not pair.get("body")]


def labels(arm: bpy.types.Object, data: dict) -> list[tuple[Vector, str, tuple[float, ...]]]:
    """(world point, text, colour) of each clearance pair's distance: mm, at the middle of its line."""
    m: Matrix = arm.matrix_world
    out = []
    for pair in drawn_pairs(data):
        middle = m @ ((Vector(pair["point"]) + Vector(pair["other_point"])) / 2.0)
        out.append((middle, f"{round(1e3 * pair['distance']):d} mm", BELOW_COLOR if pair.get("below") else NEAR_COLOR))
    return out


def shown(arm: bpy.types.Object) -> tuple[str, ...]:
    """The keys of :func:`geometry` that ``arm``'s toggles show."""
    settings = arm.manikin
    return (OVERLAY_KEYS if settings.show_overlay else ()) + (("capsules",) if settings.show_capsules else ())


def _drawn_manikins() -> list[tuple[bpy.types.Object, dict]]:
    """(armature, last result) of every visible manikin with something to draw."""
    out = []
    for arm in bpy.context.view_layer.objects:
        if is_manikin(arm) and arm.visible_get() and shown(arm):
            data = _result(arm)
            if data is not None:
                out.append((arm, data))
    return out


def draw() -> None:
    """POST_VIEW draw callback: the lines of every visible manikin with a toggle on."""
    lines_shader = gpu.shader.from_builtin("POLYLINE_UNIFORM_COLOR")
    viewport = gpu.state.viewport_get()
    gpu.state.blend_set("ALPHA")
    gpu.state.depth_test_set("NONE")
    for arm, data in _drawn_manikins():
        keys = shown(arm)
        geo = geometry(arm, data, "capsules" in keys)
        lines_shader.uniform_float("viewportSize", (viewport[2], viewport[3]))
        lines_shader.uniform_float("lineWidth", 2.0)
        for key in keys:
            if geo[key]:
                lines_shader.uniform_float("color", COLORS[key])
                batch_for_shader(lines_shader, "LINES", {"pos": geo[key]}).draw(lines_shader)
    gpu.state.blend_set("NONE")


def draw_labels(region: bpy.types.Region | None = None, view: bpy.types.RegionView3D | None = None) -> None:
    """POST_PIXEL draw callback: the distances of the clearance pairs, beside their lines (``region`` and ``view``:
    the context's, unless given)."""
    region = bpy.context.region if region is None else region
    view = bpy.context.region_data if view is None else view
    if region is None or view is None:
        return
    blf.size(FONT, TEXT_SIZE * bpy.context.preferences.system.ui_scale)
    for arm, data in _drawn_manikins():
        if not arm.manikin.show_overlay:
            continue
        for point, text, color in labels(arm, data):
            xy = location_3d_to_region_2d(region, view, point)
            if xy is not None:  # None: behind the viewer
                blf.color(FONT, *color)
                blf.position(FONT, xy.x + 4.0, xy.y + 4.0, 0.0)
                blf.draw(FONT, text)


def add_handlers() -> None:
    """Add the draw callbacks to the 3D view (once)."""
    if not _handles:
        _handles.append((bpy.types.SpaceView3D.draw_handler_add(draw, (), "WINDOW", "POST_VIEW"), "WINDOW"))
        _handles.append((bpy.types.SpaceView3D.draw_handler_add(draw_labels, (), "WINDOW", "POST_PIXEL"), "WINDOW"))


def remove_handlers() -> None:
    """Remove what :func:`add_handlers` added."""
    while _handles:
        handle, region_type = _handles.pop()
        bpy.types.SpaceView3D.draw_handler_remove(handle, region_type)


def register() -> None:
    if not bpy.app.background:
        add_handlers()


def unregister() -> None:
    remove_handlers()
    _parsed.clear()
    _wires.clear()
