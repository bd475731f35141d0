"""Capsules vs oriented boxes, one loop over the rows (the kernel of :func:`solver.collision.boxes.box_rows`: box
obstacles and the carried box).

Units: m. A row apart from its box is the exact distance of ``_outside`` in :mod:`solver.collision.boxes` (the same
pieces, knots and ties); a row whose axis meets its box, minus the penetration depth of ``_overlap`` (the same
separating axes), in a second loop over those rows only. A row whose axis only touches the surface (rounding's
case: the slab test counts touching as meeting) is left to the caller's NumPy code.
"""

from __future__ import annotations

import math

import numpy as np

from . import kernel

# copies, not imports: Numba's cache of this file's kernels would not see a change made in another file
TINY = 1e-24  # m^2: as solver.collision.closest.TINY
PARALLEL = 1e-12  # as solver.collision.closest.PARALLEL


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
    ``point``, ``normal`` (world), ``closest``. Rows whose axis meets the box are marked 1 in ``rare`` (zeros from the
    caller; :func:`box_rows_overlap` answers them), rows that only touch it 2; their fields unset. Returns how many."""
    count, work = 0, np.empty(26)
    for k in range(p0.shape[0]):
        c = 0 if center.shape[0] == 1 else k
        r = 0 if rotation.shape[0] == 1 else k
        g = 0 if half.shape[0] == 1 else k
        code = box_row_apart(p0, p1, radii, k, center, c, rotation, r, half, g, distance, t_out, point, normal,
                             closest, k, work)  # fmt: skip
        if code:
            rare[k] = code
            count += 1
    return count


@kernel
def box_row_apart(
    p0: np.ndarray,
    p1: np.ndarray,
    radii: np.ndarray,
    k: int,
    center: np.ndarray,
    c: int,
    rotation: np.ndarray,
    r: int,
    half: np.ndarray,
    g: int,
    distance: np.ndarray,
    t_out: np.ndarray,
    point: np.ndarray,
    normal: np.ndarray,
    closest: np.ndarray,
    o: int,
    work: np.ndarray,
) -> int:
    """One row of :func:`box_rows_apart`: capsule ``k`` vs the box of rows ``c``, ``r``, ``g`` of ``center``,
    ``rotation``, ``half``, its fields written at row ``o``; ``work`` (26,) scratch. Returns 0, or 1 when the axis
    meets the box, 2 when it only touches it (the fields unset)."""
    a, b, u, h = work[0:3], work[3:6], work[6:9], work[9:12]
    knots, gap, best_gap = work[12:20], work[20:23], work[23:26]
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
        return 1
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
        return 2
    distance[o], t_out[o] = axis - radii[k], best_t
    for i in range(3):
        point[o, i] = p0[k, i] + best_t * (p1[k, i] - p0[k, i])
        n = best_gap[0] / axis * rotation[r, i, 0] + best_gap[1] / axis * rotation[r, i, 1]
        normal[o, i] = n + best_gap[2] / axis * rotation[r, i, 2]
        closest[o, i] = point[o, i] - axis * normal[o, i]
    return 0


@kernel
def box_rows_overlap(p0: np.ndarray, p1: np.ndarray, radii: np.ndarray, center: np.ndarray, rotation: np.ndarray,
                     half: np.ndarray, rows: np.ndarray, distance: np.ndarray, t_out: np.ndarray, point: np.ndarray,
                     normal: np.ndarray, closest: np.ndarray) -> None:  # fmt: skip
    """:func:`box_rows_apart`'s fields for the ``rows`` whose capsule axis meets its box: minus the penetration depth
    along the best of the 3 face normals and the axis crossed with each edge's direction, and the deeper end (a face)
    or the point passing the box edge that sticks out furthest along it (an edge)."""
    a, b, u, h, axes, n = np.empty(3), np.empty(3), np.empty(3), np.empty(3), np.zeros((6, 3)), np.empty(3)
    e0, d2 = np.empty(3), np.empty(3)
    for m in range(rows.shape[0]):
        k = rows[m]
        c = 0 if center.shape[0] == 1 else k
        r = 0 if rotation.shape[0] == 1 else k
        g = 0 if half.shape[0] == 1 else k
        for j in range(3):  # box coordinates, as in box_rows_apart
            a[j] = (p0[k, 0] - center[c, 0]) * rotation[r, 0, j] + (p0[k, 1] - center[c, 1]) * rotation[r, 1, j]
            a[j] += (p0[k, 2] - center[c, 2]) * rotation[r, 2, j]
            b[j] = (p1[k, 0] - center[c, 0]) * rotation[r, 0, j] + (p1[k, 1] - center[c, 1]) * rotation[r, 1, j]
            b[j] += (p1[k, 2] - center[c, 2]) * rotation[r, 2, j]
            u[j], h[j] = b[j] - a[j], half[g, j]
        size = math.sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2])
        best, depth, up_best, down_best = 0, np.inf, 0.0, 0.0
        for i in range(6):
            for j in range(3):
                axes[i, j] = 0.0
            if i < 3:
                axes[i, i] = 1.0
            else:  # u x e_(i-3), made unit where it has a length
                e = i - 3
                axes[i, (e + 1) % 3], axes[i, (e + 2) % 3] = u[(e + 2) % 3], -u[(e + 1) % 3]
                length = math.sqrt(axes[i, 0] ** 2 + axes[i, 1] ** 2 + axes[i, 2] ** 2)
                if not length > 1e-9 * size:
                    continue
                for j in range(3):
                    axes[i, j] = axes[i, j] / length
            sa = axes[i, 0] * a[0] + axes[i, 1] * a[1] + axes[i, 2] * a[2]
            sb = axes[i, 0] * b[0] + axes[i, 1] * b[1] + axes[i, 2] * b[2]
            rho = abs(axes[i, 0]) * h[0] + abs(axes[i, 1]) * h[1] + abs(axes[i, 2]) * h[2]
            up, down = rho - min(sa, sb), max(sa, sb) + rho  # moves along +axis / -axis that separate
            if min(up, down) < depth:  # the first least, as np.argmin
                best, depth, up_best, down_best = i, min(up, down), up, down
        sign = 1.0 if up_best <= down_best else -1.0
        for j in range(3):
            n[j] = axes[best, j] * sign
        t = 0.0 if n[0] * a[0] + n[1] * a[1] + n[2] * a[2] <= n[0] * b[0] + n[1] * b[1] + n[2] * b[2] else 1.0
        if best >= 3:  # where the segment passes the box edge along e_i at the corner furthest along n: s of
            # segment_segment(a, b, e0, e1), its branches as in axes_closest (clamps as comparisons keep a NaN)
            i = best - 3
            for j in range(3):
                e0[j] = h[j] if n[j] >= 0.0 else -h[j]
                d2[j] = 0.0
            e0[i], d2[i] = -h[i], 2.0 * h[i]
            aa = u[0] * u[0] + u[1] * u[1] + u[2] * u[2]
            ee, bb = d2[i] * d2[i], u[i] * d2[i]
            cc = u[0] * (a[0] - e0[0]) + u[1] * (a[1] - e0[1]) + u[2] * (a[2] - e0[2])
            ff = d2[i] * (a[i] - e0[i])
            safe_a, safe_e, denom = max(aa, TINY), max(ee, TINY), aa * ee - bb * bb
            t = (bb * ff - cc * ee) / (1e-300 if denom < 1e-300 else denom)
            t = (0.0 if t < 0.0 else (1.0 if t > 1.0 else t)) * (1.0 if denom > PARALLEL * aa * ee else 0.0)
            lone = -cc / safe_a
            lone = 0.0 if lone < 0.0 else (1.0 if lone > 1.0 else lone)
            t = lone if ee <= TINY else t
            other = (bb * t + ff) / safe_e * (0.0 if ee <= TINY else 1.0)
            if other < 0.0:
                t = lone
            elif other > 1.0:
                t = (bb - cc) / safe_a
                t = 0.0 if t < 0.0 else (1.0 if t > 1.0 else t)
            t = t * (0.0 if aa <= TINY else 1.0)
        distance[k], t_out[k] = -depth - radii[k], t
        for i in range(3):
            point[k, i] = p0[k, i] + t * (p1[k, i] - p0[k, i])
            normal[k, i] = n[0] * rotation[r, i, 0] + n[1] * rotation[r, i, 1] + n[2] * rotation[r, i, 2]
            closest[k, i] = point[k, i] + depth * normal[k, i]
