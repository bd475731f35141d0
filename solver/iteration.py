"""The iteration: dx = -J^+ g(x) + lambda (I - J^+ J) grad h(x) (thesis eq. 2.4), made fast and robust.

Per iteration, in scaled variables (rows / tolerance, forces / body weight, joints / half their range):

1. Task step: damped least squares on the Jacobian of the free variables, from a Cholesky factor of J J^T
   (m ~ 24 rows) with a Tikhonov damping of 1e-3 of the largest singular value, which matters only near
   singularities; a trust region adds Levenberg-Marquardt damping.
2. Comfort step in the null space N = I - V_r^T V_r of the undamped row space (V_r = L^-1 J, orthonormal). The thesis
   takes lambda N grad h with a scalar lambda from a line search; we give lambda a metric: both parts are
   computed in the variables y = W^(1/2) x, W = diag(curvature of -h) + mu (comfort.py), so the comfort part
   is a diagonal Newton step and the task part a weighted least-norm step that keeps joints near their
   limits still (Chan & Dubey's joint-limit weighting). For large mu this is exactly the thesis step with
   lambda = 1/mu. mu adapts like Levenberg-Marquardt from how well the model predicted the comfort change.
   From curvature pairs gathered near the constraints, the comfort part also sees a limited-memory BFGS
   model of the Lagrangian's curvature (the joint coupling of the load term and the curvature of the
   constraints, which the diagonal misses), applied in the null space by a Woodbury identity of rank 2 x memory.
3. Bounds are never left: variables the task step pushes past a bound are saturated there and the step is
   solved again without them (the clamping loop); the comfort part is shortened to stay inside. Contact edge
   weights (>= 0) carry a log barrier's curvature in the metric, so lightly loaded edges move little and
   rarely need that re-solve (as the tan^2 curvature does for joints near their limits).
4. Acceptance: a task step must lower the constraint error; far from the constraints the comfort part may
   ride along if the error still falls and comfort ends no worse than the model predicts for the task part
   alone. Far away a step is first shortened so that no joint turns more than MAX_TURN (as Buss & Kim's
   selectively damped least squares clamps joint changes): the linear model holds about that far, and the
   iterate stays in the basin of a comfortable pose. Near the constraints (within COMFORT_SLACK tolerances)
   task + comfort is tried first and must lower the exact-penalty merit -h + nu sum |scaled error|, nu twice
   the largest multiplier estimate (or meet the constraints and raise h), judged after a second-order
   correction that reuses the same factors. A rejected step is halved, then the task part is tried alone (its
   step length from a safeguarded quadratic fit of the error); when comfort keeps failing, mu grows and the
   comfort part turns back into the thesis's gradient step. A full step that raises the error gets the same
   correction before it is shortened: far from the constraints the balance moment is what bends (a step that
   swings the body's weight and moves the center of pressure under it is bilinear in both), and the
   correction keeps the full step where backtracking would keep a tenth of it (measured on 480 fresh random
   trials: iterations -7 %, evaluations -5 %, time -7 %, comfort and success unchanged).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from functools import cached_property

import numpy as np
from scipy.linalg import lapack

from .options import DEFAULT_OPTIONS, SolverOptions
from .problem import Problem
from .result import Result

POLISH_ITERATIONS = 20  # iterations kept for restoring the constraints without comfort
HOVER_LIMIT = 12  # comfort iterations just outside the constraints before the restoring phase takes over
FRACTION_NEAR = 0.02  # scaled distance below which a joint may be saturated right at its limit
INITIAL_MU = 0.1  # comfort metric damping at the start (x mean curvature); measured: fewer rejected comfort steps
COMFORT_SLACK = 10.0  # how far (in tolerances) a comfort step may leave the constraints before the next task step
# A second-order correction shrinks a comfort step's constraint error by a factor 2..8 (measured), so a trial more than
# HOPELESS x COMFORT_SLACK off is halved without one: random trials -2 % evaluations, comfort unchanged.
HOPELESS = 5.0
MAX_TURN = 0.3  # rad: largest joint rotation of a step far from the constraints; measured: 0.25..0.4 better than none
MAX_SLIDE = 0.3  # m: the same for a prismatic joint
STAGNATION_WINDOW = 10  # iterations over which the error must fall by STAGNATION_GAIN while far from the constraints
STAGNATION_GAIN = 0.02  # measured on 300 random trials: no success lost, failures stop after ~55 instead of 100
# Without comfort every accepted step lowers the error, so the sum of squares is judged over a shorter window; the
# worst row must also fall over STAGNATION_WINDOW (a flat worst row under a slowly falling sum is a stall too).
# Measured on 320 random trials: no success lost, unreachable targets give up ~20 iterations sooner (-4 % overall).
RESTORE_STAGNATION_WINDOW = 3
# Contact edge weights w >= 0 get FORCE_BARRIER / (w / body weight)^2 in the step's metric (scaled variables, where a
# joint's entry is about 1..10), like joints near their limits. Measured on 240 random trials: clamping re-solves per
# step 2.6 -> 1.8, iterations -4 %, evaluations -12 %, comfort better (geometric mean of |h| -10 %); 0.01 / 0.03 / 0.1
# / 0.3 / 1 and a multiple of the mean curvature did less. The floor keeps an edge at zero free to take load again.
FORCE_BARRIER = 0.05
FORCE_FLOOR = 0.01
# A comfort phase ends after a full, feasible comfort step predicted to gain less than FINAL_GAIN x the comfort
# tolerance, instead of spending one more iteration to find the next gain negligible. Measured: random trials -5 %
# iterations and evaluations, comfort 0.5 % lower (geometric mean of |h|); warm re-solves 2.9 -> 2.1 iterations. So
# does one predicted to gain < 2 FINAL_GAIN x tolerance that gained less than the tolerance (warm: 2.1 -> 1.9).
FINAL_GAIN = 2.0
# A failed solve starts again from its pose with the joints that ended near a limit (within RESTART_NEAR of their
# range) moved to RESTART_AT of their range from the other limit. Measured on 25 failures at Max Dev = pi: 19 met
# their targets after one such restart; starting those joints at their neutral values instead rescued 4.
RESTART_NEAR = 0.05
RESTART_AT = 0.25
MEMORY = 6  # curvature pairs kept by the quasi-Newton comfort model; measured: 3 and 12 no better




@dataclass
class _Step:
    task: np.ndarray  # scaled task step (fixed variables included)
    comfort: np.ndarray  # scaled comfort step
    predicted_gain: float  # comfort gain the quadratic model predicts for the comfort step (>= 0)
    free: np.ndarray  # variables the step moved freely
    least_squares: _LeastSquares  # the factors of the free variables' Jacobian, in the metric
    root_metric: np.ndarray  # square root of the metric on the free variables
    free_gradient: np.ndarray  # grad f on the free variables, in the metric

    def correction(self, err: np.ndarray) -> np.ndarray:
        """Second-order correction: the task step for a new error, reusing this step's factors."""
        out = np.zeros_like(self.task)
        out[self.free] = self.least_squares.step(err) / self.root_metric
        return out

    @cached_property
    def multipliers(self) -> np.ndarray:
        """Per scaled row: lambda with grad f + J^T lambda ~ 0 on the free variables (only near the constraints)."""
        return self.least_squares.multipliers(self.free_gradient)

    @cached_property
    def penalty(self) -> float:
        """Weight of sum |scaled error| in the merit: twice the largest multiplier estimate."""
        return 2.0 * float(np.max(np.abs(self.multipliers), initial=0.0)) + 1e-9


class _LeastSquares:
    """Damped least squares on one Jacobian J (m x n): steps, row-space basis, multipliers.

    Everything comes from G = J J^T (m is ~24, n ~100..190). Steps and multipliers use (G + d^2 I)^-1 with a
    Tikhonov damping d = max_damping * s_max (s_max^2 estimated by ||G||_F, at most sqrt(m) times larger), which
    only changes singular values within ~10 d of it: the damped least squares of Nakamura & Hanafusa near
    singularities, negligible elsewhere. The row-space basis for the null-space projection is L^-1 J, G = L L^T,
    undamped. A trust region adds Levenberg-Marquardt damping found by Newton's method on the secular equation
    (Moré & Sorensen), each trial one Cholesky of an m x m matrix. When G is numerically singular (or too
    ill-conditioned for Cholesky to be trusted) its eigendecomposition stands in for the factors.
    """

    def __init__(self, jac: np.ndarray, opts: SolverOptions) -> None:
        self._jac = jac
        m = jac.shape[0]
        gram = jac @ jac.T
        self._gram = gram
        self._damp2 = opts.max_damping**2 * math.sqrt(float(np.vdot(gram, gram)))
        self._eig: tuple[np.ndarray, np.ndarray] | None = None
        self._factors: dict[float, np.ndarray] = {}
        low, info = lapack.dpotrf(gram, lower=1) if m else (None, 1)
        inverse = None
        if info == 0:
            inverse, info = lapack.dtrtri(low, lower=1)
        # cond(G) <= trace(G) ||L^-1||_F^2 <= 1e10 keeps L^-1 J orthonormal to ~1e-5 (eps cond); beyond, eigenvectors
        if info == 0 and float(gram.diagonal().sum()) * float(np.vdot(inverse, inverse)) < 1e10:
            self.basis = inverse @ jac  # orthonormal rows spanning the row space
        else:
            lam, u = np.linalg.eigh(gram) if m else (np.zeros(0), np.zeros((0, 0)))
            keep = lam > 1e-14 * max(float(lam[-1]), 0.0) if m else np.zeros(0, dtype=bool)
            self._eig = (np.clip(lam, 0.0, None), u)
            self.basis = (u[:, keep] / np.sqrt(lam[keep])).T @ jac  # undamped; J J^T gives s >= 1e-7 s_max accurately

    def _solve(self, rhs: np.ndarray, extra2: float = 0.0) -> np.ndarray:
        """(G + (d^2 + extra2) I)^-1 rhs."""
        shift = self._damp2 + extra2
        if self._eig is not None:
            lam, u = self._eig
            denom = lam + shift
            return u @ np.divide(u.T @ rhs, denom, out=np.zeros_like(lam), where=denom > 0)
        factor = self._factors.get(shift)
        if factor is None:
            shifted = self._gram.copy()
            shifted.flat[:: len(shifted) + 1] += shift
            factor, info = lapack.dpotrf(shifted, lower=1, overwrite_a=1)
            if info != 0:  # cannot happen for shift >= 0 once G itself factored; stay finite regardless
                return np.zeros_like(rhs)
            self._factors[shift] = factor
        return lapack.dpotrs(factor, rhs, lower=1)[0]

    def step(self, err: np.ndarray, extra2: float = 0.0) -> np.ndarray:
        """-J^T (G + d^2 I)^-1 err (plus ``extra2``, a squared LM damping)."""
        return -self._jac.T @ self._solve(err, extra2)

    def step_within(self, err: np.ndarray, col_scale: np.ndarray, radius: float) -> np.ndarray:
        """The step, in variables ``col_scale * y``, with LM damping raised until its 2-norm <= radius."""
        z = self._solve(err)
        scaled = self._jac * col_scale  # the step is -scaled^T z
        out = -scaled.T @ z
        size = math.sqrt(float(out @ out))
        if size <= radius:
            return out
        weight = scaled @ scaled.T  # ||step||^2 = z^T weight z, only needed when the trust region binds
        extra2 = 0.0
        for _ in range(30):
            if size <= 1.05 * radius:
                break
            # Newton on 1/||step(extra2)|| = 1/radius: d||step||^2/d extra2 = -2 z^T weight (G + shift I)^-1 z
            slope = -2.0 * float((weight @ z) @ self._solve(z, extra2))
            if not slope < 0.0:
                extra2 = 4.0 * extra2 + self._damp2 + 1e-300
            else:
                extra2 += (1.0 / size - 1.0 / radius) / (0.5 * slope / size**3)
            z = self._solve(err, extra2)
            size = math.sqrt(max(float(z @ weight @ z), 0.0))
        out = -scaled.T @ z
        size = math.sqrt(float(out @ out))
        return out * (radius / size) if size > radius else out

    def multipliers(self, g: np.ndarray) -> np.ndarray:
        """lambda with g + J^T lambda ~ 0 (damped least squares)."""
        return -self._solve(self._jac @ g)


class _CurvatureMemory:
    """Limited-memory BFGS model of the Lagrangian's curvature, in scaled variables.

    Pairs s = step, y = change of grad f + J^T lambda (one lambda for both ends, so y sees the constraints'
    curvature); a pair with s.y <= 0 is skipped, which keeps the model positive definite. The model on top of
    a diagonal b0 is B = diag(b0) - U M^-1 U^T (the compact form of Byrd, Nocedal & Schnabel 1994).
    """

    def __init__(self, size: int) -> None:
        self.size = size
        self.steps: list[np.ndarray] = []
        self.changes: list[np.ndarray] = []
        self._pairs: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray] | None = None  # what b0 does not change

    def add(self, step: np.ndarray, change: np.ndarray) -> None:
        if float(step @ change) > 1e-10 * float(step @ step) and np.all(np.isfinite(change)):
            self.steps = [*self.steps, step][-self.size :]
            self.changes = [*self.changes, change][-self.size :]
            self._pairs = None

    def compact(self, b0: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
        """(U (n, 2k), M (2k, 2k)) with B = diag(b0) - U M^-1 U^T; None while the memory is empty."""
        if not self.steps:
            return None
        if self._pairs is None:
            s, y = np.array(self.steps).T, np.array(self.changes).T
            s_y = s.T @ y
            self._pairs = (s, y, np.tril(s_y, -1), -np.diag(np.diag(s_y)))
        s, y, lower, minus_diagonal = self._pairs
        b0_s = b0[:, None] * s
        k = s.shape[1]
        middle = np.empty((2 * k, 2 * k))
        middle[:k, :k] = s.T @ b0_s
        middle[:k, k:] = lower
        middle[k:, :k] = lower.T
        middle[k:, k:] = minus_diagonal
        return np.concatenate((b0_s, y), axis=1), middle


def null_space_newton(grad: np.ndarray, basis: np.ndarray, low_rank: tuple[np.ndarray, np.ndarray] | None):
    """argmin_z grad.z + z.B z / 2 subject to basis z = 0, B = I - V M^-1 V^T, ``low_rank`` = (V, M) or None.

    ``basis`` has orthonormal rows (the row space to stay out of). Woodbury on the null space: with
    A = (I - P) V, the step is -(q - A (A^T A - M)^-1 A^T q), q = (I - P) grad. Falls back to -q (B = I)
    when the correction is singular or not a descent direction.
    """
    q = grad - basis.T @ (basis @ grad)
    if low_rank is None:
        return -q
    v, middle = low_rank
    a = v - basis.T @ (basis @ v)
    _, _, inner, info = lapack.dgesv(a.T @ a - middle, a.T @ q)
    if info != 0:
        return -q
    z = -(q - a @ inner)
    return z if (math.isfinite(float(z @ z)) and z @ grad < 0.0) else -q


def _step(problem: Problem, x, jac, err, grad_f, curv_f, mu, radius, opts, comfort_on, memory) -> _Step:
    """Task and comfort step (scaled variables) in the metric W = diag(curvature of -h) + mu, inside bounds.

    With y = W^(1/2) dx the step is the thesis's: y = -Jw^+ err - (I - Jw^+ Jw) W^(-1/2) grad f, Jw = J W^(-1/2),
    the exact minimiser of the diagonal comfort model on the linearised constraints. The bound check is made
    on the sum of both parts, so a joint that the task alone would push past its limit stays free when
    comfort pulls it back; variables the sum pushes past a bound are saturated there and the step is solved
    again without them. Without comfort (``comfort_on`` false) the metric is the curvature alone if one is
    given, else the identity.
    """
    lo = (problem.lower - x) / problem.scale
    hi = (problem.upper - x) / problem.scale
    # Start by holding variables on a bound that neither the constraint error nor comfort would pull inwards.
    outward = jac.T @ err + grad_f  # descent of both pushes along -outward
    free = (lo < hi) & ~((lo >= -1e-12) & (outward >= 0)) & ~((hi <= 1e-12) & (outward <= 0))
    if comfort_on or curv_f.any():
        curv_free = curv_f[free]
        level = float(curv_free.sum()) / curv_free.size if curv_free.size else 1.0  # their mean curvature
        metric = curv_f + mu * max(level, 1e-12) + 1e-12
        force = ~problem.is_joint
        if force.any():  # a log barrier's curvature keeps lightly loaded contact edges from being driven negative
            share = np.maximum(x[force] / problem.scale[force], FORCE_FLOOR)  # edge weight / body weight
            metric[force] += FORCE_BARRIER / (share * share)
    else:
        metric = np.ones_like(x)
    root = np.sqrt(metric)
    fixed = np.zeros_like(x)
    n = len(x)
    compact = memory.compact(curv_f + 1e-12) if memory is not None else None  # memory is None without comfort
    task = np.zeros(n)
    comfort = np.zeros(n)
    for _ in range(opts.clamping_rounds):
        err_eff = err + jac[:, ~free] @ fixed[~free] if (~free).any() else err
        r_f = root[free]
        lsq = _LeastSquares(jac[:, free] / r_f, opts)
        basis = lsq.basis
        task = fixed.copy()
        task[free] = lsq.step_within(err_eff, 1.0 / r_f, radius)
        comfort = np.zeros(n)
        if comfort_on:
            g_w = grad_f[free] / r_f
            low_rank = None if compact is None else (compact[0][free] / r_f[:, None], compact[1])
            comfort[free] = null_space_newton(g_w, basis, low_rank) / r_f
            biggest = float(np.abs(comfort).max()) if n else 0.0
            if biggest > opts.max_comfort_step:
                comfort *= opts.max_comfort_step / biggest
        total = task + comfort
        below = free & (total < lo - 1e-12)
        above = free & (total > hi + 1e-12)
        if not (below.any() or above.any()):
            break
        if _ == opts.clamping_rounds - 1:
            # out of rounds: shorten the comfort part so that the sum stays inside the bounds
            with np.errstate(divide="ignore", invalid="ignore"):
                room = np.where(comfort > 0, (hi - task) / comfort, np.where(comfort < 0, (lo - task) / comfort, 1.0))
            comfort *= float(np.clip(np.min(room, initial=1.0), 0.0, 1.0))
            break
        # Saturate: a joint stops halfway to its limit unless it is already close to it (fraction to the
        # boundary, so the tan^2 comfort is not slammed to its wall); forces stop exactly at zero.
        joint = problem.is_joint
        fixed[below] = lo[below] * np.where(joint[below] & (-lo[below] > FRACTION_NEAR), 0.5, 1.0)
        fixed[above] = hi[above] * np.where(joint[above] & (hi[above] > FRACTION_NEAR), 0.5, 1.0)
        free &= ~(below | above)
    if not (np.isfinite(task).all() and np.isfinite(comfort).all()):
        task, comfort = np.nan_to_num(task), np.nan_to_num(comfort)
    predicted = -(grad_f @ comfort + 0.5 * (curv_f * comfort) @ comfort) if comfort_on else 0.0
    if compact is not None:  # the quasi-Newton part of comfort @ B @ comfort / 2
        u_c = compact[0].T @ comfort
        _, _, inner, info = lapack.dgesv(compact[1], u_c)
        if info == 0:
            predicted += 0.5 * float(u_c @ inner)
    r_free = root[free]
    return _Step(task, comfort, max(float(predicted), 0.0), free, lsq, r_free, grad_f[free] / r_free)


class _Evaluator:
    """Evaluates x once: state, scaled error, merit (sum of squares), worst unweighted scaled error; f = -h on
    demand (:meth:`cost`), since trial points rejected on their error never need it."""

    def __init__(self, problem: Problem, comfort_on: bool) -> None:
        self.problem = problem
        self.comfort_on = comfort_on
        self.unweight = 1.0 / problem.row_weight if problem.n_rows else np.zeros(0)

    def __call__(self, x: np.ndarray):
        state = self.problem.state(x)
        err = self.problem.scaled_error(state)
        worst = float(np.max(np.abs(err) * self.unweight, initial=0.0))
        return state, err, float(err @ err), worst

    def cost(self, state) -> float:
        """f = -h at ``state`` (0 without comfort), computed once per state."""
        if not self.comfort_on:
            return 0.0
        f = state.cache.get(self)
        if f is None:
            f = state.cache[self] = -self.problem.comfort.value(state)
        return f


def solve(problem: Problem, x0: np.ndarray | None = None, options: SolverOptions = DEFAULT_OPTIONS) -> Result:
    """Find x meeting the constraints and maximising comfort, warm-started from ``x0`` (any earlier pose).

    Comfort is optimised while the constraints are met; if they are not met by the end of that phase (or the
    iterate keeps hovering just outside them), the last iterations restore them with comfort switched off
    (but still in its curvature metric, which keeps joints off their limits). A phase ends early when, far
    from the constraints, the error has stopped falling (unreachable targets: the best compromise, sooner).
    A solve that still fails starts again (up to ``options.restarts`` times) from :func:`restart_pose`; the
    result is the first that meets the constraints, else the one with the smallest worst error, with the
    iterations and time of all attempts.
    """
    t0 = time.perf_counter()
    worst, used, state = _attempt(problem, problem.start(x0), options)
    for _ in range(options.restarts):
        if worst <= 1.0:
            break
        start = restart_pose(problem, state.x)
        if start is None:
            break
        worst_again, more, state_again = _attempt(problem, problem.start(start), options)
        used += more
        if worst_again < worst:
            worst, state = worst_again, state_again
    return Result.from_state(problem, state, used, time.perf_counter() - t0)


def restart_pose(problem: Problem, x: np.ndarray) -> np.ndarray | None:
    """Where a failed solve starts again: its pose x (joints + forces) with every joint that ended within
    RESTART_NEAR of its range from a limit moved to the other side of its range (RESTART_AT of the range from
    the opposite limit); None when no joint ended at a limit.

    A local solver fails mostly in a local minimum: an arm twisted the wrong way round to a hand orientation,
    its forearm or shoulder rotation stopped at a limit (for Max Dev = pi in the random benchmark, 21 of 25
    failures met their targets from some other start). Starting those joints from the other side lets the
    iteration take the other way round.
    """
    model = problem.model
    n = model.n
    theta = x[:n]
    span = model.upper - model.lower
    finite = np.isfinite(span) & (span > 0)
    at_upper = finite & (model.upper - theta < RESTART_NEAR * span)
    at_lower = finite & (theta - model.lower < RESTART_NEAR * span) & ~at_upper
    if not (at_upper.any() or at_lower.any()):
        return None
    out = np.array(x, dtype=float)
    out[:n][at_upper] = (model.lower + RESTART_AT * span)[at_upper]
    out[:n][at_lower] = (model.upper - RESTART_AT * span)[at_lower]
    return out


def _attempt(problem: Problem, x: np.ndarray, opts: SolverOptions):
    """One solve from solver variables x: the comfort phase, then (if needed) the restoring phase; returns
    (worst scaled error, iterations, the state it ended at)."""
    budget = opts.max_iterations
    used = 0
    state = None
    if opts.optimize_comfort:
        polish = min(POLISH_ITERATIONS, budget // 3)
        x, worst, used, state = _iterate(problem, x, opts, True, budget - polish)
    else:
        worst = np.inf
    if worst > 1.0 and used < budget:
        x, worst, more, state = _iterate(problem, x, opts, False, budget - used, keep_off_limits=opts.optimize_comfort)
        used += more
    if state is None:  # no iteration ran: the start itself
        state, _, _, worst = _Evaluator(problem, False)(x)
    return worst, used, state


def _iterate(
    problem: Problem, x: np.ndarray, opts: SolverOptions, comfort_on: bool, budget: int, keep_off_limits: bool = False
):
    """Up to ``budget`` iterations from x; returns (x, worst scaled error, iterations used, the state at x).

    Without comfort, ``keep_off_limits`` still steps in the comfort's curvature metric (no comfort part), so
    restoring the constraints after the comfort phase does not drive joints onto their limits.
    """
    evaluate = _Evaluator(problem, comfort_on)
    state, err, merit, worst = evaluate(x)
    f = evaluate.cost(state)
    mu = INITIAL_MU
    radius = opts.max_step
    stalls = hovering = quiet = 0  # quiet: feasible iterations in a row that gained negligible comfort
    iterations = 0
    memory = _CurvatureMemory(MEMORY) if comfort_on else None
    move_limit = np.where(problem.model.prismatic, MAX_SLIDE, MAX_TURN)
    previous = None  # (x, jac, grad_f, step) of the previous iteration
    history: list[tuple[float, float]] = []  # (merit, worst) after each iteration
    stagnant_above = COMFORT_SLACK if comfort_on else 1.0
    window = STAGNATION_WINDOW if comfort_on else RESTORE_STAGNATION_WINDOW
    while iterations < budget:
        iterations += 1
        jac = problem.scaled_jacobian(state)
        if comfort_on:
            grad_h, curv = problem.comfort_derivatives(state)
            grad_f, curv_f = -grad_h * problem.scale, curv * problem.scale**2
            # Curvature pairs only near the constraints: far away the multipliers are no estimate yet.
            if previous is not None and previous[0] is not x and worst <= COMFORT_SLACK:
                x_old, jac_old, grad_old, step_old = previous
                memory.add((x - x_old) / problem.scale, grad_f - grad_old + (jac - jac_old).T @ step_old.multipliers)
        elif keep_off_limits:
            grad_f, curv_f = np.zeros(problem.n_var), problem.comfort_derivatives(state)[1] * problem.scale**2
        else:
            grad_f, curv_f = np.zeros(problem.n_var), np.zeros(problem.n_var)
        step = _step(problem, x, jac, err, grad_f, curv_f, mu, radius, opts, comfort_on, memory)
        previous = (x, jac, grad_f, step)
        negligible = opts.comfort_tolerance * max(f, 1.0)
        if worst <= 1.0 and (step.predicted_gain <= negligible or quiet >= 2):
            break
        hovering = hovering + 1 if 1.0 < worst <= COMFORT_SLACK else 0
        if comfort_on and hovering > HOVER_LIMIT:
            break

        # Far from the constraints only the task part is tried (its metric already keeps joints off their
        # limits); near them task + comfort first, halved once, then the task part alone.
        near = worst <= COMFORT_SLACK
        if step.predicted_gain > 0:
            attempts = [(True, 2), (False, 4)] if near else [(True, 1), (False, 5)]
        else:
            attempts = [(False, 5)]
        accepted = use_comfort = settled = False
        task_change = 0.0  # f's predicted rise from the task part alone (diagonal model): a ride-along need not undo it
        if not near and step.predicted_gain > 0:
            task_change = max(float(grad_f @ step.task + 0.5 * (curv_f * step.task) @ step.task), 0.0)
        alpha = 1.0
        for use_comfort, tries in attempts:
            direction = step.task + step.comfort if use_comfort else step.task
            if not near:  # far away, a joint turns at most MAX_TURN per step: the linear model holds about that far
                move = np.abs(problem.joint_change(state, direction * problem.scale)) / move_limit
                direction = direction / max(float(np.max(move, initial=0.0)), 1.0)
            # d merit / d alpha at 0 on the linear model, for the task part's backtracking
            slope = 0.0 if use_comfort else 2.0 * float(err @ (jac @ direction))
            alpha = 1.0
            for _ in range(tries):
                x_try = np.clip(x + alpha * direction * problem.scale, problem.lower, problem.upper)
                s_try, e_try, m_try, w_try = evaluate(x_try)
                if use_comfort and near and w_try > HOPELESS * COMFORT_SLACK:
                    alpha *= 0.5  # too far off for a correction to bring it back: halve without trying one
                    continue
                # Second-order correction before judging the trial: a comfort step near the constraints is pulled
                # back onto them (kept if it lowers the error); a full step (task, or far away task + comfort) that
                # the constraints' curvature undid (the balance moment is bilinear in joint motion and forces) gets
                # the same correction before backtracking (kept if it beats the current error).
                if use_comfort and near:
                    bar = m_try if w_try > 1.0 else None
                else:
                    bar = merit if (comfort_on and alpha == 1.0 and merit <= m_try < np.inf) else None
                if bar is not None:
                    x_soc = np.clip(x_try + step.correction(e_try) * problem.scale, problem.lower, problem.upper)
                    soc = evaluate(x_soc)
                    if soc[2] < bar:
                        x_try, (s_try, e_try, m_try, w_try) = x_soc, soc
                if use_comfort and not near:  # far from the constraints comfort rides along a task step
                    better = m_try < merit and evaluate.cost(s_try) < f + task_change + step.predicted_gain
                elif use_comfort:
                    penalty = step.penalty * (np.abs(e_try).sum() - np.abs(err).sum())
                    # the exact-penalty merit, or (as a filter would) any feasible point that is more comfortable:
                    # 840 fresh random trials, evaluations -1.8 %, time -2 %, comfort and success unchanged
                    cost_try = evaluate.cost(s_try)
                    feasible_gain = w_try <= 1.0 and cost_try < f
                    better = w_try <= COMFORT_SLACK and (cost_try - f + penalty < 0.0 or feasible_gain)
                else:
                    better = m_try < merit
                if better and np.isfinite(m_try) and np.isfinite(evaluate.cost(s_try)):
                    accepted = True
                    f_try = evaluate.cost(s_try)
                    break
                if use_comfort or not np.isfinite(m_try):
                    alpha *= 0.5
                else:  # minimum of the quadratic through merit(0), its slope and merit(alpha), safeguarded
                    bend = (m_try - merit - alpha * slope) / alpha**2
                    guess = -slope / (2.0 * bend) if (slope < 0.0 and bend > 0.0) else 0.5 * alpha
                    alpha = float(np.clip(guess, 0.1 * alpha, 0.5 * alpha))
            if accepted:
                break
        if near and step.predicted_gain > 0:
            if accepted and use_comfort:
                ratio = (f - f_try) / (alpha * step.predicted_gain)
                mu = mu / 4 if (ratio > 0.75 and alpha == 1.0) else (mu * 4 if ratio < 0.25 else mu)
            else:
                mu *= 4
        if accepted:
            quiet = quiet + 1 if (w_try <= 1.0 and f - f_try < negligible) else 0
            # a full, feasible comfort step that was to gain little (or did gain little, as a modest prediction
            # confirmed) leaves less than the tolerance for the next one
            small = step.predicted_gain < FINAL_GAIN * negligible
            confirmed = f - f_try < negligible and step.predicted_gain < 2 * FINAL_GAIN * negligible
            settled = use_comfort and alpha == 1.0 and w_try <= 1.0 and (small or confirmed)
            x, state, err, merit, worst, f = x_try, s_try, e_try, m_try, w_try, f_try
            stalls = 0
            radius = min(2 * radius, opts.max_step) if alpha == 1.0 else radius
        else:
            stalls += 1
            radius = max(radius / 4, 1e-6)
            if stalls >= 6:
                break
        mu = float(np.clip(mu, 1e-8, 1e8))
        if settled:
            break
        history.append((merit, worst))
        if worst > stagnant_above and len(history) > window:
            stalled = merit > (1.0 - STAGNATION_GAIN) * history[-1 - window][0]
            if len(history) > STAGNATION_WINDOW:
                stalled |= worst > (1.0 - STAGNATION_GAIN) * history[-1 - STAGNATION_WINDOW][1]
            if stalled:
                break  # far from the constraints and the error no longer falls: the targets are out of reach
    return x, worst, iterations, state
