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

from .boxes import box_set, boxes_distance
from .closest import cross, dot, perpendicular, point_segment, segment_segment, unit
from .mesh_distance import mesh_distance
from .mesh_index import MeshIndex, NearMemory
from .proximity import PairProximity, Proximity
from .shapes import Box, Capsule, HalfSpace, Mesh, Obstacle, Sphere


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
    gap = w - q
    length = np.sqrt(dot(gap, gap))
    normal = gap / np.maximum(length, 1e-150)[:, None]
    meet = np.flatnonzero(length <= 1e-150)  # the axes meet (rare): the normal is made only for these rows
    if meet.size:
        um, vm = u[meet], v[meet]
        normal[meet] = unit(cross(um, vm), perpendicular(np.where(dot(um, um)[:, None] > 0, um, vm)))
    return s, w, t, q, normal


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


def obstacle_distance(
    p0: np.ndarray,
    p1: np.ndarray,
    radii: np.ndarray,
    obstacle: Obstacle | MeshIndex,
    margin: float = np.inf,
    memory: NearMemory | None = None,
) -> Proximity:
    """Capsules vs any obstacle. ``margin`` (m) bounds the search of a mesh (pass a prepared :class:`MeshIndex`
    to reuse its grid; a bare :class:`Mesh` is indexed on every call): rows farther than the margin may come back
    as +inf; ``memory`` (a mesh's, for the same capsules) lets a query near the last one skip the tree walk. The
    distance ignores the obstacle's clearance."""
    if isinstance(obstacle, Sphere):
        return sphere_distance(p0, p1, radii, obstacle)
    if isinstance(obstacle, Capsule):
        return capsule_distance(p0, p1, radii, obstacle)
    if isinstance(obstacle, Box):  # only the capsules near the box: most of a scene's boxes are far from most parts
        return boxes_distance(*_batch(p0, p1, radii), box_set([obstacle]), margin)[0]
    if isinstance(obstacle, HalfSpace):
        return halfspace_distance(p0, p1, radii, obstacle)
    if isinstance(obstacle, Mesh | MeshIndex):
        index = obstacle if isinstance(obstacle, MeshIndex) else MeshIndex(obstacle)
        return mesh_distance(p0, p1, radii, index, margin, memory)
    raise TypeError(f"not an obstacle: {type(obstacle).__name__}")
