"""Capsules vs oriented boxes, one loop over the rows (the kernel of :func:`solver.collision.boxes.box_rows`: box
obstacles and the carried box).

Units: m. A row whose capsule axis meets its box (the penetration depth by separating axes) or touches its surface
(the face's normal) is rare and left to the caller, which answers it with the NumPy code; every other row is the
exact distance of :func:`solver.collision.boxes._outside`, the same pieces, knots and ties.
"""

from __future__ import annotations

import math

import numpy as np

from . import kernel


@kernel
def box_rows_apart(
    p0: np.ndarray,
    p1: np.ndarray,
    radii: np.ndarray,
    center: np.ndarray,
    rotation: np.ndarray,
    half: np.ndarray,
    distance: np.ndarray,
    t_out: np.ndarray,
    point: np.ndarray,
    normal: np.ndarray,
    closest: np.ndarray,
    rare: np.ndarray,
) -> int:
    """Row k: capsule ``p0[k]``-``p1[k]`` of ``radii[k]`` vs the box ``center``, ``rotation`` (axes as columns),
    ``half`` sizes (row k, or row 0 of a one-row array), filling the Proximity fields ``distance``, ``t_out``,
    ``point``, ``normal`` (world), ``closest``. Rows whose axis meets or touches the box are marked True in
    ``rare`` (all False from the caller; their fields unset); returns how many."""
    a, b, u, h, knots = np.empty(3), np.empty(3), np.empty(3), np.empty(3), np.empty(8)
    count, gap, best_gap = 0, np.empty(3), np.empty(3)
    for k in range(p0.shape[0]):
        c = 0 if center.shape[0] == 1 else k
        r = 0 if rotation.shape[0] == 1 else k
        g = 0 if half.shape[0] == 1 else k
        for j in range(3):  # box coordinates: (p - center) @ rotation
            a[j] = (p0[k, 0] - center[c, 0]) * rotation[r, 0, j] + (p0[k, 1] - center[c, 1]) * rotation[r, 1, j]
            a[j] += (p0[k, 2] - center[c, 2]) * rotation[r, 2, j]
            b[j] = (p1[k, 0] - center[c, 0]) * rotation[r, 0, j] + (p1[k, 1] - center[c, 1]) * rotation[r, 1, j]
            b[j] += (p1[k, 2] - center[c, 2]) * rotation[r, 2, j]
            u[j], h[j] = b[j] - a[j], half[g, j]
        enter, leave = -np.inf, np.inf  # slab test: does the axis segment meet the box?
        for j in range(3):
            if u[j] == 0.0:
                lo, hi = (-np.inf if abs(a[j]) <= h[j] else np.inf), np.inf
            else:
                lo, hi = (-h[j] - a[j]) / u[j], (h[j] - a[j]) / u[j]
            enter, leave = max(enter, min(lo, hi)), min(leave, max(lo, hi))
        if max(enter, 0.0) <= min(leave, 1.0):
            rare[k] = True
            count += 1
            continue
        knots[0], knots[1] = 0.0, 1.0  # where a coordinate meets a face plane (0 for one that does not move)
        for j in range(3):
            knots[2 + j] = (h[j] - a[j]) / u[j] if u[j] != 0.0 else 0.0
            knots[5 + j] = (-h[j] - a[j]) / u[j] if u[j] != 0.0 else 0.0
        for i in range(8):
            knots[i] = min(max(knots[i], 0.0), 1.0)
        knots.sort()
        best, best_t = np.inf, 0.0
        for p in range(7):  # the piece's quadratic in the coordinates outside their slab, clipped to the piece
            mid = 0.5 * (knots[p] + knots[p + 1])
            squared, pull = 0.0, 0.0
            for j in range(3):
                xj = a[j] + mid * u[j]
                side = min(max(xj, -h[j]), h[j])
                if xj != side:
                    squared += u[j] * u[j]
                    pull += (side - a[j]) * u[j]
            t = min(max(pull / (squared if squared > 0.0 else 1.0), knots[p]), knots[p + 1])
            d2 = 0.0
            for j in range(3):
                xj = a[j] + t * u[j]
                gap[j] = xj - min(max(xj, -h[j]), h[j])
                d2 += gap[j] * gap[j]
            if d2 < best:  # the first least, as np.argmin
                best, best_t = d2, t
                best_gap[0], best_gap[1], best_gap[2] = gap[0], gap[1], gap[2]
        axis = math.sqrt(best)
        if axis <= 1e-150:  # on the surface: the face's normal, by the caller
            rare[k] = True
            count += 1
            continue
        distance[k], t_out[k] = axis - radii[k], best_t
        for i in range(3):
            point[k, i] = p0[k, i] + best_t * (p1[k, i] - p0[k, i])
            n = best_gap[0] / axis * rotation[r, i, 0] + best_gap[1] / axis * rotation[r, i, 1]
            normal[k, i] = n + best_gap[2] / axis * rotation[r, i, 2]
            closest[k, i] = point[k, i] - axis * normal[k, i]
    return count
