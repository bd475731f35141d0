"""Capsules vs oriented boxes, row by row: exact distance when apart, minus the penetration depth when they overlap
(the conventions of :mod:`.distance`).

Every function works on rows that each pair one capsule with one box (its center, rotation and half sizes given per
row), so a scene's boxes are answered by one set of NumPy calls instead of one set per box (the box obstacle kind:
:mod:`solver.collision.kinds.box`; the carried box's rows).
"""

from __future__ import annotations

import numpy as np

from .. import kernels
from ..kernels.clearance_box import box_rows_apart, box_rows_overlap
from .closest import dot, perpendicular, segment_segment, unit
from .proximity import Proximity

_BOX_EDGES = np.array(
    [[[-1, j, k], [1, j, k]] for j in (-1, 1) for k in (-1, 1)]
    + [[[i, -1, k], [i, 1, k]] for i in (-1, 1) for k in (-1, 1)]
    + [[[i, j, -1], [i, j, 1]] for i in (-1, 1) for j in (-1, 1)],
    dtype=float,
)  # (12, 2, 3): the unit cube's edges as corner pairs, scaled by the half sizes


_CORNERS = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float)
_EDGES = np.array([(i, j) for i in range(8) for j in range(i + 1, 8) if np.abs(_CORNERS[i] - _CORNERS[j]).sum() == 2])


def box_corners(center: np.ndarray, rotation: np.ndarray, half: np.ndarray) -> np.ndarray:
    """The 8 corners ((8, 3) world m) of the box ``center``, ``rotation`` (axes as columns), ``half`` sizes."""
    return center + (_CORNERS * half) @ rotation.T


def box_edges(center: np.ndarray, rotation: np.ndarray, half: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The 12 edges (starts, ends: (12, 3) world m) of the box ``center``, ``rotation`` (axes as columns), ``half``."""
    return edges_of_corners(box_corners(center, rotation, half))


def edges_of_corners(corners: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The 12 edges (starts, ends (12, 3)) of a box given by its :func:`box_corners`."""
    return corners[_EDGES[:, 0]], corners[_EDGES[:, 1]]


def _outside(a: np.ndarray, b: np.ndarray, half: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Segments a-b (k, 3) in box coordinates vs the boxes |x_i| <= half_i (k, 3), as if disjoint: (t, distance,
    normal). The squared distance from a + t (b - a) to the box is convex and piecewise quadratic in t, with knots
    where a coordinate meets a face plane: minimised on each of the pieces between the sorted knots (its quadratic
    in the coordinates outside their slab there, clipped to the piece), the least of those is exact."""
    k = len(a)
    u = b - a
    knots = np.zeros((k, 8))
    knots[:, 1] = 1.0
    # where a coordinate meets a face plane (a coordinate that does not move: a spare knot at 0, harmless)
    np.divide(np.concatenate([half - a, -half - a], axis=1), np.tile(u, 2), out=knots[:, 2:], where=np.tile(u != 0, 2))
    np.minimum(np.maximum(knots, 0.0, out=knots), 1.0, out=knots)
    knots.sort(axis=1)
    lo, hi = knots[:, :-1], knots[:, 1:]  # (k, 7) pieces on which the clamped coordinates do not change
    h, column = half[:, None], u[:, :, None]
    x = a[:, None] + (0.5 * (lo + hi))[..., None] * u[:, None]
    side = np.minimum(np.maximum(x, -h), h)
    out = (x != side).astype(float)  # (k, 7, 3): the coordinates outside their slab on each piece
    squared = (out @ (column * column))[..., 0]
    pull = ((out * (side - a[:, None])) @ column)[..., 0]
    t = np.minimum(np.maximum(pull / np.where(squared > 0, squared, 1.0), lo), hi)
    x = a[:, None] + t[..., None] * u[:, None]
    gap = x - np.minimum(np.maximum(x, -h), h)
    d2 = (gap * gap).sum(axis=2)
    best = np.argmin(d2, axis=1)
    rows = np.arange(k)
    gap, x, t = gap[rows, best], x[rows, best], t[rows, best]
    distance = np.sqrt(d2[rows, best])
    normal = gap / np.maximum(distance, 1e-150)[:, None]
    touching = np.flatnonzero(distance <= 1e-150)  # on the surface: the face's normal (rare: worked out only here)
    if touching.size:
        x, touched = x[touching], half[touching]
        face = np.eye(3)[np.argmax(np.abs(x) / touched, axis=1)] * np.sign(x)
        normal[touching] = unit(face, perpendicular(b[touching] - a[touching]))
    return t, distance, normal


def _overlap(a: np.ndarray, b: np.ndarray, half: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Segments a-b (k, 3) in box coordinates that touch their boxes (half sizes (k, 3)): (t, penetration depth >= 0,
    normal) by the separating axes (the 3 face normals and the segment's direction crossed with each edge's)."""
    u = b - a
    cross = np.cross(u[:, None, :], np.eye(3)[None])  # (k, 3, 3)
    length = np.sqrt(dot(cross, cross))
    valid = length > 1e-9 * np.sqrt(dot(u, u))[:, None]
    axes = np.concatenate([np.broadcast_to(np.eye(3), cross.shape), cross / np.where(valid, length, 1)[..., None]], 1)
    sa, sb = dot(axes, a[:, None]), dot(axes, b[:, None])
    rho = dot(np.abs(axes), half[:, None])
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
    e0[rows, i], e1[rows, i] = -half[rows, i], half[rows, i]
    s, _ = segment_segment(a, b, e0, e1)
    t = np.where(best >= 3, s, t)
    return t, depth[rows, best], n


def box_rows(p0, p1, radii, center, rotation, half) -> Proximity:
    """Capsule p0-p1 (k, 3) m of radius ``radii`` (k,) vs box ``center`` (k, 3), ``rotation`` (k, 3, 3) (box axes
    as columns) and ``half`` sizes (k, 3) m, row by row."""
    if kernels.active():
        return _compiled_rows(p0, p1, radii, center, rotation, half)
    return _numpy_rows(p0, p1, radii, center, rotation, half)


def box_rows_one(p0, p1, radii, center, rotation, half) -> Proximity:
    """:func:`box_rows` of capsules p0-p1 (k, 3) m against the one box ``center`` (3,) m, ``rotation`` (3, 3),
    ``half`` (3,) m (the kernels take it as one row: no arrays broadcast per call)."""
    if kernels.active():
        # writable C copies: the array types the kernels were compiled for (a read-only or F-ordered rotation
        # would compile them once more on a cold cache)
        one = (np.array(x, dtype=float, order="C")[None] for x in (center, rotation, half))
        return _compiled_rows(p0, p1, radii, *one)
    k = len(p0)
    return _numpy_rows(p0, p1, radii, *(np.broadcast_to(x, (k, *np.shape(x))) for x in (center, rotation, half)))


def _numpy_rows(p0, p1, radii, center, rotation, half) -> Proximity:
    """:func:`box_rows` by NumPy (the reference path)."""
    a = np.einsum("ki,kij->kj", p0 - center, rotation)
    b = np.einsum("ki,kij->kj", p1 - center, rotation)
    t, axis, n = _outside(a, b, half)
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
        tm, depth, nm = _overlap(a[meet], b[meet], half[meet])
        t[meet], axis[meet], n[meet] = tm, -depth, nm
    w = p0 + t[:, None] * (p1 - p0)
    n_world = np.einsum("kj,kij->ki", n, rotation)
    return Proximity(axis - radii, t, w, n_world, w - axis[:, None] * n_world)


def _compiled_rows(p0, p1, radii, center, rotation, half) -> Proximity:
    """:func:`box_rows` by the kernels; a row whose axis only touches its box (rounding's case) by the NumPy code."""
    p0, p1, radii = (np.ascontiguousarray(x, dtype=float) for x in (p0, p1, radii))
    center, rotation, half = (np.asarray(x, dtype=float) for x in (center, rotation, half))
    # a box broadcast to every row (one box's query, the carried box) is passed as its one row
    center, rotation, half = (x[:1] if x.strides[0] == 0 else np.ascontiguousarray(x) for x in (center, rotation, half))
    k = len(p0)
    distance, t, rare = np.empty(k), np.empty(k), np.zeros(k, dtype=np.int64)
    point, normal, closest = np.empty((k, 3)), np.empty((k, 3)), np.empty((k, 3))
    if box_rows_apart(p0, p1, radii, center, rotation, half, distance, t, point, normal, closest, rare):
        meet = np.flatnonzero(rare == 1)
        if meet.size:
            box_rows_overlap(p0, p1, radii, center, rotation, half, meet, distance, t, point, normal, closest)
        rows = np.flatnonzero(rare == 2)
        if rows.size:
            m = len(rows)
            box = (np.broadcast_to(x, (m, *x.shape[1:])) if len(x) == 1 else x[rows] for x in (center, rotation, half))
            got = _numpy_rows(p0[rows], p1[rows], radii[rows], *box)
            for mine, theirs in zip((distance, t, point, normal, closest), got, strict=True):
                mine[rows] = theirs
    return Proximity(distance, t, point, normal, closest)
