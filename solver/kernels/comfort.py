"""The standard comfort terms' own arithmetic as loops (the kernels of :mod:`solver.comfort`'s joint-load, joint-range,
trunk-tilt and contact-spread terms).

Units: the costs are dimensionless; joint values in rad (m if prismatic), joint moments in N*m, forces in N. Each
loop does what the term's NumPy code does, in the same order of operations, so the two agree to the bit; what NumPy
leaves to BLAS (dot products) or to its own vector maths (``np.tan``) the callers compute with the same NumPy call.
"""

from __future__ import annotations

import math

import numpy as np

from . import kernel


@kernel
def load_strains(tau: np.ndarray, inv_negative: np.ndarray, inv_positive: np.ndarray, squares: np.ndarray) -> None:
    """Fill ``squares`` (n,) = (tau_i / s_i)^2 for the axis loads ``tau`` (n,) N*m; the muscles produce -tau, so a
    negative tau takes the positive strength's inverse ``inv_positive`` (1/N*m). The cost is c @ squares (BLAS)."""
    for i in range(tau.shape[0]):
        strain = tau[i] * (inv_positive[i] if tau[i] < 0.0 else inv_negative[i])
        squares[i] = strain * strain


@kernel
def load_factors(
    tau: np.ndarray,
    inv_negative: np.ndarray,
    inv_positive: np.ndarray,
    joint_weight: np.ndarray,
    weight: float,
    coef: np.ndarray,
    rows: np.ndarray,
) -> None:
    """Fill ``coef`` (n,) = d cost / d tau (1/N*m) and ``rows`` (n,) = the Gauss-Newton weights of (d tau / dx)^2
    (times ``weight``, 1/(N*m)^2) for the axis loads ``tau`` (n,) N*m."""
    for i in range(tau.shape[0]):
        scale = inv_positive[i] if tau[i] < 0.0 else inv_negative[i]
        coef[i] = 2.0 * joint_weight[i] * tau[i] * scale * scale
        rows[i] = 2.0 * weight * joint_weight[i] * scale * scale


@kernel
def range_angles(
    theta: np.ndarray,
    neutral: np.ndarray,
    span_up: np.ndarray,
    span_down: np.ndarray,
    u_max: float,
    work: np.ndarray,
) -> None:
    """Fill ``work`` (3, n): u = (pi/2)(theta - neutral)/span, u clipped to +-``u_max`` (for the caller's
    ``np.tan``), and du/dtheta (per rad or m)."""
    half_pi = 0.5 * math.pi
    for i in range(theta.shape[0]):
        d = theta[i] - neutral[i]
        span = span_up[i] if d >= 0.0 else span_down[i]
        u = half_pi * d / span
        work[0, i] = u
        work[1, i] = u_max if u > u_max else (-u_max if u < -u_max else u)
        work[2, i] = half_pi / span


@kernel
def range_per_joint(
    work: np.ndarray, u_max: float, value: np.ndarray, slope: np.ndarray, curvature: np.ndarray
) -> None:
    """Fill ``value`` = tan^2(u) per joint (continued linearly past |u| = ``u_max``), ``slope`` its derivative
    (per rad or m) and ``curvature`` its second derivative from ``work`` (3, n): u, tan of the clipped u, du/dtheta."""
    for i in range(work.shape[1]):
        u, t, du = work[0, i], work[1, i], work[2, i]
        t2 = t * t
        rise = 2.0 * t * (1.0 + t2)
        beyond = abs(u) - u_max
        value[i] = t2 + (abs(rise) * beyond if beyond > 0.0 else 0.0)
        slope[i] = rise * du
        curvature[i] = 2.0 * (1.0 + t2) * (1.0 + 3.0 * t * t) * du * du


@kernel
def weighted_pair(
    weight: float, joint_weight: np.ndarray, first: np.ndarray, second: np.ndarray, n_x: int
) -> tuple[np.ndarray, np.ndarray]:
    """(weight c_i first_i, weight c_i second_i) over the first n entries of two zero (n_x,) vectors."""
    grad = np.zeros(n_x)
    curv = np.zeros(n_x)
    for i in range(joint_weight.shape[0]):
        factor = weight * joint_weight[i]
        grad[i] = factor * first[i]
        curv[i] = factor * second[i]
    return grad, curv


@kernel
def trunk_derivatives(
    rotation: np.ndarray, axis: np.ndarray, link: int, chain: np.ndarray, along: np.ndarray, factor: float, n_x: int
) -> tuple[np.ndarray, np.ndarray]:
    """Gradient and Hessian diagonal (n_x,) of ``factor`` (1 - z_z), z the up axis of link ``link``'s rotation
    (n, 3, 3); turning joint j of ``chain`` (world axis a_j, (n, 3)) turns z by a_j x z; ``along`` (chain,) a_j . z
    (the caller's BLAS product, as the NumPy path's)."""
    grad = np.zeros(n_x)
    curv = np.zeros(n_x)
    z0, z1, z2 = rotation[link, 0, 2], rotation[link, 1, 2], rotation[link, 2, 2]
    for k in range(chain.shape[0]):
        j = chain[k]
        a0, a1, a2 = axis[j, 0], axis[j, 1], axis[j, 2]
        grad[j] = -factor * (a0 * z1 - a1 * z0)
        second = z2 - a2 * along[k]  # d2(1 - z_z)/d theta_j^2
        curv[j] = factor * (0.0 if second < 0.0 else second)  # NaN stays NaN, as np.maximum
    return grad, curv


@kernel
def contact_cost(w: np.ndarray, body_weight: float) -> float:
    """sum_k (w_k / body weight)^2 for the contact edge weights ``w`` (N, at most 128: the caller's NumPy sums more),
    summed as ``np.sum`` sums: in order below eight, else in eight lanes, then the lanes pairwise, then the tail."""
    m = w.shape[0]
    lanes = np.zeros(8)
    if m < 8:
        total = 0.0
        for k in range(m):
            share = w[k] / body_weight
            total += share * share
        return total
    i = 0
    while i < m - (m % 8):
        for lane in range(8):
            share = w[i + lane] / body_weight
            lanes[lane] = share * share if i == 0 else lanes[lane] + share * share
        i += 8
    total = ((lanes[0] + lanes[1]) + (lanes[2] + lanes[3])) + ((lanes[4] + lanes[5]) + (lanes[6] + lanes[7]))
    while i < m:
        share = w[i] / body_weight
        total += share * share
        i += 1
    return total


@kernel
def contact_derivatives(w: np.ndarray, n: int, body_weight: float, weight: float) -> tuple[np.ndarray, np.ndarray]:
    """Gradient and (exact, diagonal) Hessian (n + n_w,) of ``weight`` sum_k (w_k / body weight)^2, zero over the
    n joints."""
    grad = np.zeros(n + w.shape[0])
    curv = np.zeros(n + w.shape[0])
    square = body_weight * body_weight
    for k in range(w.shape[0]):
        grad[n + k] = weight * 2.0 * w[k] / square
        curv[n + k] = weight * 2.0 / square
    return grad, curv
