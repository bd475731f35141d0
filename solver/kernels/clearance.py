"""The clearance rows' stages, each as one loop (the kernels of :mod:`solver.constraints.clearance` and
:mod:`solver.collision.distance`): the capsules' world ends, the floor's rows, the closest points of capsule axes
(the body's own pairs, capsule obstacles) and the self pairs' movement bound.

Units: m. Every kernel computes what its NumPy reference does, in the same order of operations where it matters
(the branches of :func:`solver.collision.closest.segment_segment`, NaN passed on as ``np.minimum`` does).
"""

from __future__ import annotations

import math

import numpy as np

from . import kernel

TINY = 1e-24  # m^2: as solver.collision.closest.TINY
PARALLEL = 1e-12  # as solver.collision.closest.PARALLEL


@kernel
def capsule_ends(
    rotation: np.ndarray,
    position: np.ndarray,
    link: np.ndarray,
    start: np.ndarray,
    end: np.ndarray,
    p0: np.ndarray,
    p1: np.ndarray,
) -> None:
    """Fill ``p0``, ``p1`` (k, 3) m: capsule k's ends ``start[k]``, ``end[k]`` (link frame, m) on link ``link[k]``
    of the pose (``rotation`` (n, 3, 3), ``position`` (n, 3) m)."""
    for k in range(link.shape[0]):
        a = link[k]
        for r in range(3):
            q0, q1, q2 = rotation[a, r, 0], rotation[a, r, 1], rotation[a, r, 2]
            p0[k, r] = position[a, r] + (q0 * start[k, 0] + q1 * start[k, 1] + q2 * start[k, 2])
            p1[k, r] = position[a, r] + (q0 * end[k, 0] + q1 * end[k, 1] + q2 * end[k, 2])


@kernel
def plane_rows(
    p0: np.ndarray,
    p1: np.ndarray,
    subset: np.ndarray,
    point: np.ndarray,
    normal: np.ndarray,
    radius: np.ndarray,
    far: float,
    height: np.ndarray,
    ends: np.ndarray,
) -> None:
    """A half-space's rows, a row per capsule end (starts first) of the capsules ``subset`` of ``p0``, ``p1``
    (k, 3) m: fill ``ends`` (2 s, 3) with the ends and ``height`` (2 s,) with n . (end - point) - ``radius`` (m),
    ``far`` where that is not finite."""
    s = subset.shape[0]
    for i in range(s):
        c = subset[i]
        for r in range(3):
            ends[i, r] = p0[c, r]
            ends[s + i, r] = p1[c, r]
    for i in range(2 * s):
        h = (ends[i, 0] - point[0]) * normal[0] + (ends[i, 1] - point[1]) * normal[1]
        h = h + (ends[i, 2] - point[2]) * normal[2] - radius[i]
        height[i] = h if math.isfinite(h) else far


@kernel
def least_bound(
    p0: np.ndarray,
    p1: np.ndarray,
    start: np.ndarray,
    end: np.ndarray,
    slack: np.ndarray,
    row_capsule: np.ndarray,
    row_other: np.ndarray,
    paired: bool,
) -> float:
    """The least ``slack`` (rows,) m less the most a row's gap can have changed since the capsules' ends were
    ``start``, ``end`` (k, 3) m and now are ``p0``, ``p1``: the largest move of a pair of ends (4 per pair of
    capsules ``row_capsule``, ``row_other`` when ``paired``; else the row capsule's 2 ends). NaN if any is NaN,
    +inf without rows (as ``ClearanceRows._least_bound``)."""
    least = np.inf
    for r in range(row_capsule.shape[0]):
        a = row_capsule[r]
        worst = -1.0
        for ea in range(2):
            x0 = (p0[a, 0] - start[a, 0]) if ea == 0 else (p1[a, 0] - end[a, 0])
            x1 = (p0[a, 1] - start[a, 1]) if ea == 0 else (p1[a, 1] - end[a, 1])
            x2 = (p0[a, 2] - start[a, 2]) if ea == 0 else (p1[a, 2] - end[a, 2])
            for eb in range(2 if paired else 1):
                d0, d1, d2 = x0, x1, x2
                if paired:
                    b = row_other[r]
                    d0 = x0 - ((p0[b, 0] - start[b, 0]) if eb == 0 else (p1[b, 0] - end[b, 0]))
                    d1 = x1 - ((p0[b, 1] - start[b, 1]) if eb == 0 else (p1[b, 1] - end[b, 1]))
                    d2 = x2 - ((p0[b, 2] - start[b, 2]) if eb == 0 else (p1[b, 2] - end[b, 2]))
                change = d0 * d0 + d1 * d1 + d2 * d2
                if change != change:
                    return np.nan
                if change > worst:
                    worst = change
        value = slack[r] - math.sqrt(worst)
        if value != value:
            return np.nan
        if value < least:
            least = value
    return least


@kernel
def axes_closest(
    p0: np.ndarray,
    p1: np.ndarray,
    q0: np.ndarray,
    q1: np.ndarray,
    first: np.ndarray,
    second: np.ndarray,
    s_out: np.ndarray,
    w_out: np.ndarray,
    t_out: np.ndarray,
    q_out: np.ndarray,
    normal: np.ndarray,
    length: np.ndarray,
) -> int:
    """Row m: the closest points of segment ``first[m]`` of p0-p1 and segment ``second[m]`` of q0-q1 (m): their
    parameters ``s_out``, ``t_out`` (:func:`solver.collision.closest.segment_segment`'s rule and branches), points
    ``w_out``, ``q_out``, the gap's ``length`` (m) and the unit ``normal`` from q to w (left as the gap where the
    length is <= 1e-150: the axes meet, the caller picks a normal). Returns how many rows' axes meet."""
    d1, d2, r = np.empty(3), np.empty(3), np.empty(3)
    meets = 0
    for m in range(first.shape[0]):
        i, j = first[m], second[m]
        for k in range(3):
            d1[k] = p1[i, k] - p0[i, k]
            d2[k] = q1[j, k] - q0[j, k]
            r[k] = p0[i, k] - q0[j, k]
        a = d1[0] * d1[0] + d1[1] * d1[1] + d1[2] * d1[2]
        e = d2[0] * d2[0] + d2[1] * d2[1] + d2[2] * d2[2]
        b = d1[0] * d2[0] + d1[1] * d2[1] + d1[2] * d2[2]
        c = d1[0] * r[0] + d1[1] * r[1] + d1[2] * r[2]
        f = d2[0] * r[0] + d2[1] * r[1] + d2[2] * r[2]
        safe_a = TINY if a < TINY else a
        safe_e = TINY if e < TINY else e
        denom = a * e - b * b
        # clamps written as comparisons keep a NaN, as np.minimum(np.maximum(x, 0), 1) does
        s = (b * f - c * e) / (1e-300 if denom < 1e-300 else denom)
        s = (0.0 if s < 0.0 else (1.0 if s > 1.0 else s)) * (1.0 if denom > PARALLEL * a * e else 0.0)
        lone = -c / safe_a  # s optimal for t = 0 (or for a point q)
        lone = 0.0 if lone < 0.0 else (1.0 if lone > 1.0 else lone)
        if e <= TINY:
            s = lone
        t = (b * s + f) / safe_e * (0.0 if e <= TINY else 1.0)
        if t < 0.0:
            s = lone
        elif t > 1.0:
            s = (b - c) / safe_a
            s = 0.0 if s < 0.0 else (1.0 if s > 1.0 else s)
        s = s * (0.0 if a <= TINY else 1.0)
        t = 0.0 if t < 0.0 else (1.0 if t > 1.0 else t)
        s_out[m], t_out[m] = s, t
        size = 0.0
        for k in range(3):
            w_out[m, k] = p0[i, k] + s * d1[k]
            q_out[m, k] = q0[j, k] + t * d2[k]
            normal[m, k] = w_out[m, k] - q_out[m, k]
            size += normal[m, k] * normal[m, k]
        size = math.sqrt(size)
        length[m] = size
        if size > 1e-150:
            for k in range(3):
                normal[m, k] = normal[m, k] / size
        else:
            meets += 1
    return meets


@kernel
def clearance_jacobian(
    point: np.ndarray,
    normal: np.ndarray,
    link: np.ndarray,
    other_point: np.ndarray,
    other_link: np.ndarray,
    rows: np.ndarray,
    descendant: np.ndarray,
    twist: np.ndarray,
    out: np.ndarray,
) -> None:
    """Fill ``out`` (len(rows), >= n; zeros beyond n by the caller): per row r of ``rows``, n . (velocity of
    ``point[r]`` carried by ``link[r]``) - n . (velocity of ``other_point[r]`` carried by ``other_link[r]``) per joint
    j (the second term only where ``other_link[r]`` >= 0), n = ``normal[r]``; a joint moves a link where
    ``descendant[j, link]``; ``twist`` (n, 6) [velocity of the world origin, spin]."""
    for m in range(rows.shape[0]):
        r = rows[m]
        lx, ly, lz = normal[r, 0], normal[r, 1], normal[r, 2]
        a, b = link[r], other_link[r]
        px, py, pz = point[r, 0], point[r, 1], point[r, 2]
        t0, t1, t2 = -(ly * pz - lz * py), -(lz * px - lx * pz), -(lx * py - ly * px)
        if b >= 0:
            qx, qy, qz = other_point[r, 0], other_point[r, 1], other_point[r, 2]
            u0, u1, u2 = -(ly * qz - lz * qy), -(lz * qx - lx * qz), -(lx * qy - ly * qx)
        for j in range(twist.shape[0]):
            along = lx * twist[j, 0] + ly * twist[j, 1] + lz * twist[j, 2]
            value = 0.0
            if descendant[j, a]:
                value = t0 * twist[j, 3] + t1 * twist[j, 4] + t2 * twist[j, 5] + along
            if b >= 0 and descendant[j, b]:
                value = value - (u0 * twist[j, 3] + u1 * twist[j, 4] + u2 * twist[j, 5] + along)
            out[m, j] = value


@kernel
def plane_distance(
    p0: np.ndarray,
    p1: np.ndarray,
    radii: np.ndarray,
    point: np.ndarray,
    normal: np.ndarray,
    distance: np.ndarray,
    t_out: np.ndarray,
    w_out: np.ndarray,
    n_out: np.ndarray,
    closest: np.ndarray,
) -> None:
    """Capsules p0-p1 (k, 3) m of ``radii`` (k,, or (1,) for all) vs the half-space through ``point`` with unit
    ``normal``: the lower end along the normal (p0 on a tie), as ``halfspace_distance``: fill ``distance`` (k,),
    ``t_out`` (0 or 1), the end ``w_out``, the normal ``n_out`` and ``closest`` (k, 3) m."""
    for k in range(p0.shape[0]):
        h0 = (p0[k, 0] - point[0]) * normal[0] + (p0[k, 1] - point[1]) * normal[1] + (p0[k, 2] - point[2]) * normal[2]
        h1 = (p1[k, 0] - point[0]) * normal[0] + (p1[k, 1] - point[1]) * normal[1] + (p1[k, 2] - point[2]) * normal[2]
        lower = h1 < h0
        h = h1 if lower else h0
        distance[k] = h - radii[0 if radii.shape[0] == 1 else k]
        t_out[k] = 1.0 if lower else 0.0
        for j in range(3):
            w = p1[k, j] if lower else p0[k, j]
            w_out[k, j], n_out[k, j] = w, normal[j]
            closest[k, j] = w - h * normal[j]
