"""A frame group's errors and Jacobian rows, each stage as one loop over the members (the kernels of
:class:`solver.constraints.frame.FrameGroup`).

Units: m, rad. Error of a member (TCP frame (R, o), target frame (R_T, o_T)): e_p = R_T^T (o - o_T),
e_r = log(R_T^T R); a row is its operator row times [e_p, e_r]. Its Jacobian row on joint j (twist [v_j, w_j]):
sign * ((m - l x o) . w_j + l . v_j), with l = L_lin R_T^T and m = L_ang J_l^-1(e_r) R_T^T. Also the general
rows of :meth:`solver.body.model.Kinematics.jacobian_rows` (points moved by masked joints, the clearance rows').
"""

from __future__ import annotations

import math

import numpy as np

from . import kernel


@kernel
def frame_errors(
    rotation: np.ndarray,
    position: np.ndarray,
    links: np.ndarray,
    local: np.ndarray,
    operator: np.ndarray,
    row_member: np.ndarray,
    target: np.ndarray,
    values: np.ndarray,
    errors: np.ndarray,
) -> None:
    """Fill per member ``target`` (C, 3, 4) [R_T | o_T] (world, m) and ``values`` (C, 9) [o (m), e_p (m), e_r (rad)],
    and the rows ``errors`` (R,). ``links`` (C, 2): the TCP's link and the reference TCP's (-1: a fixed target);
    ``local`` (C, 3, 3, 4): the TCP, the target (in the reference TCP for a loop) and the reference TCP, [R | p]."""
    frame, rel, d = np.empty((2, 3, 4)), np.empty((3, 3)), np.empty(3)
    for i in range(links.shape[0]):
        for f in range(2):  # the TCP's world frame, then the reference TCP's (the world's for a fixed target)
            a = links[i, f]
            for r in range(3):
                if a < 0:
                    for c in range(4):
                        frame[f, r, c] = 1.0 if r == c else 0.0
                    continue
                q0, q1, q2 = rotation[a, r, 0], rotation[a, r, 1], rotation[a, r, 2]
                m = 0 if f == 0 else 2
                for c in range(4):
                    frame[f, r, c] = q0 * local[i, m, 0, c] + q1 * local[i, m, 1, c] + q2 * local[i, m, 2, c]
                frame[f, r, 3] += position[a, r]
        for r in range(3):  # the target in the reference frame
            s0, s1, s2 = frame[1, r, 0], frame[1, r, 1], frame[1, r, 2]
            for c in range(4):
                target[i, r, c] = s0 * local[i, 1, 0, c] + s1 * local[i, 1, 1, c] + s2 * local[i, 1, 2, c]
            target[i, r, 3] += frame[1, r, 3]
            values[i, r] = frame[0, r, 3]
            d[r] = frame[0, r, 3] - target[i, r, 3]
        for r in range(3):  # R_T^T (o - o_T) and R_T^T R
            t0, t1, t2 = target[i, 0, r], target[i, 1, r], target[i, 2, r]
            values[i, 3 + r] = t0 * d[0] + t1 * d[1] + t2 * d[2]
            for c in range(3):
                rel[r, c] = t0 * frame[0, 0, c] + t1 * frame[0, 1, c] + t2 * frame[0, 2, c]
        # log(rel) as solver.body.spatial.log_so3 takes it: the axis from the symmetric part near pi
        cos_angle = min(1.0, max(-1.0, (rel[0, 0] + rel[1, 1] + rel[2, 2] - 1.0) * 0.5))
        angle = math.acos(cos_angle)
        vee = (rel[2, 1] - rel[1, 2], rel[0, 2] - rel[2, 0], rel[1, 0] - rel[0, 1])
        if angle < 1e-6 or math.pi - angle > 1e-4:
            k = 0.5 if angle < 1e-6 else angle / (2.0 * math.sin(angle))
            for r in range(3):
                values[i, 6 + r] = vee[r] * k
            continue
        col = 0
        for c in range(1, 3):
            if rel[c, c] - cos_angle > rel[col, col] - cos_angle:
                col = c
        root = math.sqrt(max(0.5 * (rel[col, col] + rel[col, col]) - cos_angle, 1e-8))
        for r in range(3):
            d[r] = (0.5 * (rel[r, col] + rel[col, r]) - (cos_angle if r == col else 0.0)) / root
        sign = -1.0 if d[0] * vee[0] + d[1] * vee[1] + d[2] * vee[2] < 0.0 else 1.0
        norm = math.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
        for r in range(3):
            values[i, 6 + r] = sign * d[r] / norm * angle
    for r in range(row_member.shape[0]):
        total = 0.0
        for k in range(6):
            total += operator[r, k] * values[row_member[r], 3 + k]
        errors[r] = total


@kernel
def frame_jacobian_rows(
    values: np.ndarray,
    target: np.ndarray,
    operator: np.ndarray,
    row_member: np.ndarray,
    twist: np.ndarray,
    joint_start: np.ndarray,
    joint: np.ndarray,
    sign: np.ndarray,
    out: np.ndarray,
) -> None:
    """Fill the rows' Jacobian entries of ``out`` (R, >= n; zeros elsewhere, by the caller) from :func:`frame_errors`'s
    ``values`` and ``target``, the joints' ``twist`` (n, 6) [velocity of the world origin, spin]. Member i's
    moving joints are ``joint[joint_start[i]:joint_start[i + 1]]`` with ``sign`` +1 (moves the TCP) or -1 (the
    reference TCP)."""
    jinv, lin, u, through = np.empty((3, 3)), np.empty(3), np.empty(3), np.empty(3)
    last = -1
    for r in range(row_member.shape[0]):
        i = row_member[r]
        if i != last:  # J_l^-1(e_r) = I - K/2 + coef K^2, K = [e_r]x, as solver.body.spatial computes it
            last = i
            x, y, z = values[i, 6], values[i, 7], values[i, 8]
            angle2 = x * x + y * y + z * z
            angle = math.sqrt(angle2)
            half = 0.5 * angle
            coef = 1.0 / 12.0 if angle < 1e-5 else (1.0 - half * math.cos(half) / math.sin(half)) / angle2
            diag = 1.0 - coef * angle2
            jinv[0, 0], jinv[0, 1], jinv[0, 2] = diag + coef * x * x, 0.5 * z + coef * x * y, -0.5 * y + coef * x * z
            jinv[1, 0], jinv[1, 1], jinv[1, 2] = -0.5 * z + coef * x * y, diag + coef * y * y, 0.5 * x + coef * y * z
            jinv[2, 0], jinv[2, 1], jinv[2, 2] = 0.5 * y + coef * x * z, -0.5 * x + coef * y * z, diag + coef * z * z
        for k in range(3):
            u[k] = operator[r, 3] * jinv[0, k] + operator[r, 4] * jinv[1, k] + operator[r, 5] * jinv[2, k]
        for c in range(3):  # l = L_lin R_T^T, m = (L_ang J_l^-1) R_T^T, through = m - l x o
            lin[c] = (
                operator[r, 0] * target[i, c, 0] + operator[r, 1] * target[i, c, 1] + operator[r, 2] * target[i, c, 2]
            )
            through[c] = u[0] * target[i, c, 0] + u[1] * target[i, c, 1] + u[2] * target[i, c, 2]
        px, py, pz = values[i, 0], values[i, 1], values[i, 2]
        t0 = through[0] - (lin[1] * pz - lin[2] * py)
        t1 = through[1] - (lin[2] * px - lin[0] * pz)
        t2 = through[2] - (lin[0] * py - lin[1] * px)
        for s in range(joint_start[i], joint_start[i + 1]):
            j = joint[s]
            moved = t0 * twist[j, 3] + t1 * twist[j, 4] + t2 * twist[j, 5]
            out[r, j] = sign[s] * (moved + lin[0] * twist[j, 0] + lin[1] * twist[j, 1] + lin[2] * twist[j, 2])


@kernel
def point_jacobian_rows(
    points: np.ndarray, rows_lin: np.ndarray, rows_ang: np.ndarray, mask: np.ndarray, twist: np.ndarray, out: np.ndarray
) -> None:
    """Fill ``out`` (k, n): row r is mask[r] * ((m - l x p) . w_j + l . v_j) for l = ``rows_lin[r]``, m =
    ``rows_ang[r]`` (k, 3), p = ``points[r]`` m (or ``points[0]`` when one point (1, 3) serves every row; the same
    for a one-row ``mask`` (1, n)) and the joints' ``twist`` (n, 6) [velocity of the world origin, spin]."""
    for r in range(out.shape[0]):
        p = 0 if points.shape[0] == 1 else r
        q = 0 if mask.shape[0] == 1 else r
        lx, ly, lz = rows_lin[r, 0], rows_lin[r, 1], rows_lin[r, 2]
        px, py, pz = points[p, 0], points[p, 1], points[p, 2]
        t0 = rows_ang[r, 0] - (ly * pz - lz * py)
        t1 = rows_ang[r, 1] - (lz * px - lx * pz)
        t2 = rows_ang[r, 2] - (lx * py - ly * px)
        for j in range(out.shape[1]):
            m = mask[q, j]
            if m == 0.0:
                out[r, j] = 0.0
                continue
            moved = t0 * twist[j, 3] + t1 * twist[j, 4] + t2 * twist[j, 5]
            out[r, j] = (moved + lx * twist[j, 0] + ly * twist[j, 1] + lz * twist[j, 2]) * m
