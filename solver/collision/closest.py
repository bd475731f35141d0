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
    """Row-wise dot product of 3-vectors (last axis); faster than einsum on the arrays met here."""
    return x[..., 0] * y[..., 0] + x[..., 1] * y[..., 1] + x[..., 2] * y[..., 2]


def cross(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Row-wise cross product of 3-vectors (np.cross does the same, several times slower on small arrays)."""
    out = np.empty(np.broadcast_shapes(x.shape, y.shape))
    x0, x1, x2, y0, y1, y2 = x[..., 0], x[..., 1], x[..., 2], y[..., 0], y[..., 1], y[..., 2]
    out[..., 0] = x1 * y2 - x2 * y1
    out[..., 1] = x2 * y0 - x0 * y2
    out[..., 2] = x0 * y1 - x1 * y0
    return out


def clip01(x: np.ndarray) -> np.ndarray:
    """x clamped to [0, 1] (np.clip does the same, slower on small arrays)."""
    return np.minimum(np.maximum(x, 0.0), 1.0)


def unit(v: np.ndarray, fallback: np.ndarray) -> np.ndarray:
    """``v`` scaled to unit length along the last axis; rows of (near) zero length take ``fallback`` (unit)."""
    length = np.sqrt(dot(v, v))[..., None]
    ok = length > 1e-150  # below, |v|^2 is subnormal and its square root too imprecise to normalise by
    return np.where(ok, v / np.maximum(length, 1e-150), fallback)


def perpendicular(u: np.ndarray) -> np.ndarray:
    """A unit vector perpendicular to each ``u`` (..., 3); +z where u is zero."""
    u = np.asarray(u, dtype=float)
    axis = np.zeros(u.shape)
    smallest = np.argmin(np.abs(u), axis=-1)
    np.put_along_axis(axis, smallest[..., None], 1.0, axis=-1)
    ez = np.broadcast_to(np.array([0.0, 0.0, 1.0]), u.shape)
    return unit(cross(u, axis), ez)


def point_segment(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Parameter t (...) and point (..., 3) on the segment a-b closest to p (t = 0 for a zero-length segment)."""
    u = b - a
    t = clip01(dot(p - a, u) / np.maximum(dot(u, u), TINY))
    return t, a + t[..., None] * u


def distances_to_segments(points: tuple[np.ndarray, ...], a: np.ndarray, b: np.ndarray) -> list[np.ndarray]:
    """Distances (m) from each array of points (..., 3) to the segments a-b (..., 3), sharing the segments' set-up."""
    u = b - a
    inv = 1.0 / np.maximum(dot(u, u), TINY)
    out = []
    for p in points:
        w = p - a
        gap = w - clip01(dot(w, u) * inv)[..., None] * u
        out.append(np.sqrt(dot(gap, gap)))
    return out


def segment_segment(p0: np.ndarray, p1: np.ndarray, q0: np.ndarray, q1: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Parameters (s, t) of the closest points p0 + s (p1 - p0) and q0 + t (q1 - q0) of two segments.

    Minimises the convex quadratic |p(s) - q(t)|^2 on [0, 1]^2: s from the lines' closest points (0 when
    parallel) clamped, t optimal for that s; if t had to be clamped, s optimal for that t.
    """
    d1, d2, r = p1 - p0, q1 - q0, p0 - q0
    a, e, b, c, f = dot(d1, d1), dot(d2, d2), dot(d1, d2), dot(d1, r), dot(d2, r)
    a_zero, e_zero = a <= TINY, e <= TINY
    safe_a, safe_e = np.maximum(a, TINY), np.maximum(e, TINY)
    denom = a * e - b * b
    skew = denom > PARALLEL * a * e
    s = clip01((b * f - c * e) / np.maximum(denom, 1e-300)) * skew  # 0 when parallel (clip01 keeps it finite)
    s = np.where(e_zero, clip01(-c / safe_a), s)
    t = (b * s + f) / safe_e * ~e_zero
    s = np.where(t < 0.0, clip01(-c / safe_a), np.where(t > 1.0, clip01((b - c) / safe_a), s))
    return s * ~a_zero, clip01(t)


def _barycentric(p: np.ndarray, a: np.ndarray, ab: np.ndarray, ac: np.ndarray) -> tuple[np.ndarray, ...]:
    """Coordinates (v, w) of p's projection a + v ab + w ac on the triangle's plane, and whether it is inside."""
    ap = p - a
    d00, d01, d11 = dot(ab, ab), dot(ab, ac), dot(ac, ac)
    d20, d21 = dot(ap, ab), dot(ap, ac)
    den = d00 * d11 - d01 * d01
    ok = den > PARALLEL * d00 * d11
    safe = np.maximum(den, 1e-300)
    v = (d11 * d20 - d01 * d21) / safe
    w = (d00 * d21 - d01 * d20) / safe
    inside = ok & (v >= 0.0) & (w >= 0.0) & (v + w <= 1.0)
    return v, w, inside


def point_triangle(p: np.ndarray, a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    """The point (..., 3) of the triangle a, b, c closest to p: its projection on the plane when that falls
    inside, else the closest point of the three edges."""
    ab, ac = b - a, c - a
    v, w, inside = _barycentric(p, a, ab, ac)
    starts = np.stack(np.broadcast_arrays(a, b, c), axis=-2)
    ends = np.stack(np.broadcast_arrays(b, c, a), axis=-2)
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
    shape = np.broadcast_shapes(p0.shape, p1.shape, a.shape, b.shape, c.shape)
    if len(shape) != 2 or any(x.shape != shape for x in (p0, p1, a, b, c)):
        p0, p1, a, b, c = (np.broadcast_to(x, shape).reshape(-1, 3) for x in (p0, p1, a, b, c))
    u, ab, ac = p1 - p0, b - a, c - a
    n = cross(ab, ac)
    nn = dot(n, n)
    inv = 1.0 / np.maximum(nn, 1e-300)
    h0, h1 = dot(n, p0 - a), dot(n, p1 - a)  # heights above the plane, times |n|
    crosses = (h0 * h1 <= 0.0) & (h0 != h1)
    tx = h0 / np.where(crosses, h0 - h1, 1.0) * crosses
    m = len(p0)
    ends = np.empty((m, 6, 3))  # candidates on the segment: end 0, the plane crossing, end 1, 3 near edges
    ends[:, 0], ends[:, 1], ends[:, 2] = p0, p0 + tx[:, None] * u, p1
    heights = np.stack([h0, np.zeros(m), h1], axis=1) * inv[:, None]
    near = np.empty((m, 6, 3))  # the paired candidates on the triangle
    near[:, :3] = ends[:, :3] - heights[..., None] * n[:, None]
    ap = near[:, :3] - a[:, None]
    d20, d21 = dot(ap, ab[:, None]), dot(ap, ac[:, None])
    d00, d01, d11 = (dot(x, y)[:, None] for x, y in ((ab, ab), (ab, ac), (ac, ac)))
    v, w = (d11 * d20 - d01 * d21) * inv[:, None], (d00 * d21 - d01 * d20) * inv[:, None]
    over = (v >= 0.0) & (w >= 0.0) & (v + w <= 1.0) & (nn[:, None] > PARALLEL * d00 * d11)
    over[:, 1] &= crosses
    d2 = np.empty((m, 6))
    d2[:, :3] = np.where(over, heights**2 * nn[:, None], np.inf)
    starts, dirs = np.empty((m, 3, 3)), np.empty((m, 3, 3))
    starts[:, 0], starts[:, 1], starts[:, 2] = a, b, c
    dirs[:, 0], dirs[:, 1], dirs[:, 2] = ab, c - b, -ac
    s, r = segment_segment(p0[:, None], p1[:, None], starts, starts + dirs)
    ends[:, 3:] = p0[:, None] + s[..., None] * u[:, None]
    near[:, 3:] = starts + r[..., None] * dirs
    gap = ends[:, 3:] - near[:, 3:]
    d2[:, 3:] = dot(gap, gap)
    params = np.concatenate([np.zeros((m, 1)), tx[:, None], np.ones((m, 1)), s], axis=1)
    rows, best = np.arange(m), np.argmin(d2, axis=1)
    lead = shape[:-1]
    return params[rows, best].reshape(lead), ends[rows, best].reshape(shape), near[rows, best].reshape(shape)
