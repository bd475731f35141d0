"""Signed distances between pairs of capsules (the body's links, self-collision), and the conventions every
capsule-obstacle query follows (each obstacle kind's own distance: :mod:`solver.collision.kinds`).

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

from .. import kernels
from ..kernels.clearance import axes_closest
from .closest import cross, dot, perpendicular, segment_segment, unit
from .proximity import PairProximity


def as_batch(p0: np.ndarray, p1: np.ndarray, radii: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Capsule ends as (k, 3) float arrays and the radii as (k,) (one radius for all is broadcast)."""
    p0, p1 = np.atleast_2d(np.asarray(p0, dtype=float)), np.atleast_2d(np.asarray(p1, dtype=float))
    return p0, p1, np.broadcast_to(np.asarray(radii, dtype=float), (len(p0),))


def closest_on_axes(p0, p1, q0, q1) -> tuple[np.ndarray, ...]:
    """Closest parameters, points and the unit normal from the q segment to the p segment (any direction
    perpendicular to both where the axes meet)."""
    if kernels.active():
        index = np.arange(len(p0))
        return _compiled_axes(p0, p1, q0, q1, index, index)[:5]
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


def capsule_pairs(p0: np.ndarray, p1: np.ndarray, radii: np.ndarray, i: np.ndarray, j: np.ndarray) -> PairProximity:
    """Capsule i[m] vs capsule j[m] of one batch (self-collision), m = 0..len(i)-1."""
    if kernels.active():  # the kernel takes the arrays as they are (no broadcast copies)
        s, w, t, q, n, length = _compiled_axes(p0, p1, p0, p1, i, j)
        radii = np.asarray(radii, dtype=float)
        return PairProximity(length - radii[i] - radii[j] if radii.ndim else length - radii - radii, s, w, t, q, n)
    p0, p1, radii = as_batch(p0, p1, radii)
    i, j = np.asarray(i, dtype=np.int64), np.asarray(j, dtype=np.int64)
    s, w, t, q, n = closest_on_axes(p0[i], p1[i], p0[j], p1[j])
    d = np.sqrt(dot(w - q, w - q)) - radii[i] - radii[j]
    return PairProximity(d, s, w, t, q, n)


def _compiled_axes(p0, p1, q0, q1, i: np.ndarray, j: np.ndarray) -> tuple[np.ndarray, ...]:
    """(s, w, t, q, normal, gap length (m)) of segments p0[i]-p1[i] and q0[j]-q1[j] by the kernel; where the axes
    meet (rare) the normal is made as :func:`closest_on_axes` makes it."""
    p0, p1, q0, q1 = (_rows(x) for x in (p0, p1, q0, q1))
    i, j = np.ascontiguousarray(i, dtype=np.int64), np.ascontiguousarray(j, dtype=np.int64)
    m = len(i)
    s, t, length = np.empty(m), np.empty(m), np.empty(m)
    w, q, normal = np.empty((m, 3)), np.empty((m, 3)), np.empty((m, 3))
    if axes_closest(p0, p1, q0, q1, i, j, s, w, t, q, normal, length):
        meet = np.flatnonzero(length <= 1e-150)
        um, vm = p1[i[meet]] - p0[i[meet]], q1[j[meet]] - q0[j[meet]]
        normal[meet] = unit(cross(um, vm), perpendicular(np.where(dot(um, um)[:, None] > 0, um, vm)))
    return s, w, t, q, normal, length


def _rows(x) -> np.ndarray:
    """``x`` as a contiguous (k, 3) float64 array (itself when it is one already: the common case, kept cheap)."""
    if isinstance(x, np.ndarray) and x.ndim == 2 and x.dtype == np.float64 and x.flags.c_contiguous:
        return x
    return np.ascontiguousarray(x, dtype=float).reshape(-1, 3)
