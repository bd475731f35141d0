"""One step in scaled variables: the task part, the comfort part in the null space, both kept inside the bounds.

With W = diag(curvature of -h) + mu and y = W^(1/2) dx the step is the thesis's (eq. 2.4):
y = -Jw^+ err - (I - Jw^+ Jw) W^(-1/2) grad f, Jw = J W^(-1/2), the exact minimiser of the diagonal comfort
model on the linearised constraints. The bound check is made on the sum of both parts, so a joint that the task
alone would push past its limit stays free when comfort pulls it back; variables the sum pushes past a bound are
saturated there and the step is solved again without them.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from .. import kernels
from ..body.state import computed_once
from ..kernels import bounded_step as fused
from ..kernels import step as compiled
from ..problem.problem import Problem
from . import lapack
from .curvature_memory import CurvatureMemory, null_space_newton
from .least_squares import LeastSquares
from .trial import Trial
from .tuning import Tuning


@dataclass(slots=True)
class Linearization:
    """The models a step is computed from, at one iterate (scaled variables, rows in tolerances)."""

    jac: np.ndarray  # d scaled error / d scaled variables, on the rows ``live`` (the others are zero)
    live: np.ndarray  # indices of the rows ``jac`` holds
    grad_f: np.ndarray  # gradient of f = -h (zeros without comfort)
    curv_f: np.ndarray  # diagonal curvature model of f (zeros when no metric is wanted)
    comfort_on: bool  # whether the step carries a comfort part
    rows: np.ndarray | None = None  # R (k, n) with exact low-rank curvature R^T R of f beyond curv_f


@dataclass
class Step:
    """A task step and a comfort step, with what a second-order correction and the merit need."""

    task: np.ndarray  # scaled task step (fixed variables included)
    comfort: np.ndarray  # scaled comfort step
    predicted_gain: float  # comfort gain the quadratic model predicts for the comfort step (>= 0)
    free: np.ndarray  # variables the step moved freely
    least_squares: LeastSquares  # the factors of the free variables' Jacobian, in the metric
    root_metric: np.ndarray  # square root of the metric on the free variables
    free_gradient: np.ndarray  # grad f on the free variables, in the metric
    saturated_gain: float = 0.0  # first-order comfort gain of the variables the step saturated on a bound

    @property
    def gain_left(self) -> float:
        """What the step still expects to gain: the comfort part's model gain plus the saturated variables'."""
        return self.predicted_gain + self.saturated_gain

    def correction(self, err: np.ndarray) -> np.ndarray:
        """Second-order correction: the task step for a new error, reusing this step's factors."""
        out = np.zeros_like(self.task)
        out[self.free] = self.least_squares.step(err) / self.root_metric
        return out

    @computed_once
    def multipliers(self) -> np.ndarray:
        """Per scaled row: lambda with grad f + J^T lambda ~ 0 on the free variables (only near the constraints)."""
        return self.least_squares.multipliers(self.free_gradient)

    @computed_once
    def penalty(self) -> float:
        """Weight of sum |scaled error| in the merit: twice the largest multiplier estimate."""
        return 2.0 * float(np.maximum.reduce(np.abs(self.multipliers), initial=0.0)) + 1e-9


def metric(problem: Problem, x: np.ndarray, lin: Linearization, free: np.ndarray, mu: float, tuning: Tuning):
    """Diagonal metric W of the step: the comfort curvature + mu x its mean on the free variables, with a log
    barrier's curvature on contact edge weights; the identity when there is neither comfort nor curvature."""
    curv_f = lin.curv_f
    if not (lin.comfort_on or curv_f.any()):
        return np.ones_like(x)
    curv_free = curv_f[free]
    level = float(curv_free.sum()) / curv_free.size if curv_free.size else 1.0
    out = curv_f + mu * max(level, 1e-12) + 1e-12
    force = ~problem.bounds.is_joint
    if force.any():  # keeps lightly loaded contact edges from being driven negative
        share = np.maximum(x[force] / problem.bounds.scale[force], tuning.force_floor)  # edge weight / body weight
        out[force] += tuning.force_barrier / (share * share)
    return out


def compute_step(
    problem: Problem,
    at: Trial,
    lin: Linearization,
    mu: float,
    radius: float,
    tuning: Tuning,
    memory: CurvatureMemory | None,
) -> Step:
    """The step from ``at`` in the metric of :func:`metric`, inside the bounds (``memory`` None without comfort).

    Met one-sided rows near their floor (error zero, Jacobian given: a clearance within its watch band) are
    released first; those the step would then push past their floor are held there (the row's step must cover its
    slack, no more) and the step is solved again, so a part slides along a surface or leaves it, never into it.
    """
    live = lin.live
    if kernels.active():
        watched, released = _watched_compiled(problem, at, lin)
    else:
        watched = problem.one_sided[live] & (at.err[live] == 0.0) & lin.jac.any(axis=1)  # per row of lin.jac
        released = _without(lin, watched) if watched.any() else None
    if released is None:
        return _bounded_step(problem, at, lin, mu, radius, tuning, memory)
    step = _bounded_step(problem, at, released, mu, radius, tuning, memory)
    reach = lin.jac @ (step.task + step.comfort)
    # slack >= 0 (or NaN, never pushed), so a row not pushed past -(0 + overshoot) is not pushed past its floor either:
    # most steps push no watched row that far, and skip measuring the slack
    if not (watched & (reach < -(0.0 + tuning.hold_overshoot))).any():
        return step
    slack = problem.scaled_slack(at.state)[live]
    pushed = watched & (reach < -(slack + tuning.hold_overshoot))
    if not pushed.any():
        return step
    err = at.err.copy()
    err[live[pushed]] = slack[pushed]  # J dx = -slack: onto the floor
    return _bounded_step(problem, replace(at, err=err), _without(lin, watched & ~pushed), mu, radius, tuning, memory)


def _watched_compiled(problem: Problem, at: Trial, lin: Linearization) -> tuple[np.ndarray, Linearization | None]:
    """(the watched rows, ``lin`` without them or None when there are none), as compute_step's NumPy lines, by
    :func:`solver.kernels.step.watched_rows`."""
    m = len(lin.live)
    watched, kept_jac, kept_live = np.empty(m, dtype=bool), np.empty(lin.jac.shape), np.empty(m, lin.live.dtype)
    count = compiled.watched_rows(problem.one_sided, at.err, lin.live, lin.jac, watched, kept_jac, kept_live)
    if not count:
        return watched, None
    rest = m - count
    return watched, Linearization(kept_jac[:rest], kept_live[:rest], lin.grad_f, lin.curv_f, lin.comfort_on, lin.rows)


def _without(lin: Linearization, rows: np.ndarray) -> Linearization:
    """``lin`` without its Jacobian rows ``rows`` (bool, per row of ``lin.jac``)."""
    keep = ~rows
    # the constructor, not dataclasses.replace: a third of the time, once or twice a frame
    return Linearization(lin.jac[keep], lin.live[keep], lin.grad_f, lin.curv_f, lin.comfort_on, lin.rows)


def _bounded_step(
    problem: Problem,
    at: Trial,
    lin: Linearization,
    mu: float,
    radius: float,
    tuning: Tuning,
    memory: CurvatureMemory | None,
) -> Step:
    """The step on the rows of ``lin``: variables the step would push past a bound are saturated there and the
    step solved again without them."""
    if kernels.active():
        return _bounded_step_compiled(problem, at, lin, mu, radius, tuning, memory)
    x, jac, err, grad_f = at.x, lin.jac, at.err, lin.grad_f
    lo, hi = problem.bounds.room(x)
    # Start by holding variables on a bound that neither the constraint error nor comfort would pull inwards.
    outward = jac.T @ err[lin.live] + grad_f  # descent of both pushes along -outward
    free = (lo < hi) & ~((lo >= -1e-12) & (outward >= 0)) & ~((hi <= 1e-12) & (outward <= 0))
    root = np.sqrt(metric(problem, x, lin, free, mu, tuning))
    compact = _curvature_model(memory, lin) if memory is not None else None
    fixed = np.zeros_like(x)
    for round_ in range(tuning.clamping_rounds):
        task, comfort, lsq = _free_step(problem, at, lin, free, fixed, root, radius, compact, tuning)
        total = task + comfort
        below = free & (total < lo - 1e-12)
        above = free & (total > hi + 1e-12)
        if not (below.any() or above.any()):
            break
        if round_ == tuning.clamping_rounds - 1:
            comfort *= _room(task, comfort, lo, hi)  # out of rounds: shorten the comfort part to stay inside
            break
        # Saturate: a joint stops halfway to its limit unless it is already close to it (so the tan^2 comfort is
        # not slammed to its wall); forces stop exactly at zero.
        joint = problem.bounds.is_joint
        fixed[below] = lo[below] * np.where(joint[below] & (-lo[below] > tuning.fraction_near), 0.5, 1.0)
        fixed[above] = hi[above] * np.where(joint[above] & (hi[above] > tuning.fraction_near), 0.5, 1.0)
        free &= ~(below | above)
    if not (np.isfinite(task).all() and np.isfinite(comfort).all()):
        task, comfort = np.nan_to_num(task), np.nan_to_num(comfort)
    gain = _predicted_gain(lin, comfort, compact)
    # The first-order gain of the variables saturated on a bound: part of the task step, yet moved for comfort;
    # without it a phase whose progress is all on bounds (a motion's per-frame limits) would look finished.
    saturated = (~free) & (fixed != 0.0)
    saturated_gain = max(-float(grad_f[saturated] @ fixed[saturated]), 0.0) if lin.comfort_on else 0.0
    r_free = root[free]
    return Step(task, comfort, gain, free, lsq, r_free, grad_f[free] / r_free, saturated_gain)


def _bounded_step_compiled(
    problem: Problem,
    at: Trial,
    lin: Linearization,
    mu: float,
    radius: float,
    tuning: Tuning,
    memory: CurvatureMemory | None,
) -> Step:
    """:func:`_bounded_step` in one kernel (:mod:`solver.kernels.bounded_step`); where J J^T needs an
    eigendecomposition, with its element-wise stages in the loops of :mod:`solver.kernels.step` (the matrix products
    and LAPACK calls are the NumPy path's). The same numbers to rounding."""
    compact = _curvature_model(memory, lin) if memory is not None else None
    whole = _fused_step(problem, at, lin, mu, radius, tuning, compact)
    if whole is not None:
        return whole
    x, bounds, grad_f = at.x, problem.bounds, lin.grad_f
    n = len(x)
    lo, hi, root, free = np.empty(n), np.empty(n), np.empty(n), np.empty(n, dtype=bool)
    outward = lin.jac.T @ at.err[lin.live] + grad_f  # descent of both pushes along -outward
    compiled.bound_start(bounds.lower, bounds.upper, bounds.scale, x, outward, lo, hi, free)
    curv_free = lin.curv_f[free]
    level = float(curv_free.sum()) / curv_free.size if curv_free.size else 1.0  # as in metric(): the same rounding
    compiled.root_metric(
        lin.curv_f, mu * max(level, 1e-12), lin.comfort_on, x, bounds.scale, bounds.is_joint, tuning.force_floor,
        tuning.force_barrier, root,
    )  # fmt: skip
    fixed = np.zeros(n)
    for round_ in range(tuning.clamping_rounds):
        task, comfort, lsq = _free_step_compiled(at, lin, free, fixed, root, radius, compact, tuning)
        last = round_ == tuning.clamping_rounds - 1  # out of rounds: nothing more is saturated
        if not compiled.saturate(task, comfort, lo, hi, free, fixed, bounds.is_joint, tuning.fraction_near, not last):
            break
        if last:
            comfort *= _room(task, comfort, lo, hi)  # shorten the comfort part to stay inside
    k = int(np.count_nonzero(free))
    r_free, g_free = np.empty(k), np.empty(k)
    if not compiled.step_tail(task, comfort, free, grad_f, root, r_free, g_free):
        task, comfort = np.nan_to_num(task), np.nan_to_num(comfort)
    gain = _predicted_gain(lin, comfort, compact)
    saturated_gain = 0.0
    if lin.comfort_on and fixed.any():  # as in _bounded_step (a BLAS dot: the same rounding)
        saturated = (~free) & (fixed != 0.0)
        saturated_gain = max(-float(grad_f[saturated] @ fixed[saturated]), 0.0)
    return Step(task, comfort, gain, free, lsq, r_free, g_free, saturated_gain)


def _fused_step(problem: Problem, at: Trial, lin: Linearization, mu: float, radius: float, tuning: Tuning, compact):
    """The whole bounded step from :func:`solver.kernels.bounded_step.bounded_step`; None when J J^T is too
    ill-conditioned for Cholesky."""
    bounds, n, m = problem.bounds, len(at.x), len(lin.live)
    columns, middle = compact if compact is not None else (np.zeros((n, 0)), np.zeros((0, 0)))
    controls = np.array(
        (mu, radius, tuning.max_damping, tuning.max_comfort_step, tuning.fraction_near, tuning.force_floor,
         tuning.force_barrier, tuning.clamping_rounds), dtype=float,
    )  # fmt: skip
    vectors, free, factors = np.empty((5, n)), np.empty(n, dtype=bool), np.empty((2, n * m))  # factors transposed
    active, factor, results = np.empty(m, dtype=np.int64), np.empty((m, m)), np.empty(5)
    status = fused.bounded_step(
        np.ascontiguousarray(lin.jac), at.err[lin.live], lin.grad_f, lin.curv_f, lin.comfort_on, bounds.lower,
        bounds.upper, bounds.scale, bounds.is_joint, at.x, controls, np.ascontiguousarray(columns),
        np.ascontiguousarray(middle), vectors, free, factors, factor, active, results,
    )  # fmt: skip
    if status != fused.OK:
        return None
    task, comfort, _, r_free, g_free = vectors
    k, rows = int(results[3]), int(results[4])
    jac_t, basis_t = factors[0, : k * rows].reshape(k, rows), factors[1, : k * rows].reshape(k, rows)  # views
    lsq = LeastSquares.from_factors(
        jac_t.T, basis_t.T, lin.live[active[:rows]], factor[:rows, :rows], float(results[0]), len(at.err)
    )
    return Step(task, comfort, float(results[1]), free, lsq, r_free[:k], g_free[:k], float(results[2]))


def _free_step_compiled(at, lin, free, fixed, root, radius, compact, tuning):
    """:func:`_free_step` with the gathering and scattering of the free variables in compiled loops."""
    jac, err = lin.jac, at.err
    n, m, k = len(at.x), len(jac), int(np.count_nonzero(free))
    # Fortran order, as NumPy's jac[:, free] has: the products below then take the same BLAS paths (same rounding)
    scaled, used, r_f = np.empty((m, k), order="F"), np.empty(m, dtype=bool), np.empty(k)
    compiled.free_columns(jac, free, root, scaled, used, r_f)
    err_eff = err
    if fixed.any():  # held variables move by ``fixed``: the free ones make up the rest of the error
        err_eff = err.copy()
        err_eff[lin.live] += jac[:, ~free] @ fixed[~free]
    lsq = LeastSquares(scaled, tuning.max_damping, lin.live, len(err), used)
    task = fixed.copy()
    task[free] = lsq.step_within(err_eff, 1.0 / r_f, radius)
    comfort = np.zeros(n)
    if lin.comfort_on:
        columns = np.ascontiguousarray(compact[0]) if compact is not None else np.zeros((n, 0))  # one signature
        g_w, v = np.empty(k), np.empty((k, columns.shape[1]))
        compiled.gather_scaled(lin.grad_f, columns, free, r_f, g_w, v)
        z = null_space_newton(g_w, lsq.basis, None if compact is None else (v, compact[1]))
        compiled.scatter_scaled(z, r_f, free, comfort, tuning.max_comfort_step)
    return task, comfort, lsq


def _curvature_model(memory: CurvatureMemory, lin: Linearization) -> tuple[np.ndarray, np.ndarray] | None:
    """(U, M) with the model B = diag(curv_f) - U M^-1 U^T: the quasi-Newton pairs and the exact rows R
    (block M = -I, so that R^T R is added)."""
    compact = memory.compact(lin.curv_f + 1e-12) if memory.steps else None  # an empty memory: no b0 to add
    if lin.rows is None or not len(lin.rows):
        return compact
    k = len(lin.rows)
    if compact is None:
        return lin.rows.T.copy(), -np.eye(k)
    u, middle = compact
    m = len(middle)
    both = np.zeros((m + k, m + k))
    both[:m, :m] = middle
    both[m:, m:] = -np.eye(k)
    return np.concatenate((u, lin.rows.T), axis=1), both


def _free_step(problem, at, lin, free, fixed, root, radius, compact, tuning):
    """(task, comfort, factors) with the variables outside ``free`` held at ``fixed``."""
    jac, err = lin.jac, at.err
    n = len(at.x)
    err_eff = err
    if (~free).any():
        err_eff = err.copy()
        err_eff[lin.live] += jac[:, ~free] @ fixed[~free]
    r_f = root[free]
    lsq = LeastSquares(jac[:, free] / r_f, tuning.max_damping, lin.live, len(err))
    task = fixed.copy()
    task[free] = lsq.step_within(err_eff, 1.0 / r_f, radius)
    comfort = np.zeros(n)
    if lin.comfort_on:
        g_w = lin.grad_f[free] / r_f
        low_rank = None if compact is None else (compact[0][free] / r_f[:, None], compact[1])
        comfort[free] = null_space_newton(g_w, lsq.basis, low_rank) / r_f
        biggest = float(np.abs(comfort).max()) if n else 0.0
        if biggest > tuning.max_comfort_step:
            comfort *= tuning.max_comfort_step / biggest
    return task, comfort, lsq


def _room(task: np.ndarray, comfort: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> float:
    """The largest fraction in [0, 1] of ``comfort`` that keeps task + fraction x comfort inside [lo, hi]."""
    with np.errstate(divide="ignore", invalid="ignore"):
        room = np.where(comfort > 0, (hi - task) / comfort, np.where(comfort < 0, (lo - task) / comfort, 1.0))
    return float(np.clip(np.min(room, initial=1.0), 0.0, 1.0))


def _predicted_gain(lin: Linearization, comfort: np.ndarray, compact) -> float:
    """Comfort gain the model predicts for the comfort part: diagonal model plus the quasi-Newton part (>= 0)."""
    if not lin.comfort_on:
        return 0.0
    predicted = -(lin.grad_f @ comfort + 0.5 * (lin.curv_f * comfort) @ comfort)
    if compact is not None:  # the quasi-Newton part of comfort @ B @ comfort / 2
        u_c = compact[0].T @ comfort
        _, _, inner, info = lapack.dgesv(compact[1], u_c)
        if info == 0:
            predicted += 0.5 * float(u_c @ inner)
    return max(float(predicted), 0.0)
