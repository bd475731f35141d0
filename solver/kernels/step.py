"""The step's element-wise stages as loops (the kernels of :mod:`solver.iteration.step`): the bound check, the
metric, gathering the free columns, scattering the free variables' steps back and saturating on bounds.

Units: scaled variables (a joint's half range, body weight for a force); rows in tolerances. The LAPACK and matrix
products of the step stay with NumPy/SciPy; these loops replace the many small array operations around them.
"""

from __future__ import annotations

import math

import numpy as np

from . import kernel


@kernel
def bound_start(
    lower: np.ndarray,
    upper: np.ndarray,
    scale: np.ndarray,
    x: np.ndarray,
    outward: np.ndarray,
    lo: np.ndarray,
    hi: np.ndarray,
    free: np.ndarray,
) -> int:
    """Fill the room ``lo`` <= 0 <= ``hi`` of each variable (scaled) and ``free``: inside its bounds and not held on a
    bound that ``outward`` (the descent of both pushes is along -outward) presses it against; return the count."""
    count = 0
    for i in range(x.shape[0]):
        low = (lower[i] - x[i]) / scale[i]
        high = (upper[i] - x[i]) / scale[i]
        lo[i], hi[i] = low, high
        held = (low >= -1e-12 and outward[i] >= 0.0) or (high <= 1e-12 and outward[i] <= 0.0)
        free[i] = low < high and not held
        count += free[i]
    return count


@kernel
def root_metric(
    curv_f: np.ndarray,
    shift: float,
    comfort_on: bool,
    x: np.ndarray,
    scale: np.ndarray,
    is_joint: np.ndarray,
    force_floor: float,
    force_barrier: float,
    root: np.ndarray,
) -> None:
    """Fill ``root`` with the square root of the step's diagonal metric (``solver.iteration.step.metric``); ``shift``
    is mu x the mean of ``curv_f`` on the free variables (summed by NumPy, so that both paths round alike)."""
    n = curv_f.shape[0]
    curved = False
    for i in range(n):
        curved = curved or curv_f[i] != 0.0
    if not (comfort_on or curved):
        for i in range(n):
            root[i] = 1.0
        return
    for i in range(n):
        value = curv_f[i] + shift + 1e-12
        if not is_joint[i]:  # a contact edge weight: the log barrier's curvature
            share = x[i] / scale[i]
            share = force_floor if share < force_floor else share  # np.maximum: NaN stays NaN
            value += force_barrier / (share * share)
        root[i] = math.sqrt(value)


@kernel
def free_columns(
    jac: np.ndarray, free: np.ndarray, root: np.ndarray, scaled: np.ndarray, used: np.ndarray, r_f: np.ndarray
) -> None:
    """The free variables' Jacobian in the metric: ``scaled`` (m, k, Fortran order) = the free columns of ``jac`` /
    their metric root ``r_f`` (k), and ``used``: the rows with an entry there."""
    m, n = jac.shape
    for r in range(m):
        used[r] = False
    k = 0
    for j in range(n):  # column by column: ``scaled`` is in Fortran order
        if free[j]:
            r_f[k] = root[j]
            for r in range(m):
                value = jac[r, j] / root[j]
                scaled[r, k] = value
                used[r] = used[r] or value != 0.0
            k += 1


@kernel
def gather_scaled(values: np.ndarray, columns: np.ndarray, free: np.ndarray, r_f: np.ndarray, out_values, out_columns):
    """``out_values`` = values[free] / r_f and ``out_columns`` = columns[free] / r_f[:, None] (the comfort gradient and
    the quasi-Newton columns in the metric, free variables only)."""
    k = 0
    for i in range(values.shape[0]):
        if free[i]:
            out_values[k] = values[i] / r_f[k]
            for c in range(columns.shape[1]):
                out_columns[k, c] = columns[i, c] / r_f[k]
            k += 1


@kernel
def scatter_scaled(part: np.ndarray, r_f: np.ndarray, free: np.ndarray, out: np.ndarray, cap: float) -> None:
    """out[free] = part / r_f (the other entries kept), then all of ``out`` scaled so its largest |entry| <= ``cap``."""
    k = 0
    biggest = 0.0
    for i in range(out.shape[0]):
        if free[i]:
            out[i] = part[k] / r_f[k]
            k += 1
        size = abs(out[i])
        if size > biggest or size != size:  # NaN wins, as in NumPy's max: then nothing is scaled
            biggest = size
    if biggest > cap:
        factor = cap / biggest
        for i in range(out.shape[0]):
            out[i] *= factor


@kernel
def saturate(
    task: np.ndarray,
    comfort: np.ndarray,
    lo: np.ndarray,
    hi: np.ndarray,
    free: np.ndarray,
    fixed: np.ndarray,
    is_joint: np.ndarray,
    fraction_near: float,
    apply: bool,
) -> int:
    """How many free variables task + comfort pushes past a bound; with ``apply`` they leave ``free`` and are held in
    ``fixed``: a joint halfway to its limit unless already within ``fraction_near`` of it, a force at zero."""
    count = 0
    for i in range(task.shape[0]):
        if not free[i]:
            continue
        total = task[i] + comfort[i]
        if total < lo[i] - 1e-12:
            count += 1
            if apply:
                fixed[i] = lo[i] * (0.5 if (is_joint[i] and -lo[i] > fraction_near) else 1.0)
                free[i] = False
        elif total > hi[i] + 1e-12:
            count += 1
            if apply:
                fixed[i] = hi[i] * (0.5 if (is_joint[i] and hi[i] > fraction_near) else 1.0)
                free[i] = False
    return count


@kernel
def step_tail(
    task: np.ndarray, comfort: np.ndarray, free: np.ndarray, grad_f: np.ndarray, root: np.ndarray, r_free, g_free
) -> bool:
    """Whether task and comfort are all finite; fills ``r_free`` = root[free] and ``g_free`` = grad_f[free] /
    r_free."""
    finite = True
    k = 0
    for i in range(task.shape[0]):
        finite = finite and math.isfinite(task[i]) and math.isfinite(comfort[i])
        if free[i]:
            r_free[k] = root[i]
            g_free[k] = grad_f[i] / root[i]
            k += 1
    return finite


@kernel
def watched_rows(
    one_sided: np.ndarray,
    err: np.ndarray,
    live: np.ndarray,
    jac: np.ndarray,
    out: np.ndarray,
    kept_jac: np.ndarray,
    kept_live: np.ndarray,
) -> int:
    """``out`` per row of ``jac`` (rows ``live``): a one-sided row met with no error (a clearance within its watch
    band) whose Jacobian row has an entry; return how many. When there are any, the other rows of ``jac`` and ``live``
    are copied, in order, to the first rows of ``kept_jac`` and ``kept_live`` (NumPy's ``jac[~out]``, without its
    fancy-indexing overhead)."""
    count = 0
    for r in range(live.shape[0]):
        row = live[r]
        watched = False
        if one_sided[row] and err[row] == 0.0:
            for j in range(jac.shape[1]):
                if jac[r, j] != 0.0:
                    watched = True
                    break
        out[r] = watched
        count += watched
    if count:
        kept = 0
        for r in range(live.shape[0]):
            if not out[r]:
                for j in range(jac.shape[1]):
                    kept_jac[kept, j] = jac[r, j]
                kept_live[kept] = live[r]
                kept += 1
    return count


@kernel
def turn_share(
    direction: np.ndarray, scale: np.ndarray, column: np.ndarray, weight: np.ndarray, limit: np.ndarray
) -> float:
    """The largest |joint change| / ``limit`` (0 when none; NaN when a change is NaN) of the scaled step
    ``direction``: per joint j, dx_j = weight_j * (direction * scale)[column_j] (``column`` -1: no change; a row per
    joint of a linear reduction's basis, or ``column`` = arange for x itself), as ``np.max(np.abs(
    Problem.joint_change(state, direction * scale)) / limit, initial=0.0)`` (the same numbers)."""
    best = 0.0
    for j in range(limit.shape[0]):
        c = column[j]
        if c < 0:
            change = 0.0
        else:
            change = weight[j] * (direction[c] * scale[c])
        share = abs(change) / limit[j]
        if share > best or share != share:  # np.max: a NaN wins and stays
            best = share
            if share != share:
                return share
    return best
