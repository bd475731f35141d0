"""Simple visible bodies for the armature, NumPy only: one low-poly solid per bone, sized by the segment's mass,
or the solver's collision capsules.

Each bone gets a solid of revolution around the segment from its head to ``segment_end`` whose volume is the
segment's mass at the density of water: a capsule for limbs, a flat-ended cylinder for short heavy segments
(the vertebrae stack into a trunk), an ellipsoid for heavy end segments (head, hands, feet). Massless
segments (fingers, neck) get a fraction of the radius of the nearest heavy ancestor. Every vertex belongs to
its bone only (rigid skinning). The capsules (:func:`capsule_mesh`) are rigid on their links' bones too.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .bones import RigLayout

DENSITY = 1000.0  # kg/m^3
SIDES = 10
MAX_RADIUS = 0.16  # m
MIN_RADIUS = 0.008  # m
MASSLESS_FRACTION = 0.35


@dataclass(frozen=True)
class BodyMesh:
    """Vertices (m, armature space, zero pose), quad/triangle faces, and the bone index of every vertex."""

    vertices: np.ndarray
    faces: list[tuple[int, ...]]
    vertex_bone: np.ndarray


def _profile(length: float, radius: float, kind: str) -> list[tuple[float, float]]:
    """(axial position, radius) rings from the head (0) towards the end (``length``)."""
    if kind == "cylinder":  # overlapping its neighbours, so a bent spine shows no gaps
        return [(-0.4 * length, 0.9 * radius), (0.0, radius), (length, radius), (1.4 * length, 0.9 * radius)]
    if kind == "ellipsoid":
        half = max(length / 2.0, radius)
        angles = np.deg2rad(np.arange(15.0, 180.0, 30.0))
        return [(length / 2.0 - half * np.cos(a), radius * np.sin(a)) for a in angles]
    angles = np.deg2rad([20.0, 50.0, 90.0])
    start = [(-radius * np.cos(a), radius * np.sin(a)) for a in angles]
    end = [(length + radius * np.cos(a), radius * np.sin(a)) for a in reversed(angles)]
    return start + end


def _radius(layout: RigLayout, b: int, radii: list[float]) -> tuple[float, str]:
    bone = layout.bones[b]
    length = max(float(np.linalg.norm(bone.segment_end - bone.head)), 1e-3)
    has_heavy_child = any(c.parent == b and c.mass > 0 for c in layout.bones)
    if bone.mass <= 0:
        ancestor, r = bone.parent, MIN_RADIUS / MASSLESS_FRACTION
        while ancestor >= 0:
            if layout.bones[ancestor].mass > 0:
                r = radii[ancestor]
                break
            ancestor = layout.bones[ancestor].parent
        return max(MASSLESS_FRACTION * r, MIN_RADIUS), "capsule"
    volume = bone.mass / DENSITY
    if not has_heavy_child:
        sphere = (3.0 * volume / (4.0 * np.pi)) ** (1.0 / 3.0)
        half = max(length / 2.0, sphere)
        return float(np.clip(np.sqrt(3.0 * volume / (4.0 * np.pi * half)), MIN_RADIUS, MAX_RADIUS)), "ellipsoid"
    r = float(np.clip(np.sqrt(volume / (np.pi * length)), MIN_RADIUS, MAX_RADIUS))
    return r, ("capsule" if r < length else "cylinder")


def _sweep(start: np.ndarray, axis: np.ndarray, side: np.ndarray, profile: list[tuple[float, float]],
           wide: float = 1.0, deep: float = 1.0) -> tuple[np.ndarray, list[tuple[int, ...]]]:  # fmt: skip
    """Rings of ``profile`` (axial position, radius; m) along the unit ``axis`` from ``start``, joined by quads and
    closed by an n-gon at each end; ``side``: a direction across the axis (the ``wide`` one)."""
    side = side - axis * (side @ axis)
    side /= np.linalg.norm(side)
    depth = np.cross(axis, side)
    ring = np.linspace(0.0, 2.0 * np.pi, SIDES, endpoint=False)
    across = wide * np.cos(ring)[:, None] * side + deep * np.sin(ring)[:, None] * depth
    vertices = np.concatenate([start + s * axis + rho * across for s, rho in profile])
    faces: list[tuple[int, ...]] = []
    for k in range(len(profile) - 1):
        for i in range(SIDES):
            a0, a1 = k * SIDES + i, k * SIDES + (i + 1) % SIDES
            faces.append((a0, a1, a1 + SIDES, a0 + SIDES))
    last = (len(profile) - 1) * SIDES
    faces.append(tuple(reversed(range(SIDES))))
    faces.append(tuple(last + i for i in range(SIDES)))
    return vertices, faces


def _joined(parts: list[tuple[np.ndarray, list[tuple[int, ...]], int]]) -> BodyMesh:
    """One mesh of (vertices, faces, bone) parts."""
    vertices, faces, owner, base = [], [], [], 0
    for points, polygons, bone in parts:
        vertices.append(points)
        faces += [tuple(base + i for i in f) for f in polygons]
        owner += [bone] * len(points)
        base += len(points)
    return BodyMesh(np.concatenate(vertices), faces, np.array(owner, dtype=int))


def build_body_mesh(layout: RigLayout) -> BodyMesh:
    """Solids for every bone of ``layout`` in the zero pose."""
    parts = []
    radii: list[float] = []
    for b, bone in enumerate(layout.bones):
        radius, kind = _radius(layout, b, radii)
        radii.append(radius)
        axis = bone.segment_end - bone.head
        length = max(float(np.linalg.norm(axis)), 1e-3)
        axis = axis / length
        # Wider than deep across heavy, short segments (the trunk); round elsewhere.
        side = bone.rest[:, 0] - axis * (bone.rest[:, 0] @ axis)
        if np.linalg.norm(side) < 1e-6:
            side = bone.rest[:, 2]
        wide, deep = (1.2, 0.8) if kind == "cylinder" else (1.0, 1.0)
        parts.append((*_sweep(bone.head, axis, side, _profile(length, radius, kind), wide, deep), b))
    return _joined(parts)


def capsule_mesh(layout: RigLayout, capsules) -> BodyMesh:
    """The collision capsules (``solver.collision.body.BodyCapsules`` of the layout's model) in the zero pose,
    each on the bone that moves its link."""
    zero = layout.zero
    parts = []
    for link, start, end, radius in zip(capsules.link, capsules.start, capsules.end, capsules.radius, strict=True):
        a, z = (zero.rotation[link] @ p + zero.position[link] for p in (start, end))
        length = float(np.linalg.norm(z - a))
        axis = (z - a) / length if length > 1e-9 else np.array([0.0, 0.0, 1.0])
        side = np.array([1.0, 0.0, 0.0]) if abs(axis[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
        surface = _sweep(a, axis, side, _profile(length, float(radius), "capsule"))
        parts.append((*surface, int(layout.bone_of_link[link])))
    return _joined(parts)
