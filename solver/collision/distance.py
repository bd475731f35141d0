"""Signed distances between a batch of capsules (the body's links) and obstacles, or between pairs of capsules.

A capsule k is the segment p0[k]-p1[k] (m) swept by a ball of radius radii[k] (m). Every query returns per
capsule (see :class:`Proximity`): the surface-to-surface distance d (m, negative when they overlap), the witness
point w = p0 + t (p1 - p0) on the capsule's axis, and the unit normal n pointing from the obstacle towards the
capsule with dd/dw = n. Wherever the closest pair is unique, dd/dp0 = (1 - t) n and dd/dp1 = t n, so the
Jacobian of d with respect to joint values is n . (velocity of the point w carried by the link).

When shapes overlap, d is minus the penetration depth (the shortest translation of the capsule that separates
them) for spheres, capsules, boxes and half-spaces; meshes: :mod:`.mesh_distance`.
"""

from __future__ import annotations

import numpy as np

from .closest import cross, dot, perpendicular, point_segment, segment_segment, unit
from .mesh_distance import mesh_distance
from .mesh_index import MeshIndex
from .proximity import PairProximity, Proximity, near_only
from .shapes import Box, Capsule, HalfSpace, Mesh, Obstacle, Sphere

_BOX_EDGES = np.array(
    [[[-1, j, k], [1, j, k]] for j in (-1, 1) for k in (-1, 1)]
    + [[[i, -1, k], [i, 1, k]] for i in (-1, 1) for k in (-1, 1)]
    + [[[i, j, -1], [i, j, 1]] for i in (-1, 1) for j in (-1, 1)],
    dtype=float,
)  # (12, 2, 3): the unit cube's edges as corner pairs, scaled by the half sizes


def _batch(p0: np.ndarray, p1: np.ndarray, radii: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    p0, p1 = np.atleast_2d(np.asarray(p0, dtype=float)), np.atleast_2d(np.asarray(p1, dtype=float))
    return p0, p1, np.broadcast_to(np.asarray(radii, dtype=float), (len(p0),))


def sphere_distance(p0: np.ndarray, p1: np.ndarray, radii: np.ndarray, sphere: Sphere) -> Proximity:
    """Capsules vs a sphere: the axis point nearest the center."""
    p0, p1, radii = _batch(p0, p1, radii)
    t, w = point_segment(sphere.center, p0, p1)
    n = unit(w - sphere.center, perpendicular(p1 - p0))
    axis = np.sqrt(dot(w - sphere.center, w - sphere.center)) - sphere.radius
    return Proximity(axis - radii, t, w, n, sphere.center + sphere.radius * n)


def _segments(p0, p1, q0, q1) -> tuple[np.ndarray, ...]:
    """Closest parameters, points and the unit normal from the q segment to the p segment (any direction
    perpendicular to both where the axes meet)."""
    s, t = segment_segment(p0, p1, q0, q1)
    u, v = p1 - p0, q1 - q0
    w, q = p0 + s[:, None] * u, q0 + t[:, None] * v
    across = unit(cross(u, v), perpendicular(np.where(dot(u, u)[:, None] > 0, u, v)))
    return s, w, t, q, unit(w - q, across)


def capsule_distance(p0: np.ndarray, p1: np.ndarray, radii: np.ndarray, capsule: Capsule) -> Proximity:
    """Capsules vs a capsule obstacle: closest points of the two axes (parallel axes included)."""
    p0, p1, radii = _batch(p0, p1, radii)
    q0, q1 = np.broadcast_to(capsule.a, p0.shape), np.broadcast_to(capsule.b, p0.shape)
    s, w, _, q, n = _segments(p0, p1, q0, q1)
    axis = np.sqrt(dot(w - q, w - q)) - capsule.radius
    return Proximity(axis - radii, s, w, n, q + capsule.radius * n)


def capsule_pairs(p0: np.ndarray, p1: np.ndarray, radii: np.ndarray, i: np.ndarray, j: np.ndarray) -> PairProximity:
    """Capsule i[m] vs capsule j[m] of one batch (self-collision), m = 0..len(i)-1."""
    p0, p1, radii = _batch(p0, p1, radii)
    i, j = np.asarray(i, dtype=np.int64), np.asarray(j, dtype=np.int64)
    s, w, t, q, n = _segments(p0[i], p1[i], p0[j], p1[j])
    d = np.sqrt(dot(w - q, w - q)) - radii[i] - radii[j]
    return PairProximity(d, s, w, t, q, n)


def halfspace_distance(p0: np.ndarray, p1: np.ndarray, radii: np.ndarray, plane: HalfSpace) -> Proximity:
    """Capsules vs a half-space: the lower end along the normal (p0 on a tie)."""
    p0, p1, radii = _batch(p0, p1, radii)
    h0, h1 = dot(p0 - plane.point, plane.normal), dot(p1 - plane.point, plane.normal)
    t = np.where(h1 < h0, 1.0, 0.0)
    w = np.where(t[:, None] > 0, p1, p0)
    h = np.minimum(h0, h1)
    n = np.broadcast_to(plane.normal, p0.shape).copy()
    return Proximity(h - radii, t, w, n, w - h[:, None] * n)


def _box_outside(a: np.ndarray, b: np.ndarray, half: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Segments a-b (k, 3) in box coordinates vs the box |x_i| <= half_i, as if disjoint: (t, distance, normal).
    The nearest axis point is an end or the point nearest one of the 12 edges."""
    edges = _BOX_EDGES * half
    s, _ = segment_segment(a[:, None], b[:, None], edges[None, :, 0], edges[None, :, 1])
    t = np.concatenate([np.zeros((len(a), 1)), np.ones((len(a), 1)), s], axis=1)
    x = a[:, None] + t[..., None] * (b - a)[:, None]
    gap = x - np.clip(x, -half, half)
    d2 = dot(gap, gap)
    best = np.argmin(d2, axis=1)
    rows = np.arange(len(a))
    face = np.eye(3)[np.argmax(np.abs(x[rows, best]) / half, axis=1)] * np.sign(x[rows, best])
    return t[rows, best], np.sqrt(d2[rows, best]), unit(gap[rows, best], unit(face, perpendicular(b - a)))


def _box_overlap(a: np.ndarray, b: np.ndarray, half: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Segments a-b (k, 3) in box coordinates that touch the box: (t, penetration depth >= 0, normal) by the
    separating axes (the 3 face normals and the segment's direction crossed with each edge direction)."""
    u = b - a
    cross = np.cross(u[:, None, :], np.eye(3)[None])  # (k, 3, 3)
    length = np.sqrt(dot(cross, cross))
    valid = length > 1e-9 * np.sqrt(dot(u, u))[:, None]
    axes = np.concatenate([np.broadcast_to(np.eye(3), cross.shape), cross / np.where(valid, length, 1)[..., None]], 1)
    sa, sb = dot(axes, a[:, None]), dot(axes, b[:, None])
    rho = dot(np.abs(axes), half)
    up, down = rho - np.minimum(sa, sb), np.maximum(sa, sb) + rho  # moves along +axis / -axis that separate
    depth = np.where(np.concatenate([np.ones_like(valid), valid], axis=1), np.minimum(up, down), np.inf)
    best = np.argmin(depth, axis=1)
    rows = np.arange(len(a))
    n = axes[rows, best] * np.where(up[rows, best] <= down[rows, best], 1.0, -1.0)[:, None]
    t = np.where(dot(n, a) <= dot(n, b), 0.0, 1.0)  # face axis: the deeper end
    # edge axis: where the segment passes the box edge (direction e_i) that sticks out furthest along n
    i = np.clip(best - 3, 0, 2)
    corner = np.where(n >= 0, half, -half)
    e0, e1 = corner.copy(), corner.copy()
    e0[rows, i], e1[rows, i] = -half[i], half[i]
    s, _ = segment_segment(a, b, e0, e1)
    t = np.where(best >= 3, s, t)
    return t, depth[rows, best], n


def box_distance(p0: np.ndarray, p1: np.ndarray, radii: np.ndarray, box: Box) -> Proximity:
    """Capsules vs an oriented box: exact distance when apart, minus the penetration depth when they overlap."""
    p0, p1, radii = _batch(p0, p1, radii)
    a, b = (p0 - box.center) @ box.rotation, (p1 - box.center) @ box.rotation
    half = box.half
    t, axis, n = _box_outside(a, b, half)
    u = b - a
    # slab test: does the axis segment meet the box?
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        lo, hi = (-half - a) / u, (half - a) / u
    flat = u == 0
    lo = np.where(flat, np.where(np.abs(a) <= half, -np.inf, np.inf), lo)  # a flat axis outside its slab: empty
    hi = np.where(flat, np.inf, hi)
    enter = np.maximum(np.max(np.minimum(lo, hi), axis=1), 0.0)
    leave = np.minimum(np.min(np.maximum(lo, hi), axis=1), 1.0)
    meet = np.flatnonzero(enter <= leave)
    if meet.size:
        tm, depth, nm = _box_overlap(a[meet], b[meet], half)
        t[meet], axis[meet], n[meet] = tm, -depth, nm
    w = p0 + t[:, None] * (p1 - p0)
    n_world = n @ box.rotation.T
    return Proximity(axis - radii, t, w, n_world, w - axis[:, None] * n_world)


def _near_box_only(p0: np.ndarray, p1: np.ndarray, radii: np.ndarray, box: Box, margin: float) -> Proximity:
    """box_distance for the capsules within ``margin`` (m) of the box; +inf for the others, as a mesh's (most of a
    scene's boxes are far from most capsules: their exact query is the cost of a motion frame near furniture)."""
    p0, p1, radii = _batch(p0, p1, radii)
    extent = np.abs(box.rotation) @ box.half  # the box's world bounding box: center +- extent
    return near_only(p0, p1, radii, margin, box.center - extent, box.center + extent,
                     lambda rows: box_distance(p0[rows], p1[rows], radii[rows], box))  # fmt: skip


def obstacle_distance(
    p0: np.ndarray, p1: np.ndarray, radii: np.ndarray, obstacle: Obstacle | MeshIndex, margin: float = np.inf
) -> Proximity:
    """Capsules vs any obstacle. ``margin`` (m) bounds the search of a mesh (pass a prepared :class:`MeshIndex`
    to reuse its grid; a bare :class:`Mesh` is indexed on every call): rows farther than the margin may come back
    as +inf. The distance ignores the obstacle's clearance."""
    if isinstance(obstacle, Sphere):
        return sphere_distance(p0, p1, radii, obstacle)
    if isinstance(obstacle, Capsule):
        return capsule_distance(p0, p1, radii, obstacle)
    if isinstance(obstacle, Box):
        return _near_box_only(p0, p1, radii, obstacle, margin)
    if isinstance(obstacle, HalfSpace):
        return halfspace_distance(p0, p1, radii, obstacle)
    if isinstance(obstacle, Mesh | MeshIndex):
        index = obstacle if isinstance(obstacle, MeshIndex) else MeshIndex(obstacle)
        return mesh_distance(p0, p1, radii, index, margin)
    raise TypeError(f"not an obstacle: {type(obstacle).__name__}")
