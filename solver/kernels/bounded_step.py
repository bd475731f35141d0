"""The whole bounded step of :mod:`solver.iteration.step` in one compiled call: the bound check and the metric, then
per clamping round the damped least-squares task step (in its trust region) and the comfort step in the task's null
space, saturating on bounds; the predicted comfort gain at the end.

Units: scaled variables (a joint's half range, body weight for a force); rows in tolerances. The matrices are small
(~24 rows, ~100-190 free variables, a quasi-Newton memory of ~12 columns): loops cost less than the ~30 calls into
LAPACK and BLAS (and their Python wrappers) they replace. Where the Jacobian's Gram matrix is too ill-conditioned
for Cholesky (an eigendecomposition is needed) the kernel says so and the caller takes the NumPy path.
"""

from __future__ import annotations

import math

import numpy as np

from . import kernel
from .dense import cholesky, cholesky_solve, copy_into, gauss_solve, lower_inverse
from .step import bound_start, root_metric, saturate, scatter_scaled, step_tail

OK, NEEDS_EIGEN = 0, 1  # what the kernels return
MAX_CONDITION = 1e10  # trace(G) ||L^-1||_F^2 at or beyond this: L^-1 J is no orthonormal basis (as LeastSquares)
TRUST_ROUNDS = 30  # Newton steps on the trust region's secular equation (as LeastSquares.step_within)
HUGE = 1.7976931348623157e308  # np.nan_to_num's stand-in for infinity


@kernel
def bounded_step(
    jac: np.ndarray,
    err_live: np.ndarray,
    grad_f: np.ndarray,
    curv_f: np.ndarray,
    comfort_on: bool,
    lower: np.ndarray,
    upper: np.ndarray,
    scale: np.ndarray,
    is_joint: np.ndarray,
    x: np.ndarray,
    controls: np.ndarray,
    columns: np.ndarray,
    middle: np.ndarray,
    vectors: np.ndarray,
    free: np.ndarray,
    factors: np.ndarray,
    factor: np.ndarray,
    active: np.ndarray,
    results: np.ndarray,
) -> int:
    """The step of ``solver.iteration.step._bounded_step`` for ``jac`` (m, n) and the errors of its rows
    ``err_live``; ``controls`` = (mu, radius, max_damping, max_comfort_step, fraction_near, force_floor,
    force_barrier, clamping_rounds); ``columns`` (n, c) and ``middle`` (c, c) the quasi-Newton model (c = 0: none).
    Fills ``vectors`` (5, n) = (task, comfort, root (the metric's square root), r_free, g_free (root and grad f /
    root on the free variables)), ``free`` and the last round's least squares, transposed: ``factors`` (2, n m) =
    (J^T, (L^-1 J)^T), each in its first k rows C-contiguous (k, rows), ``active`` (its rows' positions in
    ``jac``), ``factor`` (the lower Cholesky factor of J J^T + d^2 I), ``results`` = (d^2, predicted gain,
    saturated gain, k free variables, rows).
    Outputs share a few arrays: Numba checks each argument's type on every call (~0.2 us each). Returns OK or
    NEEDS_EIGEN."""
    task, comfort, root, r_free, g_free = vectors[0], vectors[1], vectors[2], vectors[3], vectors[4]
    n = x.shape[0]
    mu, radius, max_damping, max_comfort = controls[0], controls[1], controls[2], controls[3]
    fraction_near, rounds = controls[4], int(controls[7])
    outward = np.dot(jac.T, err_live)  # + grad f: the descent of both pushes is along -outward
    for j in range(n):
        outward[j] += grad_f[j]
    lo, hi = np.empty(n), np.empty(n)
    count = bound_start(lower, upper, scale, x, outward, lo, hi, free)
    level = 0.0
    for j in range(n):
        if free[j]:
            level += curv_f[j]
    level = level / count if count else 1.0
    shift = mu * max(level, 1e-12)
    root_metric(curv_f, shift, comfort_on, x, scale, is_joint, controls[5], controls[6], root)
    fixed = np.zeros(n)
    for round_ in range(rounds):
        status = free_step(
            jac, err_live, free, fixed, root, radius, max_damping, comfort_on, grad_f, columns, middle, max_comfort,
            task, comfort, factors, active, factor, results,
        )  # fmt: skip
        if status != OK:
            return status
        last = round_ == rounds - 1  # out of rounds: nothing more is saturated
        if not saturate(task, comfort, lo, hi, free, fixed, is_joint, fraction_near, not last):
            break
        if last:
            fraction = room(task, comfort, lo, hi)  # shorten the comfort part to stay inside
            for j in range(n):
                comfort[j] *= fraction
    if not step_tail(task, comfort, free, grad_f, root, r_free, g_free):
        for j in range(n):
            task[j], comfort[j] = finite(task[j]), finite(comfort[j])
    results[1] = predicted_gain(grad_f, curv_f, comfort, columns, middle) if comfort_on else 0.0
    saturated = 0.0  # first-order comfort gain of the variables saturated on a bound (BLAS's dot in NumPy)
    for j in range(n):
        if not free[j] and fixed[j] != 0.0:
            saturated -= grad_f[j] * fixed[j]
    results[2] = max(saturated, 0.0) if comfort_on else 0.0
    return OK


@kernel
def free_step(
    jac, err_live, free, fixed, root, radius, max_damping, comfort_on, grad_f, columns, middle, max_comfort,
    task, comfort, factors, active, factor, results,
) -> int:  # fmt: skip
    """One clamping round (``_free_step``): the task step of the free variables with the others held at ``fixed``,
    and the comfort step in its null space, capped at ``max_comfort`` per entry; results[3:5] = (k, rows). J^T and
    (L^-1 J)^T are made in place in ``factors`` (no copies)."""
    m, n = jac.shape
    k, rows = 0, 0
    r_f = np.empty(n)
    for j in range(n):
        if free[j]:
            r_f[k] = root[j]
            k += 1
    err_eff = err_live.copy()  # held variables move by ``fixed``: the free ones make up the rest of the error
    every = factors[0, : k * m].reshape((k, m))  # J^T in the metric, every row: the pass finds the rows that count
    for r in range(m):
        used, c = False, 0
        for j in range(n):
            if free[j]:
                value = jac[r, j] / r_f[c]
                every[c, r] = value
                used = used or value != 0.0
                c += 1
            elif fixed[j] != 0.0:
                err_eff[r] += jac[r, j] * fixed[j]
        if used:  # a row without any entry (a met one-sided row) takes no part
            active[rows] = r
            rows += 1
    results[3], results[4] = k, rows
    jt = every  # J^T of the rows that take part, in the metric: rows along the fast axis
    if rows < m:
        every = every.copy()
        jt = factors[0, : k * rows].reshape((k, rows))
        for c in range(k):
            for q in range(rows):
                jt[c, q] = every[c, active[q]]
    bt, step = factors[1, : k * rows].reshape((k, rows)), np.empty(k)
    if task_step(jt, err_eff, active[:rows], r_f[:k], radius, max_damping, factor, bt, results, step) != OK:
        return NEEDS_EIGEN
    c = 0
    for j in range(n):
        task[j] = step[c] if free[j] else fixed[j]
        comfort[j] = 0.0
        c += free[j]
    if comfort_on:
        width = columns.shape[1]
        stacked = np.empty((k, width + 1))  # the comfort gradient and the quasi-Newton columns, in the metric
        c = 0
        for j in range(n):
            if free[j]:
                stacked[c, 0] = grad_f[j] / r_f[c]
                for q in range(width):
                    stacked[c, q + 1] = columns[j, q] / r_f[c]
                c += 1
        scatter_scaled(null_space_newton(stacked, bt, middle), r_f[:k], free, comfort, max_comfort)
    return OK


@kernel
def task_step(
    jt: np.ndarray,
    err_eff: np.ndarray,
    active: np.ndarray,
    r_f: np.ndarray,
    radius: float,
    max_damping: float,
    factor: np.ndarray,
    bt: np.ndarray,
    results: np.ndarray,
    out: np.ndarray,
) -> int:
    """``LeastSquares(J, ...)`` and its ``step_within(err_eff, 1 / r_f, radius)`` for ``jt`` = J^T (k, rows): fills
    ``bt`` = (L^-1 J)^T (orthonormal columns), ``factor`` (the Cholesky factor of G + d^2 I, G = J J^T), results[0] =
    d^2 and ``out`` (k) the step; NEEDS_EIGEN when G is too ill-conditioned for Cholesky."""
    k, rows = jt.shape
    gram = np.dot(jt.T, jt)
    size2, trace = 0.0, 0.0
    for i in range(rows):
        trace += gram[i, i]
        for j in range(rows):
            size2 += gram[i, j] * gram[i, j]
    damp2 = max_damping * max_damping * math.sqrt(size2)
    results[0] = damp2
    if rows == 0:
        for c in range(k):
            out[c] = 0.0
        return OK
    low, inverse = np.empty((rows, rows)), np.empty((rows, rows))
    if not cholesky(gram, 0.0, low):
        return NEEDS_EIGEN
    lower_inverse(low, inverse)
    spread = 0.0
    for i in range(rows):
        for j in range(i + 1):
            spread += inverse[i, j] * inverse[i, j]
    if not trace * spread < MAX_CONDITION:
        return NEEDS_EIGEN
    np.dot(jt, np.ascontiguousarray(inverse.T), bt)  # (L^-1 J)^T
    damped = np.empty((rows, rows))
    if not cholesky(gram, damp2, damped):
        return NEEDS_EIGEN
    copy_into(damped, factor)
    err = np.empty(rows)
    for i in range(rows):
        err[i] = err_eff[active[i]]
    within_radius(jt, gram, damped, damp2, err, r_f, radius, out)
    return OK


@kernel
def within_radius(
    jt: np.ndarray,
    gram: np.ndarray,
    damped: np.ndarray,
    damp2: float,
    err: np.ndarray,
    r_f: np.ndarray,
    radius: float,
    out: np.ndarray,
) -> None:
    """``out`` = the step -S^T (G + d^2 I)^-1 err, S = J / r_f (``jt`` = J^T), with Levenberg-Marquardt damping
    raised (Newton on the secular equation) until its 2-norm <= ``radius``."""
    k, rows = jt.shape
    st = np.empty((k, rows))
    for c in range(k):
        inv = 1.0 / r_f[c]
        for i in range(rows):
            st[c, i] = jt[c, i] * inv
    z = np.empty(rows)
    cholesky_solve(damped, err, z)
    size = minus_product(st, z, out)
    if size <= radius:
        return
    weight = np.dot(st.T, st)
    low, solved, w_z = damped.copy(), np.empty(rows), np.empty(rows)  # low: the factor of G + (d^2 + extra2) I
    extra2 = 0.0
    for _ in range(TRUST_ROUNDS):
        if size <= 1.05 * radius:
            break
        # Newton on 1/||step(extra2)|| = 1/radius: d||step||^2/d extra2 = -2 z^T weight (G + shift I)^-1 z
        cholesky_solve(low, z, solved)
        slope = 0.0
        for i in range(rows):
            w_z[i] = 0.0
            for p in range(rows):
                w_z[i] += weight[i, p] * z[p]
            slope += w_z[i] * solved[i]
        slope *= -2.0
        if not slope < 0.0:
            extra2 = 4.0 * extra2 + damp2 + 1e-300
        else:
            extra2 += (1.0 / size - 1.0 / radius) / (0.5 * slope / size**3)
        cholesky(gram, damp2 + extra2, low)  # cannot fail: G itself factored and the shift is positive
        cholesky_solve(low, err, z)
        size2 = 0.0
        for i in range(rows):
            value = 0.0
            for p in range(rows):
                value += z[p] * weight[p, i]
            size2 += value * z[i]
        size = math.sqrt(max(size2, 0.0))
    size = minus_product(st, z, out)
    if size > radius:
        for c in range(k):
            out[c] *= radius / size


@kernel
def minus_product(at: np.ndarray, z: np.ndarray, out: np.ndarray) -> float:
    """``out`` = -A^T z from ``at`` = A^T; returns its 2-norm."""
    k, rows = at.shape
    size2 = 0.0
    for c in range(k):
        value = 0.0
        for i in range(rows):
            value -= at[c, i] * z[i]
        out[c] = value
        size2 += value * value
    return math.sqrt(size2)


@kernel
def null_space_newton(stacked: np.ndarray, bt: np.ndarray, middle: np.ndarray) -> np.ndarray:
    """argmin_z g.z + z.B z / 2 subject to basis z = 0, B = I - V M^-1 V^T (``stacked`` = [g | V], ``middle`` = M;
    no V: B = I), as ``solver.iteration.curvature_memory.null_space_newton``: -q, q = (I - P) g, Woodbury-corrected.
    ``bt`` = basis^T has orthonormal columns. ``stacked`` is projected in place."""
    k, width = stacked.shape
    rows, c = bt.shape[1], width - 1
    grad = np.empty(k)
    for p in range(k):
        grad[p] = stacked[p, 0]
    if rows:  # [q | A] = (I - P) [g | V]
        part = np.dot(bt, np.dot(np.ascontiguousarray(bt.T), stacked))
        for p in range(k):
            for q in range(width):
                stacked[p, q] -= part[p, q]
    z = np.empty(k)
    for p in range(k):
        z[p] = -stacked[p, 0]
    if c == 0:
        return z
    products = np.dot(stacked.T, stacked)  # [q | A]^T [q | A]: A^T q and A^T A
    system, rhs = np.empty((c, c)), np.empty(c)
    for i in range(c):
        rhs[i] = products[i + 1, 0]
        for j in range(c):
            system[i, j] = products[i + 1, j + 1] - middle[i, j]
    inner = np.empty(c)
    if not gauss_solve(system, rhs, np.empty((c, c)), inner):
        return z
    out = np.empty(k)
    size2, slope = 0.0, 0.0
    for p in range(k):
        value = stacked[p, 0]
        for j in range(c):
            value -= stacked[p, j + 1] * inner[j]
        out[p] = -value
        size2 += value * value
        slope += out[p] * grad[p]
    return out if (math.isfinite(size2) and slope < 0.0) else z


@kernel
def room(task: np.ndarray, comfort: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> float:
    """The largest fraction in [0, 1] of ``comfort`` that keeps task + fraction x comfort inside [lo, hi] (NaN
    stays)."""
    best = 1.0
    for j in range(task.shape[0]):
        if comfort[j] > 0.0:
            share = (hi[j] - task[j]) / comfort[j]
        elif comfort[j] < 0.0:
            share = (lo[j] - task[j]) / comfort[j]
        else:
            continue
        if share != share:
            return share
        best = min(best, share)
    return min(max(best, 0.0), 1.0)


@kernel
def finite(value: float) -> float:
    """np.nan_to_num of one number: NaN 0, +-inf the largest finite float."""
    if value != value:
        return 0.0
    return min(max(value, -HUGE), HUGE)


@kernel
def predicted_gain(
    grad_f: np.ndarray, curv_f: np.ndarray, comfort: np.ndarray, columns: np.ndarray, middle: np.ndarray
) -> float:
    """Comfort gain the model predicts for ``comfort``: diagonal model plus the quasi-Newton part, >= 0."""
    n, c = columns.shape
    predicted = 0.0
    for j in range(n):
        predicted -= grad_f[j] * comfort[j] + 0.5 * curv_f[j] * comfort[j] * comfort[j]
    if c:
        u_c, inner = np.zeros(c), np.empty(c)
        for j in range(n):
            share = comfort[j]
            for q in range(c):
                u_c[q] += columns[j, q] * share
        if gauss_solve(middle, u_c, np.empty((c, c)), inner):
            for q in range(c):
                predicted += 0.5 * u_c[q] * inner[q]
    return max(predicted, 0.0)
