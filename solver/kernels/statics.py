"""Static loads on the tree as loops over the links (the kernels of :mod:`solver.body.statics`).

Every sum is taken in the NumPy path's order, so the two agree to the bit: per-link sums of the extra points in
their order (as the 0/1 product with ``extra_on_link``), subtree sums as differences of prefix sums in preorder and
ancestor sums as entered minus closed prefixes (:class:`solver.body.tree.TreeSums`), three- and six-term dot
products in ``np.einsum``'s two lanes (even terms, odd terms, then their sum), rows summed in order as
``sum(axis=0)``. Products NumPy leaves to BLAS (the whole-body COM, the force block of the load contractions) are
computed by the caller with the same NumPy call. Units: N, N*m, m.
"""

from __future__ import annotations

import math

import numpy as np

from . import kernel

ROOT_TWO = math.sqrt(2.0)  # the folded off-diagonal pairs of a symmetric outer product


@kernel
def twists(
    position: np.ndarray, axis: np.ndarray, prismatic: np.ndarray, twist: np.ndarray, origin: np.ndarray
) -> None:
    """Fill ``origin`` (n, 3) p x a, m/s per unit rate, and ``twist`` (n, 6) [p x a, a] ([a, 0] if prismatic)."""
    for j in range(position.shape[0]):
        px, py, pz = position[j, 0], position[j, 1], position[j, 2]
        ax, ay, az = axis[j, 0], axis[j, 1], axis[j, 2]
        origin[j, 0] = py * az - pz * ay
        origin[j, 1] = pz * ax - px * az
        origin[j, 2] = px * ay - py * ax
        for r in range(3):
            if prismatic[j]:
                twist[j, r] = axis[j, r]
                twist[j, 3 + r] = 0.0
            else:
                twist[j, r] = origin[j, r]
                twist[j, 3 + r] = axis[j, r]


@kernel
def point_loads(
    rotation: np.ndarray,
    position: np.ndarray,
    com: np.ndarray,
    corner_forces: np.ndarray,
    body_com: np.ndarray,
    tables: tuple,
    points: np.ndarray,
    forces: np.ndarray,
    totals: np.ndarray,
    wrench: np.ndarray,
    loads: np.ndarray,
    twist: np.ndarray,
) -> None:
    """Fill the sole corners' and loads' ``points`` (m) and ``forces`` (N) (corners first, then loads: the corners'
    ``corner_forces`` (c, 3) are BLAS's sums over their edges, the caller's), ``totals``
    (6,) [force N, moment about the world origin N*m] (gravity at ``body_com`` = mass @ com), ``wrench`` (n, 6) per
    joint the same over its subtree, and ``loads`` (n,) = twist . wrench per joint (``twist`` (n, 6) the joints')."""
    order, gravity_force, point_link, point_local, load_force = tables[0], tables[2], tables[3], tables[4], tables[7]
    start, end, gravity, link_first, link_points = tables[8], tables[9], tables[10], tables[11], tables[12]
    n, m, c = order.shape[0], points.shape[0], points.shape[0] - load_force.shape[0]  # links, points, sole corners
    for k in range(m):
        link, lx, ly, lz = point_link[k], point_local[k, 0], point_local[k, 1], point_local[k, 2]
        for r in range(3):  # as einsum "cij,cj->ci": terms 0 and 2, then 1
            turned = (rotation[link, r, 0] * lx + rotation[link, r, 2] * lz) + rotation[link, r, 1] * ly
            points[k, r] = position[link, r] + turned
            forces[k, r] = corner_forces[k, r] if k < c else load_force[k - c, r]
    extra = np.zeros((m + 1, 6))  # the extra points' wrenches; row m: their sums, rows summed in order
    for k in range(m):
        fx, fy, fz, qx, qy, qz = forces[k, 0], forces[k, 1], forces[k, 2], points[k, 0], points[k, 1], points[k, 2]
        extra[k, 0], extra[k, 1], extra[k, 2] = fx, fy, fz
        extra[k, 3], extra[k, 4], extra[k, 5] = qy * fz - qz * fy, qz * fx - qx * fz, qx * fy - qy * fx
        for r in range(6):
            extra[m, r] = extra[k, r] if k == 0 else extra[m, r] + extra[k, r]
    bx, by, bz, fx, fy, fz = body_com[0], body_com[1], body_com[2], gravity[3], gravity[4], gravity[5]
    totals[0], totals[1], totals[2] = gravity[0] + extra[m, 0], gravity[1] + extra[m, 1], gravity[2] + extra[m, 2]
    totals[3], totals[4], totals[5] = by * fz - bz * fy, bz * fx - bx * fz, bx * fy - by * fx
    for r in range(3, 6):
        for k in range(m):
            totals[r] += extra[k, r]
    prefix, own = np.zeros((n + 1, 6)), np.empty(6)
    for k in range(n):
        j = order[k]
        fx, fy, fz = gravity_force[j, 0], gravity_force[j, 1], gravity_force[j, 2]
        qx, qy, qz = com[j, 0], com[j, 1], com[j, 2]
        own[0], own[1], own[2] = fx, fy, fz
        own[3], own[4], own[5] = qy * fz - qz * fy, qz * fx - qx * fz, qx * fy - qy * fx
        first, last = link_first[j], link_first[j + 1]
        if m > 0:  # + its extra points, as the 0/1 product adds them (from zero, in their order)
            for r in range(6):
                more = 0.0
                for q in range(first, last):
                    more += extra[link_points[q], r]
                own[r] += more
        for r in range(6):
            prefix[k + 1, r] = prefix[k, r] + own[r]
    for j in range(n):
        for r in range(6):
            wrench[j, r] = prefix[end[j], r] - prefix[start[j], r]
    for j in range(n):
        even = (twist[j, 0] * wrench[j, 0] + twist[j, 2] * wrench[j, 2]) + twist[j, 4] * wrench[j, 4]
        odd = (twist[j, 1] * wrench[j, 1] + twist[j, 3] * wrench[j, 3]) + twist[j, 5] * wrench[j, 5]
        loads[j] = even + odd  # einsum's two lanes


@kernel
def moment_derivatives(
    position: np.ndarray,
    axis: np.ndarray,
    com: np.ndarray,
    points: np.ndarray,
    forces: np.ndarray,
    wrench: np.ndarray,
    tables: tuple,
    prismatic: np.ndarray,
    outer: np.ndarray,
    g: np.ndarray,
    arms: np.ndarray,
    balance: np.ndarray,
) -> None:
    """Fill ``outer`` (n, 9) the subtree sums of q F^T (row-major, N*m), ``g`` (n, 3) d(total moment)/d theta_j
    (N*m per rad; per m if prismatic), ``arms`` (n_w, 3) q x d per contact edge (m), and ``balance`` (6, n + n_w)
    the balance Jacobian [d / d theta, d / d w]."""
    order, _, gravity_force, _, _, var_corner, var_direction, _, start, end, _, link_first, link_points = tables
    n, m = order.shape[0], points.shape[0]
    prefix = np.zeros((n + 1, 9))  # subtree sums of q F^T as differences of prefix sums in preorder
    more = np.zeros(9)  # a link's extra points' sum, as the 0/1 product adds them (from zero, in their order)
    for k in range(n):
        j = order[k]
        first, last = link_first[j], link_first[j + 1]
        if first < last:
            for r in range(9):
                more[r] = 0.0
            for q in range(first, last):
                for r in range(3):
                    for s in range(3):
                        more[3 * r + s] += points[link_points[q], r] * forces[link_points[q], s]
        for r in range(3):
            for s in range(3):
                value = com[j, r] * gravity_force[j, s]
                if m > 0:
                    value += more[3 * r + s] if first < last else 0.0
                prefix[k + 1, 3 * r + s] = prefix[k, 3 * r + s] + value
    for j in range(n):
        for r in range(9):
            outer[j, r] = prefix[end[j], r] - prefix[start[j], r]
    for j in range(n):
        ax, ay, az = axis[j, 0], axis[j, 1], axis[j, 2]
        fx, fy, fz = wrench[j, 0], wrench[j, 1], wrench[j, 2]
        if prismatic[j]:  # moving the subtree along a turns no force: a x F
            g[j, 0], g[j, 1], g[j, 2] = ay * fz - az * fy, az * fx - ax * fz, ax * fy - ay * fx
        else:  # sum (q - p)(a . F) - a ((q - p) . F), the dots in order (einsum's loop for the strided a and p)
            a_dot_f = (ax * fx + ay * fy) + az * fz
            rest = ((outer[j, 0] + outer[j, 4]) + outer[j, 8]) - (
                (position[j, 0] * fx + position[j, 1] * fy) + position[j, 2] * fz
            )
            for r in range(3):
                along = (outer[j, 3 * r] * ax + outer[j, 3 * r + 1] * ay) + outer[j, 3 * r + 2] * az
                g[j, r] = (along - position[j, r] * a_dot_f) - axis[j, r] * rest
        for r in range(3):
            balance[r, j] = 0.0
            balance[3 + r, j] = g[j, r]
    for e in range(var_corner.shape[0]):
        q = var_corner[e]
        dx, dy, dz = var_direction[e, 0], var_direction[e, 1], var_direction[e, 2]
        qx, qy, qz = points[q, 0], points[q, 1], points[q, 2]
        arms[e, 0], arms[e, 1], arms[e, 2] = qy * dz - qz * dy, qz * dx - qx * dz, qx * dy - qy * dx
        for r in range(3):
            balance[r, n + e] = var_direction[e, r]
            balance[3 + r, n + e] = arms[e, r]


@kernel
def load_contractions(
    axis: np.ndarray,
    g: np.ndarray,
    coef: np.ndarray,
    weight: np.ndarray,
    tables: tuple,
    work: np.ndarray,
    linear: np.ndarray,
    squared: np.ndarray,
) -> None:
    """Fill the joints' part (n,) of ``linear`` = coef @ J and ``squared`` = weight @ (J * J) for J = d axis loads /
    d theta (prismatic rows left out); ``work`` (3, n + 1, 9) is work space. J_ij = g_i . a_j for j revolute and i
    in its subtree, a_i . g_j for j strictly below i; the squares by the folded rows s(u) . s(v) = (u . v)^2."""
    order, revolute, start, end, after, by_end, closed_before = tables
    n = order.shape[0]
    sub, entered, closed = work[0], work[1], work[2]  # prefix sums in preorder (g-rows, a-rows), in closing order
    for r in range(9):
        sub[0, r], entered[0, r], closed[0, r] = 0.0, 0.0, 0.0
    for k in range(n):
        j, i = order[k], by_end[k]
        cj, wj, ci, wi = coef[j] * revolute[j], weight[j] * revolute[j], coef[i] * revolute[i], weight[i] * revolute[i]
        gx, gy, gz, ax, ay, az, bx, by, bz = (
            g[j, 0],
            g[j, 1],
            g[j, 2],
            axis[j, 0],
            axis[j, 1],
            axis[j, 2],
            axis[i, 0],
            axis[i, 1],
            axis[i, 2],
        )
        g_rows = (gx, gy, gz, gx * gx, gy * gy, gz * gz, gx * gy * ROOT_TWO, gx * gz * ROOT_TWO, gy * gz * ROOT_TWO)
        a_rows = (ax, ay, az, ax * ax, ay * ay, az * az, ax * ay * ROOT_TWO, ax * az * ROOT_TWO, ay * az * ROOT_TWO)
        b_rows = (bx, by, bz, bx * bx, by * by, bz * bz, bx * by * ROOT_TWO, bx * bz * ROOT_TWO, by * bz * ROOT_TWO)
        for r in range(9):
            fj, fi = (cj, ci) if r < 3 else (wj, wi)
            sub[k + 1, r] = sub[k, r] + fj * g_rows[r]
            entered[k + 1, r] = entered[k, r] + fj * a_rows[r]
            closed[k + 1, r] = closed[k, r] + fi * b_rows[r]
    for j in range(n):
        cj, wj = coef[j] * revolute[j], weight[j] * revolute[j]
        gx, gy, gz, ax, ay, az = g[j, 0], g[j, 1], g[j, 2], axis[j, 0], axis[j, 1], axis[j, 2]
        g_rows = (gx, gy, gz, gx * gx, gy * gy, gz * gz, gx * gy * ROOT_TWO, gx * gz * ROOT_TWO, gy * gz * ROOT_TWO)
        a_rows = (ax, ay, az, ax * ax, ay * ay, az * az, ax * ay * ROOT_TWO, ax * az * ROOT_TWO, ay * az * ROOT_TWO)
        lin, sq = 0.0, 0.0
        for r in range(9):
            a_r, g_r = a_rows[r], g_rows[r]
            from_ancestors = (sub[end[j], r] - sub[start[j], r]) * revolute[j]
            from_descendants = (entered[after[j], r] - closed[closed_before[j], r]) - (cj if r < 3 else wj) * a_r
            both = from_ancestors * a_r + from_descendants * g_r
            if r == 0:
                lin = both
            elif r < 3:
                lin += both
            elif r == 3:
                sq = both
            else:
                sq += both
        linear[j], squared[j] = lin, sq
