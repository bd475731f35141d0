"""Closest points between points, segments and triangles, vectorised over any leading dimensions.

Segments are given by their end points (..., 3); a parameter t in [0, 1] names the point p0 + t (p1 - p0).
Every function is exact up to round-off, handles zero-length segments and parallel segments, and never returns
NaN for finite input.
"""

from __future__ import annotations

import numpy as np

TINY = 1e-24  # m^2: a squared length below this is a zero-length segment
PARALLEL = 1e-12  # relative: segments with sin^2(angle) below this are treated as parallel


def dot(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Row-wise dot product over the last axis."""
    return np.einsum("...i,...i->...", x, y)


def unit(v: np.ndarray, fallback: np.ndarray) -> np.ndarray:
    """``v`` scaled to unit length along the last axis; rows of (near) zero length take ``fallback`` (unit)."""
    length = np.sqrt(dot(v, v))[..., None]
    ok = length > 1e-300
    return np.where(ok, v / np.where(ok, length, 1.0), fallback)


def perpendicular(u: np.ndarray) -> np.ndarray:
    """A unit vector perpendicular to each ``u`` (..., 3); +z where u is zero."""
    u = np.asarray(u, dtype=float)
    axis = np.zeros(u.shape)
    smallest = np.argmin(np.abs(u), axis=-1)
    np.put_along_axis(axis, smallest[..., None], 1.0, axis=-1)
    ez = np.broadcast_to(np.array([0.0, 0.0, 1.0]), u.shape)
    return unit(np.cross(u, axis), ez)


def point_segment(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Parameter t (...) and point (..., 3) on the segment a-b closest to p."""
    u = b - a
    uu = dot(u, u)
    t = np.clip(dot(p - a, u) / np.where(uu > TINY, uu, 1.0), 0.0, 1.0)
    t = np.where(uu > TINY, t, 0.0)
    return t, a + t[..., None] * u


def segment_segment(p0: np.ndarray, p1: np.ndarray, q0: np.ndarray, q1: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Parameters (s, t) of the closest points p0 + s (p1 - p0) and q0 + t (q1 - q0) of two segments.

    Minimises the convex quadratic |p(s) - q(t)|^2 on [0, 1]^2: s from the lines' closest points (0 when
    parallel) clamped, t optimal for that s; if t had to be clamped, s optimal for that t.
    """
    d1, d2, r = p1 - p0, q1 - q0, p0 - q0
    a, e, b, c, f = dot(d1, d1), dot(d2, d2), dot(d1, d2), dot(d1, r), dot(d2, r)
    a_zero, e_zero = a <= TINY, e <= TINY
    safe_a, safe_e = np.where(a_zero, 1.0, a), np.where(e_zero, 1.0, e)
    denom = a * e - b * b
    skew = denom > PARALLEL * a * e
    s = np.where(skew, np.clip((b * f - c * e) / np.where(skew, denom, 1.0), 0.0, 1.0), 0.0)
    s = np.where(e_zero, np.clip(-c / safe_a, 0.0, 1.0), s)
    s = np.where(a_zero, 0.0, s)
    t = np.where(e_zero, 0.0, (b * s + f) / safe_e)
    below, above = t < 0.0, t > 1.0
    t = np.clip(t, 0.0, 1.0)
    s = np.where(below, np.clip(-c / safe_a, 0.0, 1.0), s)
    s = np.where(above, np.clip((b - c) / safe_a, 0.0, 1.0), s)
    s = np.where(a_zero, 0.0, s)
    return s, t


def _barycentric(p: np.ndarray, a: np.ndarray, ab: np.ndarray, ac: np.ndarray) -> tuple[np.ndarray, ...]:
    """Coordinates (v, w) of p's projection a + v ab + w ac on the triangle's plane, and whether it is inside."""
    ap = p - a
    d00, d01, d11 = dot(ab, ab), dot(ab, ac), dot(ac, ac)
    d20, d21 = dot(ap, ab), dot(ap, ac)
    den = d00 * d11 - d01 * d01
    ok = den > PARALLEL * d00 * d11
    safe = np.where(ok, den, 1.0)
    v = (d11 * d20 - d01 * d21) / safe
    w = (d00 * d21 - d01 * d20) / safe
    inside = ok & (v >= 0.0) & (w >= 0.0) & (v + w <= 1.0)
    return v, w, inside


def point_triangle(p: np.ndarray, a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    """The point (..., 3) of the triangle a, b, c closest to p: its projection on the plane when that falls
    inside, else the closest point of the three edges."""
    ab, ac = b - a, c - a
    v, w, inside = _barycentric(p, a, ab, ac)
    starts = np.stack([a, b, c], axis=-2)
    ends = np.stack([b, c, a], axis=-2)
    _, on_edges = point_segment(p[..., None, :], starts, ends)
    gap = on_edges - p[..., None, :]
    best = np.argmin(dot(gap, gap), axis=-1)
    on_edge = np.take_along_axis(on_edges, best[..., None, None], axis=-2)[..., 0, :]
    on_plane = a + v[..., None] * ab + w[..., None] * ac
    return np.where(inside[..., None], on_plane, on_edge)


def segment_triangle(
    p0: np.ndarray, p1: np.ndarray, a: np.ndarray, b: np.ndarray, c: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Closest points of a segment and a triangle: (t on the segment, point on the segment, point on the triangle).

    If the segment pierces the triangle both points are the piercing point. Otherwise the closest pair has an
    end of the segment over the triangle's inside, or an edge of the triangle, in it (an interior pair only occurs
    for a segment parallel to the plane, and then an end or an edge crossing is as close; an end whose projection
    falls outside is beaten by that edge), so the best of 2 end projections and 3 segment-edge pairs is exact.
    """
    u, ab, ac = p1 - p0, b - a, c - a
    n = np.cross(ab, ac)
    nn = dot(n, n)
    h0, h1 = dot(n, p0 - a), dot(n, p1 - a)  # heights above the plane, times |n|
    crosses = (h0 * h1 <= 0.0) & (h0 != h1)
    tx = np.where(crosses, h0 / np.where(crosses, h0 - h1, 1.0), 0.0)
    ends = np.stack([p0, p0 + tx[..., None] * u, p1], axis=-2)  # end 0, the plane crossing, end 1
    heights = np.stack([h0, np.zeros_like(h0), h1], axis=-1) / np.where(nn > 0, nn, 1.0)[..., None]
    on_plane = ends - heights[..., None] * n[..., None, :]
    _, _, over = _barycentric(on_plane, a[..., None, :], ab[..., None, :], ac[..., None, :])
    over[..., 1] &= crosses
    plane_d2 = np.where(over, heights**2 * nn[..., None], np.inf)
    plane_d2[..., 1] = np.where(over[..., 1], 0.0, np.inf)
    starts = np.stack([a, b, c], axis=-2)
    dirs = np.stack([ab, c - b, -ac], axis=-2)
    s, r = segment_segment(p0[..., None, :], p1[..., None, :], starts, starts + dirs)
    edge_x = p0[..., None, :] + s[..., None] * u[..., None, :]
    edge_y = starts + r[..., None] * dirs
    gap = edge_x - edge_y
    cand_t = np.concatenate([np.stack([np.zeros_like(tx), tx, np.ones_like(tx)], axis=-1), s], axis=-1)
    cand_x = np.concatenate([ends, edge_x], axis=-2)
    cand_y = np.concatenate([on_plane, edge_y], axis=-2)
    best = np.argmin(np.concatenate([plane_d2, dot(gap, gap)], axis=-1), axis=-1)[..., None]
    t = np.take_along_axis(cand_t, best, axis=-1)[..., 0]
    xs = np.take_along_axis(cand_x, best[..., None], axis=-2)[..., 0, :]
    ys = np.take_along_axis(cand_y, best[..., None], axis=-2)[..., 0, :]
    return t, xs, ys
