"""The iteration: dx = -J^+ g(x) + lambda (I - J^+ J) grad h(x) (thesis eq. 2.4), made robust.

Per iteration, in scaled variables (rows / tolerance, forces / body weight):
1. Economy SVD of the Jacobian of the free variables. Task step by damped least squares whose damping grows
   smoothly only for singular values below a threshold (near singularities), capped to a trust region.
2. Comfort direction: grad h projected on the null space of the undamped, rank-truncated row space.
3. Bounds are never left: variables the step would push past a bound are saturated at it and the step is
   solved again without them (the clamping loop), instead of shrinking the whole step.
4. Line searches: the task step by backtracking on the constraint error; the comfort step length lambda by a
   parabola through h along the direction, accepted only if h rises and the constraints stay within the
   error they had (or within tolerance once converged).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from .problem import Problem
from .result import Result


@dataclass(frozen=True)
class SolverOptions:
    """Iteration limits and step controls (rad for joint steps)."""

    max_iterations: int = 200
    optimize_comfort: bool = True
    max_joint_step: float = 0.4  # rad (or m, or body weights) per iteration for the task step
    comfort_step: float = 0.05  # first comfort step length (largest joint change), rad
    comfort_tolerance: float = 1e-4  # stop when h improves by less than this (relative) over 3 iterations
    singular_threshold: float = 1e-2  # damping starts below this fraction of the largest singular value
    max_damping: float = 1e-2  # damping at a singularity, as a fraction of the largest singular value
    clamping_rounds: int = 6


def _svd_step(jac: np.ndarray, err: np.ndarray, opts: SolverOptions):
    """Damped least-squares step -J^+ err and the orthonormal row-space basis (undamped, rank-truncated)."""
    if jac.shape[0] == 0 or jac.shape[1] == 0:
        return np.zeros(jac.shape[1]), np.zeros((0, jac.shape[1]))
    u, s, vt = np.linalg.svd(jac, full_matrices=False)
    s_max = s[0] if s.size else 0.0
    if s_max <= 0.0:
        return np.zeros(jac.shape[1]), np.zeros((0, jac.shape[1]))
    eps = opts.singular_threshold * s_max
    damp2 = np.where(s < eps, (opts.max_damping * s_max) ** 2 * (1.0 - (s / eps) ** 2), 0.0)
    inv = s / (s * s + damp2)
    step = -vt.T @ (inv * (u.T @ err))
    rank = int(np.sum(s > 1e-9 * s_max))
    return step, vt[:rank]


def _direction(jac, err, grad, free, fixed_dy, opts):
    """Task step and projected comfort direction over the free variables (zero elsewhere)."""
    n = jac.shape[1]
    err_eff = err + jac[:, ~free] @ fixed_dy[~free] if (~free).any() else err
    step_f, basis = _svd_step(jac[:, free], err_eff, opts)
    g_f = grad[free]
    d_f = g_f - basis.T @ (basis @ g_f)
    task = fixed_dy.copy()
    task[free] = step_f
    comfort = np.zeros(n)
    comfort[free] = d_f
    return task, comfort


def _room(problem, x):
    """Distance to the lower and upper bounds in scaled variables (<= 0 below, >= 0 above)."""
    return (problem.lower - x) / problem.scale, (problem.upper - x) / problem.scale


def _clamped_step(problem, x, jac, err, grad, opts):
    """Task step and comfort direction (scaled variables) that keep x inside its bounds.

    Variables sitting on a bound that comfort pushes outwards are held from the start; variables the task
    step would push past a bound are saturated there and the step is solved again without them.
    """
    lo, hi = _room(problem, x)
    at_lo, at_hi = lo >= -1e-12, hi <= 1e-12
    free = (lo < hi) & ~(at_lo & (grad < 0)) & ~(at_hi & (grad > 0))
    fixed_dy = np.zeros_like(x)
    task = comfort = np.zeros_like(x)
    for _ in range(opts.clamping_rounds):
        task, comfort = _direction(jac, err, grad, free, fixed_dy, opts)
        biggest = np.max(np.abs(task[free]), initial=0.0)
        if biggest > opts.max_joint_step:
            task[free] *= opts.max_joint_step / biggest
        below = free & (task < lo - 1e-12)
        above = free & (task > hi + 1e-12)
        if not (below.any() or above.any()):
            break
        fixed_dy[below] = lo[below]
        fixed_dy[above] = hi[above]
        free &= ~(below | above)
    return np.nan_to_num(task), np.nan_to_num(comfort), free


def _comfort_direction(problem, x, jac, grad, direction, free, opts):
    """Unit comfort direction and the longest step before a bound; holds blocking variables and re-projects."""
    for _ in range(3):
        size = np.max(np.abs(direction), initial=0.0)
        if not np.isfinite(size) or size <= 1e-12:
            return None, 0.0
        unit = direction / size
        lo, hi = _room(problem, x)
        with np.errstate(divide="ignore", invalid="ignore"):
            reach = np.where(unit > 0, hi / unit, np.where(unit < 0, lo / unit, np.inf))
        reach = np.where(free, np.maximum(reach, 0.0), np.inf)
        longest = float(np.min(reach, initial=np.inf))
        if longest > 1e-9:
            return unit, longest
        free = free & (reach > 1e-9)
        _, basis = _svd_step(jac[:, free], np.zeros(jac.shape[0]), opts)
        direction = np.zeros_like(grad)
        direction[free] = grad[free] - basis.T @ (basis @ grad[free])
    return None, 0.0


COMFORT_SLACK = 10.0  # how far (in tolerances) a comfort step may leave the constraints before the next task step


class _Evaluator:
    """Evaluates x once: state, scaled error, merit, comfort."""

    def __init__(self, problem: Problem) -> None:
        self.problem = problem
        self.unweight = 1.0 / problem.row_weight if problem.n_rows else np.zeros(0)

    def __call__(self, x: np.ndarray):
        state = self.problem.state(x)
        err = self.problem.scaled_error(state)
        merit = float(err @ err)
        worst = float(np.max(np.abs(err) * self.unweight, initial=0.0))
        return state, err, merit, worst

    def comfort(self, state) -> float:
        return self.problem.comfort.value(state)


def solve(problem: Problem, x0: np.ndarray | None = None, options: SolverOptions = SolverOptions()) -> Result:
    """Find x meeting the constraints and maximising comfort, warm-started from ``x0`` (any earlier pose)."""
    t0 = time.perf_counter()
    opts = options
    evaluate = _Evaluator(problem)
    x = problem.start(x0)
    state, err, merit, worst = evaluate(x)
    comfort_on = opts.optimize_comfort
    h = evaluate.comfort(state) if comfort_on else 0.0
    lam = opts.comfort_step
    quiet = 0  # consecutive comfort steps with a negligible gain
    stalls = 0
    iterations = 0
    for iterations in range(1, opts.max_iterations + 1):
        jac = problem.scaled_jacobian(state)
        grad = problem.comfort.gradient(state) * problem.scale if comfort_on else np.zeros(problem.n_x)
        task, direction, free = _clamped_step(problem, x, jac, err, grad, opts)

        # 1. task step: backtrack on the constraint error
        moved = False
        if merit > 0.0:
            alpha = 1.0
            for _ in range(6):
                x_try = np.clip(x + alpha * task * problem.scale, problem.lower, problem.upper)
                s_try, e_try, m_try, w_try = evaluate(x_try)
                if m_try < merit:
                    x, state, err, merit, worst, moved = x_try, s_try, e_try, m_try, w_try, True
                    break
                alpha *= 0.5
        if moved:
            stalls = 0
            if comfort_on:
                h = evaluate.comfort(state)
        elif worst > 1.0:
            stalls += 1

        # 2. comfort step along the projected gradient, length lam (largest change in scaled units). It may
        #    leave the constraints by a little (COMFORT_SLACK tolerances); the next task step restores them.
        unit, longest = (None, 0.0)
        if comfort_on:
            unit, longest = _comfort_direction(problem, x, jac, grad, direction, free, opts)
        if unit is not None:
            slope = float(grad @ unit)
            x_try = np.clip(x + lam * unit * problem.scale, problem.lower, problem.upper)
            s_try, e_try, m_try, w_try = evaluate(x_try)
            h_try = evaluate.comfort(s_try)
            curvature = (h_try - h - lam * slope) / lam**2
            rises = np.isfinite(h_try) and h_try > h + 1e-4 * lam * slope
            if rises and w_try <= max(COMFORT_SLACK, worst):
                gain = h_try - h
                x, state, err, merit, worst, h = x_try, s_try, e_try, m_try, w_try, h_try
                lam = min(-slope / (2 * curvature), 3 * lam) if curvature < 0 else 3 * lam
                quiet = quiet + 1 if gain <= opts.comfort_tolerance * max(abs(h), 1e-3) else 0
            else:
                lam = min(-slope / (2 * curvature), lam / 2) if (curvature < 0 and not rises) else lam / 2
                quiet += 1
            lam = float(np.clip(lam, 1e-7, 0.5))
        else:
            quiet += 1

        comfort_settled = not comfort_on or quiet >= 3 or lam <= 1e-6
        if worst <= 1.0 and comfort_settled:
            break
        if worst > 1.0 and stalls >= 4:
            break
    return Result.from_state(problem, state, iterations, time.perf_counter() - t0)
