"""The carried box's Jacobian rows in one loop (the kernel of :func:`solver.collision.carried.carried_jacobian`: the
body's rows against the box and the box's rows against the obstacles).

Units: m. Per row, the terms of :func:`solver.collision.carried.carried_point_rows` (the box's material point moved by
the two TCPs) and :meth:`solver.body.model.Kinematics.jacobian_rows` (each term's velocity per joint), in the NumPy
code's order of operations.
"""

from __future__ import annotations

import math

import numpy as np

from . import kernel


@kernel
def _point_term(lx: float, ly: float, lz: float, p: np.ndarray, pr: int, twist: np.ndarray, j: int) -> float:
    """l . (velocity of the point ``p[pr]`` per unit rate of joint j), as ``point_jacobian_rows`` (no angular part)."""
    px, py, pz = p[pr, 0], p[pr, 1], p[pr, 2]
    t0, t1, t2 = 0.0 - (ly * pz - lz * py), 0.0 - (lz * px - lx * pz), 0.0 - (lx * py - ly * px)
    moved = t0 * twist[j, 3] + t1 * twist[j, 4] + t2 * twist[j, 5]
    return moved + lx * twist[j, 0] + ly * twist[j, 1] + lz * twist[j, 2]


@kernel
def carried_jacobian(
    held: np.ndarray,
    centre: np.ndarray,
    rotation: np.ndarray,
    length: float,
    on_box: np.ndarray,
    direction: np.ndarray,
    tcp_link: np.ndarray,
    own_point: np.ndarray,
    own_normal: np.ndarray,
    own_link: np.ndarray,
    descendant: np.ndarray,
    twist: np.ndarray,
    out: np.ndarray,
) -> None:
    """Fill ``out`` (k, >= n; zeros beyond n by the caller): row r is ``direction[r]`` . (velocity of the box's material
    point at ``on_box[r]`` (world m)) moved by the two TCPs at ``held`` (2, 3) m on links ``tcp_link`` (the box at
    ``centre``, ``rotation``; ``length`` the TCPs' distance, m), plus, where ``own_link[r]`` >= 0,
    ``own_normal[r]`` . (velocity of ``own_point[r]`` on that link); a joint moves a link where
    ``descendant[j, link]``; ``twist`` (n, 6)."""
    x0, x1, x2 = rotation[0, 0], rotation[1, 0], rotation[2, 0]
    z0, z1, z2 = rotation[0, 2], rotation[1, 2], rotation[2, 2]
    u0, u1, u2 = (0.0, 0.0, 1.0) if abs(x2) < 0.99 else (0.0, 1.0, 0.0)  # as carried._up
    along = u0 * x0 + u1 * x1 + u2 * x2
    s = math.sqrt(max(1.0 - along * along, 1e-24))
    for r in range(on_box.shape[0]):
        d0, d1, d2 = on_box[r, 0] - centre[0], on_box[r, 1] - centre[1], on_box[r, 2] - centre[2]
        bx = d0 * rotation[0, 0] + d1 * rotation[1, 0] + d2 * rotation[2, 0]
        by = d0 * rotation[0, 1] + d1 * rotation[1, 1] + d2 * rotation[2, 1]
        bz = d0 * rotation[0, 2] + d1 * rotation[1, 2] + d2 * rotation[2, 2]
        n0, n1, n2 = direction[r, 0], direction[r, 1], direction[r, 2]
        a0 = bz * n0 + by * (x1 * n2 - x2 * n1)  # bz n + by (x cross n)
        a1 = bz * n1 + by * (x2 * n0 - x0 * n2)
        a2 = bz * n2 + by * (x0 * n1 - x1 * n0)
        az = a0 * z0 + a1 * z1 + a2 * z2
        pa0, pa1, pa2 = a0 - z0 * az, a1 - z1 * az, a2 - z2 * az
        px = pa0 * x0 + pa1 * x1 + pa2 * x2
        g0 = bx * n0 + by * (n1 * z2 - n2 * z1) - (along * pa0 + u0 * px) / s
        g1 = bx * n1 + by * (n2 * z0 - n0 * z2) - (along * pa1 + u1 * px) / s
        g2 = bx * n2 + by * (n0 * z1 - n1 * z0) - (along * pa2 + u2 * px) / s
        gx = g0 * x0 + g1 * x1 + g2 * x2
        h0, h1, h2 = (g0 - x0 * gx) / length, (g1 - x1 * gx) / length, (g2 - x2 * gx) / length
        f0, f1, f2 = n0 / 2.0 - h0, n1 / 2.0 - h1, n2 / 2.0 - h2  # the first TCP's term
        e0, e1, e2 = n0 / 2.0 + h0, n1 / 2.0 + h1, n2 / 2.0 + h2  # the second's
        own = own_link[r]
        for j in range(twist.shape[0]):
            value = 0.0
            if own >= 0 and descendant[j, own]:
                value = _point_term(own_normal[r, 0], own_normal[r, 1], own_normal[r, 2], own_point, r, twist, j)
            if descendant[j, tcp_link[0]]:
                value = value + _point_term(f0, f1, f2, held, 0, twist, j)
            if descendant[j, tcp_link[1]]:
                value = value + _point_term(e0, e1, e2, held, 1, twist, j)
            out[r, j] = value
