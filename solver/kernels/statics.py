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
    (
        order,
        parent,
        gravity_force,
        point_link,
        point_local,
        var_corner,
        var_direction,
        load_force,
        start,
        end,
        gravity,
    ) = tables
    n, m, c = order.shape[0], points.shape[0], points.shape[0] - load_force.shape[0]  # links, points, sole corners
    for k in range(m):
        link, lx, ly, lz = point_link[k], point_local[k, 0], point_local[k, 1], point_local[k, 2]
        for r in range(3):
            rot = rotation[link, r]
            points[k, r] = position[link, r] + ((rot[0] * lx + rot[2] * lz) + rot[1] * ly)
            forces[k, r] = corner_forces[k, r] if k < c else load_force[k - c, r]
    bx, by, bz, fx, fy, fz = body_com[0], body_com[1], body_com[2], gravity[3], gravity[4], gravity[5]
    totals[0], totals[1], totals[2] = 0.0, 0.0, 0.0
    totals[3], totals[4], totals[5] = by * fz - bz * fy, bz * fx - bx * fz, bx * fy - by * fx
    extra = np.zeros((n, 6))  # per link, its extra points' wrenches in their order
    for k in range(m):
        fx, fy, fz, qx, qy, qz = forces[k, 0], forces[k, 1], forces[k, 2], points[k, 0], points[k, 1], points[k, 2]
        row = (fx, fy, fz, qy * fz - qz * fy, qz * fx - qx * fz, qx * fy - qy * fx)
        for r in range(6):
            extra[point_link[k], r] += row[r]
            totals[r] = row[r] if (k == 0 and r < 3) else totals[r] + row[r]
    for r in range(3):
        totals[r] = gravity[r] + totals[r]
    prefix = np.zeros((n + 1, 6))
    for k in range(n):
        j = order[k]
        fx, fy, fz, qx, qy, qz = (
            gravity_force[j, 0],
            gravity_force[j, 1],
            gravity_force[j, 2],
            com[j, 0],
            com[j, 1],
            com[j, 2],
        )
        row = (fx, fy, fz, qy * fz - qz * fy, qz * fx - qx * fz, qx * fy - qy * fx)
        for r in range(6):
            prefix[k + 1, r] = prefix[k, r] + ((row[r] + extra[j, r]) if m > 0 else row[r])
    for j in range(n):
        for r in range(6):
            wrench[j, r] = prefix[end[j], r] - prefix[start[j], r]
        t, u = twist[j], wrench[j]
        loads[j] = ((t[0] * u[0] + t[2] * u[2]) + t[4] * u[4]) + ((t[1] * u[1] + t[3] * u[3]) + t[5] * u[5])


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
    order, parent, gravity_force, point_link, point_local, var_corner, var_direction, load_force, start, end, _ = tables
    n, m = order.shape[0], points.shape[0]
    extra = np.zeros((n, 9))  # per link, its extra points' q F^T in their order
    for k in range(m):
        for r in range(9):
            extra[point_link[k], r] += points[k, r // 3] * forces[k, r % 3]
    prefix = np.zeros((n + 1, 9))
    for k in range(n):
        j = order[k]
        for r in range(9):
            value = com[j, r // 3] * gravity_force[j, r % 3]
            prefix[k + 1, r] = prefix[k, r] + ((value + extra[j, r]) if m > 0 else value)
    for j in range(n):
        for r in range(9):
            outer[j, r] = prefix[end[j], r] - prefix[start[j], r]
        a, f, p, o = axis[j], wrench[j], position[j], outer[j]
        if prismatic[j]:  # moving the subtree along a turns no force: a x F
            g[j, 0], g[j, 1], g[j, 2] = a[1] * f[2] - a[2] * f[1], a[2] * f[0] - a[0] * f[2], a[0] * f[1] - a[1] * f[0]
        else:  # sum (q - p)(a . F) - a ((q - p) . F)
            a_dot_f = (a[0] * f[0] + a[1] * f[1]) + a[2] * f[2]  # in order: einsum's loop for strided a and p
            rest = ((o[0] + o[4]) + o[8]) - ((p[0] * f[0] + p[1] * f[1]) + p[2] * f[2])
            for r in range(3):
                along = (o[3 * r] * a[0] + o[3 * r + 1] * a[1]) + o[3 * r + 2] * a[2]
                g[j, r] = (along - p[r] * a_dot_f) - a[r] * rest
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
