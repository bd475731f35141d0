"""Forward kinematics as one loop over the links, parents first (the kernel of :meth:`solver.body.model.Model.forward`).

Units: m, rad. Each link's frame is its parent's world frame times its joint origin times its joint motion.
"""

from __future__ import annotations

import math

import numpy as np

from . import kernel


@kernel
def link_frames(
    theta: np.ndarray,
    order: np.ndarray,
    parent: np.ndarray,
    prismatic: np.ndarray,
    axis: np.ndarray,
    origin_rotation: np.ndarray,
    origin_position: np.ndarray,
    com: np.ndarray,
    rotation: np.ndarray,
    position: np.ndarray,
    world_axis: np.ndarray,
    world_com: np.ndarray,
) -> None:
    """Fill ``rotation`` (n, 3, 3), ``position`` (n, 3) m, ``world_axis`` (n, 3) and ``world_com`` (n, 3) m for the
    joint values ``theta``; ``order`` lists the links parents first."""
    local = np.empty((3, 3))
    motion = np.empty((3, 3))
    offset = np.empty(3)
    for k in range(order.shape[0]):
        j = order[k]
        value = theta[j]
        ax, ay, az = axis[j, 0], axis[j, 1], axis[j, 2]
        if prismatic[j]:
            for r in range(3):
                for c in range(3):
                    motion[r, c] = 1.0 if r == c else 0.0
            slide = (value * ax, value * ay, value * az)
        else:
            s, t = math.sin(value), 1.0 - math.cos(value)
            # I + s [a]x + (1 - cos) [a]x^2, with [a]x^2 = a a^T - |a|^2 I
            square = ax * ax + ay * ay + az * az
            motion[0, 0] = 1.0 + t * (ax * ax - square)
            motion[0, 1] = -s * az + t * ax * ay
            motion[0, 2] = s * ay + t * ax * az
            motion[1, 0] = s * az + t * ay * ax
            motion[1, 1] = 1.0 + t * (ay * ay - square)
            motion[1, 2] = -s * ax + t * ay * az
            motion[2, 0] = -s * ay + t * az * ax
            motion[2, 1] = s * ax + t * az * ay
            motion[2, 2] = 1.0 + t * (az * az - square)
            slide = (0.0, 0.0, 0.0)
        for r in range(3):
            o0, o1, o2 = origin_rotation[j, r, 0], origin_rotation[j, r, 1], origin_rotation[j, r, 2]
            for c in range(3):
                local[r, c] = o0 * motion[0, c] + o1 * motion[1, c] + o2 * motion[2, c]
            offset[r] = origin_position[j, r] + o0 * slide[0] + o1 * slide[1] + o2 * slide[2]
        p = parent[j]
        if p < 0:
            for r in range(3):
                position[j, r] = offset[r]
                for c in range(3):
                    rotation[j, r, c] = local[r, c]
        else:
            for r in range(3):
                q0, q1, q2 = rotation[p, r, 0], rotation[p, r, 1], rotation[p, r, 2]
                position[j, r] = position[p, r] + q0 * offset[0] + q1 * offset[1] + q2 * offset[2]
                for c in range(3):
                    rotation[j, r, c] = q0 * local[0, c] + q1 * local[1, c] + q2 * local[2, c]
        for r in range(3):
            q0, q1, q2 = rotation[j, r, 0], rotation[j, r, 1], rotation[j, r, 2]
            world_axis[j, r] = q0 * ax + q1 * ay + q2 * az
            world_com[j, r] = position[j, r] + q0 * com[j, 0] + q1 * com[j, 1] + q2 * com[j, 2]
