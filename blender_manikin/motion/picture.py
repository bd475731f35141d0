"""A picture of key poses of a baked motion (bpy + matplotlib, a wheel of the extension): small Cycles CPU renders
side by side.

Every pose is rendered by the same orthographic camera, a view from the manikin's right side (a little from the
front and above) framed on the body, the obstacles and the carried box over all shown frames, so the poses compare
at one scale. The scene's obstacles and its carried box (:mod:`..scene.carried_object`, keyed with the hands) are
rendered as they are, but an obstacle standing between the camera and a hand is drawn see-through (a hand in a
cabinet's compartment shows through its side wall); without a carried box, a load held by both hands is drawn as a
box between the palms. The tiles are put side by side with a caption each by matplotlib. The staging (floor,
lights, camera, box, see-through copies) is removed again and the render settings restored.
"""

from __future__ import annotations

import os
import tempfile
import textwrap
from pathlib import Path

import bpy
import numpy as np
from mathutils import Matrix, Vector

from ..scene.carried_object import find_carried
from ..scene.compat import denoiser_available, node_tree
from ..scene.registries import obstacle_kind
from ..scene.schema import (
    OUR_MATERIALS,
    PICTURE_COLLECTION,
    PICTURE_PREFIX,
    SHADED_KEY,
    is_obstacle,
    members,
    tcp_empty,
)
from .written import written_by_path

VIEW = Vector((-1.5, -0.55, 0.45)).normalized()  # from the body towards the camera: right side, a bit to the front
BOX_DEPTH, BOX_HEIGHT = 0.32, 0.24  # m, the drawn box (its width is the distance between the palms)
MARGIN = 1.12
HANDS = ("hand_l", "hand_r")  # the TCPs a picture must show (obstacles hiding them are drawn see-through)
SKY = (0.85, 0.88, 0.92)
SEE_THROUGH = (0.78, 0.80, 0.84, 0.2)  # colour and alpha of an obstacle that hides a hand from the camera
_DATA = {"MESH": "meshes", "LIGHT": "lights", "CAMERA": "cameras"}  # bpy.data collections by ID type
DRAFT = "MANIKIN_RENDER_DRAFT"  # "1": draft pictures (the tests that only check a picture is written)


def quality(size: tuple[int, int], samples: int) -> tuple[tuple[int, int], int]:
    """The tiles' ``size`` (px, w, h) and ``samples``, or under MANIKIN_RENDER_DRAFT=1 a draft's: a quarter of
    each side (the same aspect, so the same layout) and one sample."""
    if os.environ.get(DRAFT, "").strip().lower() in ("1", "on", "yes", "true"):
        return (max(8, size[0] // 4), max(8, size[1] // 4)), 1
    return size, samples


def _material(name: str, color: tuple[float, float, float]) -> bpy.types.Material:
    material = bpy.data.materials.new(name)
    material.diffuse_color = (*color, 1.0)
    return material


def _principled() -> None:
    """Our plain materials (floor, box, capsules, solids) as matte Principled surfaces of their viewport colors: the
    render matches the viewport, and a rough surface needs fewer samples. The human's skin and eyes keep their own
    shading."""
    for material in bpy.data.materials:
        if not material.name.startswith(OUR_MATERIALS) or material.get(SHADED_KEY):
            continue  # the user's own materials stay as they are
        bsdf = node_tree(material).nodes.get("Principled BSDF")
        if bsdf is not None:
            bsdf.inputs["Base Color"].default_value = material.diffuse_color
            bsdf.inputs["Roughness"].default_value = 0.9


class _Stage:
    """Floor, lights, camera and box in a collection of their own; :meth:`remove` takes them away again."""

    def __init__(self, scene: bpy.types.Scene, arm: bpy.types.Object) -> None:
        self.scene, self.arm = scene, arm
        self.collection = bpy.data.collections.new(PICTURE_COLLECTION)
        scene.collection.children.link(self.collection)
        self.objects: list[bpy.types.Object] = []
        self.hidden: list[tuple[bpy.types.Object, bool]] = []  # obstacles replaced by see-through copies
        floor_mesh = bpy.data.meshes.new(PICTURE_PREFIX + "floor")
        s = 40.0
        floor_mesh.from_pydata([(-s, -s, 0), (s, -s, 0), (s, s, 0), (-s, s, 0)], [], [(0, 1, 2, 3)])
        floor_mesh.materials.append(_material(PICTURE_PREFIX + "floor", (0.5, 0.52, 0.55)))
        self._add(PICTURE_PREFIX + "floor", floor_mesh)
        sun = self._add(PICTURE_PREFIX + "sun", bpy.data.lights.new(PICTURE_PREFIX + "sun", "SUN"))
        sun.data.energy, sun.data.angle = 4.5, 0.1
        sun.rotation_euler = (0.6, 0.0, -0.9)
        self.camera = self._add(PICTURE_PREFIX + "camera", bpy.data.cameras.new(PICTURE_PREFIX + "camera"))
        self.camera.data.type = "ORTHO"
        self.box = None
        loads = {ob.manikin_target.tcp for ob in members(arm) if ob.manikin_target.role == "LOAD"}
        if {"hand_l", "hand_r"} <= loads and find_carried(arm) is None:
            box_mesh = bpy.data.meshes.new(PICTURE_PREFIX + "box")
            corners = [(x, y, z) for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)]
            faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
            box_mesh.from_pydata(corners, [], faces)
            box_mesh.materials.append(_material(PICTURE_PREFIX + "box", (0.62, 0.42, 0.22)))
            self.box = self._add(PICTURE_PREFIX + "box", box_mesh)

    def _add(self, name: str, data: bpy.types.ID) -> bpy.types.Object:
        ob = bpy.data.objects.new(name, data)
        self.collection.objects.link(ob)
        self.objects.append(ob)
        return ob

    def place_box(self) -> None:
        """Between the palms, as wide as they are apart, upright."""
        hands = [tcp_empty(self.arm, t) for t in HANDS]
        if self.box is None or None in hands:
            return
        a, b = (h.matrix_world.translation for h in hands)
        across = (a - b).normalized()
        up = Vector((0.0, 0.0, 1.0))
        depth = up.cross(across).normalized()
        up = across.cross(depth)
        rotation = Matrix((across, depth, up)).transposed().to_4x4()
        scale = Matrix.Diagonal(((a - b).length, BOX_DEPTH, BOX_HEIGHT, 1.0))
        self.box.matrix_world = Matrix.Translation((a + b) / 2) @ rotation @ scale

    def frame_camera(self, points: np.ndarray, size: tuple[int, int]) -> None:
        """Orthographic camera along VIEW that holds every point (world) with a margin in a ``size`` (w, h) image."""
        forward = -VIEW
        right = forward.cross(Vector((0.0, 0.0, 1.0))).normalized()
        up = right.cross(forward)
        basis = np.array([right, up, forward])
        local = points @ basis.T
        low, high = local.min(axis=0), local.max(axis=0)
        center = Vector(((low + high) / 2) @ basis)
        width, height = (high - low)[:2] * MARGIN
        w, h = size
        self.camera.data.ortho_scale = float(max(width, height * w / h) if w >= h else max(height, width * h / w))
        rotation = Matrix((right, up, -forward)).transposed().to_4x4()  # a camera looks along its -z, y up
        self.camera.matrix_world = Matrix.Translation(center - forward * 10.0) @ rotation
        self.camera.data.clip_end = 50.0

    def see_through(self, hiding: list[bpy.types.Object]) -> None:
        """Draw ``hiding`` (obstacles) see-through: a copy of each one's evaluated mesh with a see-through material
        takes its place in the render (the obstacle is hidden from the render until :meth:`remove`)."""
        if not hiding:
            return
        material = _material(PICTURE_PREFIX + "see-through", SEE_THROUGH[:3])
        bsdf = node_tree(material).nodes.get("Principled BSDF")
        if bsdf is not None:
            bsdf.inputs["Alpha"].default_value = SEE_THROUGH[3]
        depsgraph = bpy.context.evaluated_depsgraph_get()
        for ob in hiding:
            mesh = bpy.data.meshes.new_from_object(ob.evaluated_get(depsgraph))
            mesh.materials.clear()
            mesh.materials.append(material)
            copy = self._add(PICTURE_PREFIX + "see-through." + ob.name, mesh)
            copy.matrix_world = ob.matrix_world
            copy.visible_shadow = False  # the hand inside stays lit
            self.hidden.append((ob, ob.hide_render))
            ob.hide_render = True

    def remove(self) -> None:
        for ob, hidden in self.hidden:
            ob.hide_render = hidden
        for ob in self.objects:
            data = ob.data
            bpy.data.objects.remove(ob, do_unlink=True)
            if data is not None and data.users == 0:
                getattr(bpy.data, _DATA[data.id_type]).remove(data)
        bpy.data.collections.remove(self.collection)


def _unbounded(ob: bpy.types.Object) -> bool:
    """Whether an obstacle object stands for an endless shape (a plane): its bounds are not the shape's."""
    return obstacle_kind(ob.manikin_obstacle.shape).unbounded


def _body_points(arm: bpy.types.Object) -> np.ndarray:
    """World positions of the bone heads and tails, and the corners of the obstacles (but endless ones: planes) and of
    the carried box: what the picture shows."""
    ends = [arm.matrix_world @ p for pb in arm.pose.bones for p in (pb.head, pb.tail)]
    shown = [ob for ob in bpy.context.scene.objects if ob.type == "MESH" and is_obstacle(ob) and not ob.hide_render]
    shown = [ob for ob in shown if not _unbounded(ob)] + [find_carried(arm)]
    for ob in filter(None, shown):
        ends += [ob.matrix_world @ Vector(corner) for corner in ob.bound_box]
    return np.array([tuple(p) for p in ends])


def obstacles_hiding(points: list[Vector]) -> list[bpy.types.Object]:
    """The rendered obstacles whose bounding box a sight line from one of ``points`` (world) to the camera
    (along VIEW: the camera is orthographic) passes through."""
    hiding = []
    for ob in bpy.context.scene.objects:
        if ob.type != "MESH" or not is_obstacle(ob) or ob.hide_render or _unbounded(ob):
            continue
        corners = np.array([tuple(c) for c in ob.bound_box])
        low, high = corners.min(axis=0), corners.max(axis=0)
        inverse = ob.matrix_world.inverted()
        way = np.array(inverse.to_3x3() @ VIEW)
        for point in points:
            if _ray_meets_box(np.array(inverse @ point), way, low, high):
                hiding.append(ob)
                break
    return hiding


def _ray_meets_box(start: np.ndarray, way: np.ndarray, low: np.ndarray, high: np.ndarray) -> bool:
    """Whether the ray start + t way, t >= 0, meets the axis-aligned box low..high (slab test)."""
    near, far = 0.0, np.inf
    for axis in range(3):
        if abs(way[axis]) < 1e-12:
            if not low[axis] <= start[axis] <= high[axis]:
                return False
            continue
        t0, t1 = sorted(((low[axis] - start[axis]) / way[axis], (high[axis] - start[axis]) / way[axis]))
        near, far = max(near, t0), min(far, t1)
    return near <= far


def _render_settings(
    scene: bpy.types.Scene, size: tuple[int, int], samples: int
) -> tuple[list[tuple], bpy.types.World]:
    """Cycles on the CPU at ``size`` with few bounces and a dim sky, denoised where Cycles can (then with
    ``samples``, else with 4 times as many); (what to restore, the picture's world)."""
    world = bpy.data.worlds.new(PICTURE_PREFIX + "world")
    world.color = SKY
    if world.node_tree is not None and "Background" in world.node_tree.nodes:  # dim sky light: less noise
        world.node_tree.nodes["Background"].inputs["Color"].default_value = (*SKY, 1.0)
        world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.45
    render = scene.render
    saved = [(render, "engine", render.engine)]
    render.engine = "CYCLES"  # before touching scene.cycles
    cycles = scene.cycles
    denoise = denoiser_available()
    wanted = [
        (cycles, "device", "CPU"),
        (cycles, "samples", samples if denoise else 4 * samples),
        (cycles, "use_denoising", denoise),
        (cycles, "denoising_prefilter", "FAST"),  # ACCURATE denoises the albedo and normal passes too: twice the time
        (cycles, "filter_width", 1.5 if denoise else 2.0),  # without a denoiser, a softer filter hides some grain
        (cycles, "max_bounces", 3),
        (cycles, "diffuse_bounces", 2),
        (cycles, "glossy_bounces", 1),
        (cycles, "transmission_bounces", 0),
        (cycles, "volume_bounces", 0),
        (cycles, "transparent_max_bounces", 4),  # see-through obstacles
        (render, "resolution_x", size[0]),
        (render, "resolution_y", size[1]),
        (render, "resolution_percentage", 100),
        (render, "film_transparent", False),
        (render, "filepath", render.filepath),
        (render.image_settings, "file_format", "PNG"),
        (scene, "camera", scene.camera),
        (scene, "world", world),
    ]
    for owner, name, value in wanted:
        saved.append((owner, name, getattr(owner, name)))
        setattr(owner, name, value)
    return saved, world


def _restore(saved: list[tuple], world: bpy.types.World) -> None:
    for owner, name, value in reversed(saved):
        setattr(owner, name, value)
    if world.users == 0:
        bpy.data.worlds.remove(world)


def render_key_poses(
    arm: bpy.types.Object,
    frames: list[int],
    output: str | Path,
    captions: dict[int, str] | None = None,
    title: str = "",
    size: tuple[int, int] = (300, 400),
    samples: int = 8,
) -> Path:
    """Render ``frames`` of the armature's animation side by side into ``output`` (PNG); returns its path."""
    import matplotlib.image
    from matplotlib.figure import Figure

    size, samples = quality(size, samples)
    scene = bpy.context.scene
    current = scene.frame_current
    stage = _Stage(scene, arm)
    saved = _render_settings(scene, size, samples)
    tiles = []
    try:
        points, hands = [], []
        for frame in frames:
            scene.frame_set(frame)
            points.append(_body_points(arm))
            hands += [e.matrix_world.translation.copy() for e in (tcp_empty(arm, t) for t in HANDS) if e is not None]
        stage.frame_camera(np.concatenate(points), size)
        stage.see_through(obstacles_hiding(hands))
        scene.camera = stage.camera
        _principled()
        with tempfile.TemporaryDirectory(prefix="manikin-picture-") as tmp:
            for frame in frames:
                scene.frame_set(frame)
                stage.place_box()
                scene.render.filepath = str(Path(tmp) / f"{frame}.png")
                bpy.ops.render.render(write_still=True)
                tiles.append(matplotlib.image.imread(scene.render.filepath))
    finally:
        _restore(*saved)
        stage.remove()
        scene.frame_set(current)
    output = Path(output).resolve()
    lines = max((c.count("\n") + 1 for c in (captions or {}).values()), default=0)
    width, height = size
    tile_in = 2.8  # inches per tile
    heading = textwrap.fill(title, int(12 * tile_in * len(tiles)))  # about 12 characters an inch at 11 pt
    extra = 0.2 * heading.count("\n")  # inches for the heading's wrapped lines
    fig_h = tile_in * height / width + 0.5 + 0.17 * lines + extra
    fig = Figure(figsize=(tile_in * len(tiles), fig_h), dpi=130)
    axes = fig.subplots(1, len(tiles), squeeze=False)
    for ax, frame, tile in zip(axes[0], frames, tiles, strict=True):
        ax.imshow(tile)
        ax.set_axis_off()
        ax.set_title(f"frame {frame}", fontsize=10, fontweight="bold", pad=3)
        if captions and frame in captions:
            ax.text(0.5, -0.015, captions[frame], transform=ax.transAxes, ha="center", va="top", fontsize=7.5,
                    linespacing=1.35)  # fmt: skip
    bottom = (0.08 + 0.17 * lines) / fig_h
    fig.subplots_adjust(left=0.005, right=0.995, wspace=0.03, top=1 - (0.42 + extra) / fig_h, bottom=bottom)
    if heading:
        fig.suptitle(heading, fontsize=11, y=1 - 0.05 / fig_h, va="top")
    with written_by_path(output) as work:  # a temporary file, checked, then renamed: a full disk keeps the old one
        fig.savefig(work, format="png")
    return output
