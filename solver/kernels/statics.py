"""Static loads on the tree as loops over the links (the kernels of :mod:`solver.body.statics`).

Subtree sums are taken directly over the tree: with the links listed parents first (``order``), one reverse loop
adds every link's sum into its parent's; ancestor sums are one forward loop. Units: N, N*m, m.
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
    axis: np.ndarray,
    com: np.ndarray,
    w: np.ndarray,
    tables: tuple,
    points: np.ndarray,
    forces: np.ndarray,
    totals: np.ndarray,
    wrench: np.ndarray,
    loads: np.ndarray,
) -> None:
    """Fill the sole corners' and loads' ``points`` (m) and ``forces`` (N) (corners first, then loads), ``totals``
    (6,) [force N, moment about the world origin N*m], ``wrench`` (n, 6) per joint the same over its subtree, and
    ``loads`` (n,) the joint loads about their axes (N*m; the force along the axis, N, if prismatic)."""
    order, parent, prismatic, gravity_force, point_link, point_local, var_corner, var_direction, load_force = tables
    n, c = order.shape[0], point_link.shape[0] - load_force.shape[0]  # links, sole corners
    for k in range(points.shape[0]):
        link = point_link[k]
        for r in range(3):
            points[k, r] = position[link, r] + (
                rotation[link, r, 0] * point_local[k, 0]
                + rotation[link, r, 1] * point_local[k, 1]
                + rotation[link, r, 2] * point_local[k, 2]
            )
            forces[k, r] = 0.0 if k < c else load_force[k - c, r]
    for e in range(var_corner.shape[0]):
        for r in range(3):
            forces[var_corner[e], r] += w[e] * var_direction[e, r]
    for j in range(n):
        fx, fy, fz = gravity_force[j, 0], gravity_force[j, 1], gravity_force[j, 2]
        qx, qy, qz = com[j, 0], com[j, 1], com[j, 2]
        wrench[j, 0], wrench[j, 1], wrench[j, 2] = fx, fy, fz
        wrench[j, 3], wrench[j, 4], wrench[j, 5] = qy * fz - qz * fy, qz * fx - qx * fz, qx * fy - qy * fx
    for k in range(points.shape[0]):
        j = point_link[k]
        fx, fy, fz = forces[k, 0], forces[k, 1], forces[k, 2]
        qx, qy, qz = points[k, 0], points[k, 1], points[k, 2]
        wrench[j, 0] += fx
        wrench[j, 1] += fy
        wrench[j, 2] += fz
        wrench[j, 3] += qy * fz - qz * fy
        wrench[j, 4] += qz * fx - qx * fz
        wrench[j, 5] += qx * fy - qy * fx
    for r in range(6):
        totals[r] = 0.0
    for k in range(n - 1, -1, -1):  # children before parents: each subtree is complete when it is added up
        j = order[k]
        p = parent[j]
        for r in range(6):
            if p >= 0:
                wrench[p, r] += wrench[j, r]
            else:
                totals[r] += wrench[j, r]
        ax, ay, az = axis[j, 0], axis[j, 1], axis[j, 2]
        if prismatic[j]:
            loads[j] = ax * wrench[j, 0] + ay * wrench[j, 1] + az * wrench[j, 2]
        else:  # a . (M - p x F) = a . M + (p x a) . F
            px, py, pz = position[j, 0], position[j, 1], position[j, 2]
            loads[j] = (
                (py * az - pz * ay) * wrench[j, 0]
                + (pz * ax - px * az) * wrench[j, 1]
                + (px * ay - py * ax) * wrench[j, 2]
                + ax * wrench[j, 3]
                + ay * wrench[j, 4]
                + az * wrench[j, 5]
            )


@kernel
def moment_derivatives(
    position: np.ndarray,
    axis: np.ndarray,
    com: np.ndarray,
    points: np.ndarray,
    forces: np.ndarray,
    wrench: np.ndarray,
    tables: tuple,
    outer: np.ndarray,
    g: np.ndarray,
    arms: np.ndarray,
    balance: np.ndarray,
) -> None:
    """Fill ``outer`` (n, 9) the subtree sums of q F^T (row-major, N*m), ``g`` (n, 3) d(total moment)/d theta_j
    (N*m per rad; per m if prismatic), ``arms`` (n_w, 3) q x d per contact edge (m), and ``balance`` (6, n + n_w)
    the balance Jacobian [d / d theta, d / d w]."""
    order, parent, prismatic, gravity_force, point_link, point_local, var_corner, var_direction, load_force = tables
    n = order.shape[0]
    for j in range(n):
        for r in range(3):
            for s in range(3):
                outer[j, 3 * r + s] = com[j, r] * gravity_force[j, s]
    for k in range(points.shape[0]):
        j = point_link[k]
        for r in range(3):
            for s in range(3):
                outer[j, 3 * r + s] += points[k, r] * forces[k, s]
    for k in range(n - 1, -1, -1):
        j = order[k]
        p = parent[j]
        if p >= 0:
            for r in range(9):
                outer[p, r] += outer[j, r]
    for j in range(n):
        ax, ay, az = axis[j, 0], axis[j, 1], axis[j, 2]
        fx, fy, fz = wrench[j, 0], wrench[j, 1], wrench[j, 2]
        if prismatic[j]:  # moving the subtree along a turns no force: a x F
            g[j, 0], g[j, 1], g[j, 2] = ay * fz - az * fy, az * fx - ax * fz, ax * fy - ay * fx
        else:  # sum (q - p)(a . F) - a ((q - p) . F)
            px, py, pz = position[j, 0], position[j, 1], position[j, 2]
            a_dot_f = ax * fx + ay * fy + az * fz
            rest = outer[j, 0] + outer[j, 4] + outer[j, 8] - (px * fx + py * fy + pz * fz)
            for r in range(3):
                along = outer[j, 3 * r] * ax + outer[j, 3 * r + 1] * ay + outer[j, 3 * r + 2] * az
                g[j, r] = along - position[j, r] * a_dot_f - axis[j, r] * rest
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
    position: np.ndarray,
    axis: np.ndarray,
    g: np.ndarray,
    arms: np.ndarray,
    coef: np.ndarray,
    weight: np.ndarray,
    tables: tuple,
    folded: np.ndarray,
    linear: np.ndarray,
    squared: np.ndarray,
) -> None:
    """Fill ``linear`` = coef @ J and ``squared`` = weight @ (J * J), both (n + n_w,), for J = d axis loads / d x
    (prismatic rows left out); ``folded`` (2, n, 9) is work space. J_ij = g_i . a_j for j revolute and i in its
    subtree, a_i . g_j for j strictly below i; the squares by the folded rows s(u) . s(v) = (u . v)^2."""
    order, parent, revolute, supporting, acts, var_direction = tables
    n = order.shape[0]
    below, above = folded[0], folded[1]  # subtree sums of factor g-rows; strict-ancestor sums of factor a-rows
    for j in range(n):
        cj, wj = coef[j] * revolute[j], weight[j] * revolute[j]
        for r in range(3):
            below[j, r] = cj * g[j, r]
        below[j, 3], below[j, 4], below[j, 5] = wj * g[j, 0] * g[j, 0], wj * g[j, 1] * g[j, 1], wj * g[j, 2] * g[j, 2]
        below[j, 6] = wj * ROOT_TWO * g[j, 0] * g[j, 1]
        below[j, 7] = wj * ROOT_TWO * g[j, 0] * g[j, 2]
        below[j, 8] = wj * ROOT_TWO * g[j, 1] * g[j, 2]
    for k in range(n - 1, -1, -1):
        j = order[k]
        p = parent[j]
        if p >= 0:
            for r in range(9):
                below[p, r] += below[j, r]
    for k in range(n):
        j = order[k]
        p = parent[j]
        if p < 0:
            for r in range(9):
                above[j, r] = 0.0
        else:
            cp, wp = coef[p] * revolute[p], weight[p] * revolute[p]
            bx, by, bz = axis[p, 0], axis[p, 1], axis[p, 2]
            above[j, 0], above[j, 1], above[j, 2] = above[p, 0] + cp * bx, above[p, 1] + cp * by, above[p, 2] + cp * bz
            above[j, 3], above[j, 4], above[j, 5] = (
                above[p, 3] + wp * bx * bx,
                above[p, 4] + wp * by * by,
                above[p, 5] + wp * bz * bz,
            )
            above[j, 6] = above[p, 6] + wp * ROOT_TWO * bx * by
            above[j, 7] = above[p, 7] + wp * ROOT_TWO * bx * bz
            above[j, 8] = above[p, 8] + wp * ROOT_TWO * by * bz
    for j in range(n):
        ax, ay, az = axis[j, 0], axis[j, 1], axis[j, 2]
        gx, gy, gz = g[j, 0], g[j, 1], g[j, 2]
        rev = revolute[j]
        a_rows = (ax, ay, az, ax * ax, ay * ay, az * az, ROOT_TWO * ax * ay, ROOT_TWO * ax * az, ROOT_TWO * ay * az)
        g_rows = (gx, gy, gz, gx * gx, gy * gy, gz * gz, ROOT_TWO * gx * gy, ROOT_TWO * gx * gz, ROOT_TWO * gy * gz)
        lin, sq = 0.0, 0.0
        for r in range(9):
            term = rev * below[j, r] * a_rows[r] + above[j, r] * g_rows[r]
            if r < 3:
                lin += term
            else:
                sq += term
        linear[j], squared[j] = lin, sq
    n_w = var_direction.shape[0]
    for e in range(n_w):
        linear[n + e], squared[n + e] = 0.0, 0.0
    for row in range(supporting.shape[0]):  # the forces move only the loads of joints between root and supports
        j = supporting[row]
        cj, wj = coef[j] * revolute[j], weight[j] * revolute[j]
        ax, ay, az = axis[j, 0], axis[j, 1], axis[j, 2]
        px, py, pz = position[j, 0], position[j, 1], position[j, 2]
        ox, oy, oz = py * az - pz * ay, pz * ax - px * az, px * ay - py * ax  # p x a
        for e in range(n_w):
            if acts[row, e]:
                d = ax * arms[e, 0] + ay * arms[e, 1] + az * arms[e, 2]
                d += ox * var_direction[e, 0] + oy * var_direction[e, 1] + oz * var_direction[e, 2]
                linear[n + e] += cj * d
                squared[n + e] += wj * d * d
