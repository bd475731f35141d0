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


def _clamped_step(problem, x, jac, err, grad, opts):
    """Task step and comfort direction (scaled variables) that keep x inside its bounds."""
    lo = (problem.lower - x) / problem.scale
    hi = (problem.upper - x) / problem.scale
    free = lo < hi  # variables with an empty range never move
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
    # the comfort direction must not push a variable at a bound outwards either
    comfort = np.where((comfort < 0) & (lo >= -1e-12) | (comfort > 0) & (hi <= 1e-12), 0.0, comfort)
    return np.nan_to_num(task), np.nan_to_num(comfort)


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
    history = [h]
    stalls = 0
    iterations = 0
    for iterations in range(1, opts.max_iterations + 1):
        converged = worst <= 1.0
        jac = problem.scaled_jacobian(state)
        grad = problem.comfort.gradient(state) * problem.scale if comfort_on else np.zeros(problem.n_x)
        task, direction = _clamped_step(problem, x, jac, err, grad, opts)

        # 1. task step: backtrack on the constraint error
        moved = False
        if merit > 0.0:
            alpha = 1.0
            for _ in range(6):
                x_try = np.clip(x + alpha * task * problem.scale, problem.lower, problem.upper)
                s_try, e_try, m_try, w_try = evaluate(x_try)
                if m_try < merit or (converged and w_try <= 1.0 and m_try <= merit * 1.0001):
                    x, state, err, merit, worst, moved = x_try, s_try, e_try, m_try, w_try, True
                    break
                alpha *= 0.5
        if moved:
            stalls = 0
            if comfort_on:
                h = evaluate.comfort(state)
        elif worst > 1.0:
            stalls += 1

        # 2. comfort step along the projected gradient, length lam (largest change in scaled units)
        gained = False
        size = np.max(np.abs(direction), initial=0.0)
        if comfort_on and size > 1e-12 and np.isfinite(size):
            unit = direction / size
            slope = float(grad @ unit)
            x_try = np.clip(x + lam * unit * problem.scale, problem.lower, problem.upper)
            s_try, e_try, m_try, w_try = evaluate(x_try)
            h_try = evaluate.comfort(s_try)
            ok_constraints = w_try <= 1.0 if worst <= 1.0 else m_try <= merit
            curvature = (h_try - h - lam * slope) / lam**2
            if np.isfinite(h_try) and h_try > h + 1e-4 * lam * slope and ok_constraints:
                x, state, err, merit, worst, h = x_try, s_try, e_try, m_try, w_try, h_try
                gained = True
                lam = min(-slope / (2 * curvature), 3 * lam) if curvature < 0 else 3 * lam
            else:
                lam = -slope / (2 * curvature) if curvature < 0 else lam / 3
                lam = min(lam, 0.5 * opts.comfort_step * 10)
            lam = float(np.clip(lam, 1e-7, 0.5))
        history.append(h)

        if worst <= 1.0:
            window = history[-4:]
            settled = (
                not comfort_on
                or (len(window) == 4 and window[-1] - window[0] <= opts.comfort_tolerance * max(abs(h), 1e-3))
                or (not gained and lam <= 1e-6)
            )
            if settled:
                break
        elif stalls >= 4:
            break
    return Result.from_state(problem, state, iterations, time.perf_counter() - t0)
