"""Peers for the randomized-target benchmark: the same trials solved by a general NLP solver and by placo.

Both are judged only by our constraint function (every row of ``problem`` within its tolerance, i.e. the
worst unweighted scaled error <= 1, exactly what makes :func:`solver.solve` report ``converged``).

* :func:`slsqp_peer`: the same problem as a general nonlinear program, handed to ``scipy.optimize``:
  maximise the comfort h(v) subject to ``problem.scaled_error(v) = 0`` (every target row, the balance rows)
  and ``problem.bounds``, with our exact gradient and Jacobian, from ``problem.start()``.
  The variables are scaled (z = v / problem.scale, as our solver's), so the constraint Jacobian is
  ``problem.scaled_jacobian`` as it stands.
* :func:`placo_peer`: placo's ``KinematicsSolver`` (a QP per iteration, differential IK) on the URDF export
  of the manikin. It has no unknown contact forces: the feet are soft tasks of weight 100 (sole height z and
  the roll and pitch of the sole: our lock z, rx, ry; hard ones made the QP infeasible after a few steps),
  balance is a hard CoM-inside-the-support-polygon constraint (the convex hull of both soles' corners,
  refreshed from the current foot frames before every QP; a weight-1 task holds each sole's x, y where it
  stood before the step, without which feet and CoM ran away together), the hands are soft frame tasks.
  After it stops, its joint values are mapped back by name and the contact forces that balance the pose
  best are found by non-negative least squares on our balance rows (with only gravity acting, they exist
  exactly when the CoM is over the support polygon). placo is a benchmark extra (requirements-bench.txt),
  imported only here, only when used.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from scipy.optimize import minimize, nnls

from solver.body.model import Model
from solver.problem.problem import Problem

POSITION_TOLERANCE = 1e-3  # m, our frame constraint's tolerance
ANGLE_TOLERANCE = np.deg2rad(0.2)  # rad


class PeerResult(NamedTuple):
    """A peer's outcome: the first three fields are (converged, time_s, iterations).

    ``converged`` is judged by our constraint function; ``worst`` is the worst unweighted scaled error
    (<= 1 is converged), ``message`` the peer's own account of why it stopped, ``unmet`` the names of our
    constraints left unmet and ``comfort`` our comfort h at the returned pose (forces included).
    """

    converged: bool
    time_s: float
    iterations: int
    worst: float = np.inf
    message: str = ""
    unmet: tuple[str, ...] = ()
    comfort: float = np.nan


def judge(problem: Problem, x: np.ndarray) -> tuple[bool, float, tuple[str, ...], float]:
    """(converged, worst unweighted scaled error, names of unmet constraints, comfort h) of a full
    x = [joints, forces], by our constraint and comfort functions."""
    state = problem.state_of_x(np.asarray(x, dtype=float))
    err = problem.scaled_error(state)
    worst = float(np.max(np.abs(err) / problem.row_weight, initial=0.0)) if problem.n_rows else 0.0
    unmet = tuple(problem.unmet(state))
    return bool(not unmet and np.isfinite(worst)), worst, unmet, float(problem.comfort.value(state))


# --------------------------------------------------------------------------------------------- SLSQP


class _Cache:
    """Evaluates the problem once per point: scipy asks for f, grad f, c and grad c separately."""

    def __init__(self, problem: Problem) -> None:
        self.problem = problem
        self.key: bytes | None = None
        self.state = None

    def at(self, z: np.ndarray):
        key = z.tobytes()
        if key != self.key:
            self.key = key
            self.state = self.problem.state(z * self.problem.scale)
        return self.state


def slsqp_peer(problem: Problem, method: str = "SLSQP", max_iterations: int = 500) -> PeerResult:
    """Maximise comfort subject to our constraints with ``scipy.optimize.minimize`` (SLSQP or trust-constr).

    Works in z = v / scale; objective -h(v) with gradient -dh/dv * scale; equality constraints
    scaled_error(v) = 0 with Jacobian scaled_jacobian (already d / dz); bounds lower / scale, upper / scale.
    """
    scale = problem.scale
    cache = _Cache(problem)

    def objective(z: np.ndarray) -> float:
        return -problem.comfort.value(cache.at(z))

    def gradient(z: np.ndarray) -> np.ndarray:
        return -problem.comfort_derivatives(cache.at(z))[0] * scale

    def constraint(z: np.ndarray) -> np.ndarray:
        return problem.scaled_error(cache.at(z))

    def jacobian(z: np.ndarray) -> np.ndarray:
        return problem.scaled_jacobian(cache.at(z))

    lower = np.where(np.isfinite(problem.bounds.lower), problem.bounds.lower / scale, -np.inf)
    upper = np.where(np.isfinite(problem.bounds.upper), problem.bounds.upper / scale, np.inf)
    z0 = problem.start() / scale
    t0 = time.perf_counter()
    if method == "SLSQP":
        result = minimize(
            objective, z0, jac=gradient, method="SLSQP", bounds=list(zip(lower, upper, strict=True)),
            constraints=[{"type": "eq", "fun": constraint, "jac": jacobian}],
            options={"maxiter": max_iterations, "ftol": 1e-6},
        )  # fmt: skip
    elif method == "trust-constr":
        from scipy.optimize import Bounds, NonlinearConstraint

        result = minimize(
            objective, z0, jac=gradient, method="trust-constr", bounds=Bounds(lower, upper),
            constraints=[NonlinearConstraint(constraint, 0.0, 0.0, jac=jacobian)],
            options={"maxiter": max_iterations, "gtol": 1e-6, "xtol": 1e-9},
        )  # fmt: skip
    else:
        raise ValueError(f"unknown method {method!r} (SLSQP or trust-constr)")
    elapsed = time.perf_counter() - t0
    z = np.clip(np.nan_to_num(result.x), lower, upper)
    converged, worst, unmet, comfort = judge(problem, problem.to_x(z * scale))
    iterations = int(getattr(result, "nit", 0))
    return PeerResult(converged, elapsed, iterations, worst, str(result.message), unmet, comfort)


# --------------------------------------------------------------------------------------------- placo


@dataclass(frozen=True)
class PlacoSettings:
    """How placo is driven: task weights, its regularisation, its per-step joint speed limit, the stop."""

    hand_weight: float = 1.0  # soft frame tasks (position m and orientation rad weighted alike)
    foot_weight: float = 100.0  # soft sole height and roll/pitch tasks ("hard" makes placo's QP infeasible)
    foot_priority: str = "soft"
    regularization: float = 1e-2  # placo's regularisation task: damps each QP step
    dt: float = 0.0  # > 0: joint velocity limits (URDF velocity x dt per step); 0: off
    com_margin: float = 0.005  # m inside the support polygon
    slide_weight: float = 1.0  # soft task holding each sole's x, y where it stood before the step (sliding damper)
    max_iterations: int = 100  # as our solver's default
    stop_fraction: float = 0.5  # stop when placo's own task errors are below this fraction of our tolerances
    stall: float = 1e-7  # stop when the largest joint change of a step is below this (rad or m)


DEFAULT_PLACO = PlacoSettings()

_ROBOTS: dict[int, object] = {}  # one placo robot per model, per process (building it takes ~0.1 s)


def placo_available() -> bool:
    try:
        import placo  # noqa: F401
    except ImportError:
        return False
    return True


def _robot_for(model: Model):
    import placo

    from solver.io.urdf import model_to_urdf

    key = id(model)
    if key not in _ROBOTS:
        _ROBOTS.clear()
        _ROBOTS[key] = (model, placo.RobotWrapper("", 0, model_to_urdf(model)))
    return _ROBOTS[key][1]


def balancing_forces(problem: Problem, theta: np.ndarray) -> np.ndarray:
    """Contact edge weights w >= 0 (N) that best balance the pose ``theta``: NNLS on the scaled balance rows.

    The balance error is affine in w: e(w) = e(0) + A w, so this is min |e(0) + A w| over w >= 0.
    """
    n, n_w = problem.model.n, problem.contacts.n_vars
    if n_w == 0:
        return np.zeros(0)
    state = problem.state_of_x(np.concatenate([theta, np.zeros(n_w)]))
    e0 = problem.scaled_error(state)
    jac = problem.scaled_jacobian(state)
    if problem.reduction is not None:
        raise ValueError("balancing_forces needs a problem without variable reduction")
    a = jac[:, n:] / problem.scale[n:]
    rows = np.any(a != 0.0, axis=1)  # only the balance rows depend on the forces
    w, _ = nnls(a[rows], -e0[rows])
    return w


def _support_polygon(robot, feet) -> list[np.ndarray]:
    """Clockwise convex hull (world x-y) of the soles' corners at the robot's current foot frames."""
    from scipy.spatial import ConvexHull

    points = []
    for frame, sole in feet:
        t = robot.get_T_world_frame(frame)
        for sx, sy in sole:
            points.append((t[:3, :3] @ np.array([sx, sy, 0.0]) + t[:3, 3])[:2])
    points = np.array(points)
    hull = ConvexHull(points)
    return [points[i] for i in hull.vertices[::-1]]  # scipy gives counter-clockwise in 2-D


def _placo_tasks(solver, robot, problem: Problem, settings: PlacoSettings) -> tuple[list, list, list]:
    """placo tasks for the problem's targets: (feet (frame, sole), slide anchors, (task, our tolerance) checks)."""
    model = problem.model
    feet, anchors = [], []
    checks = []  # (placo task, our tolerance in its units): the stop test
    zero = model.forward(model.zero_pose())
    for target in problem.targets:
        frame = f"tcp_{target.tcp}"
        rotation = target.rotation if target.rotation is not None else zero.tcp_frame(model.tcp(target.tcp))[0]
        if target.support:
            height = solver.add_position_task(frame, np.asarray(target.position, dtype=float))
            height.mask.set_axises("z", "task")
            height.configure(f"{target.tcp}_z", settings.foot_priority, settings.foot_weight)
            flat = solver.add_orientation_task(frame, np.asarray(rotation, dtype=float))
            flat.mask.set_axises("xy", "task")
            flat.configure(f"{target.tcp}_flat", settings.foot_priority, settings.foot_weight)
            checks += [(height, POSITION_TOLERANCE), (flat, ANGLE_TOLERANCE)]
            sole = target.sole if target.sole is not None else model.tcp(target.tcp).sole
            feet.append((frame, np.zeros((1, 2)) if sole is None else np.asarray(sole, dtype=float)))
            if settings.slide_weight > 0:
                stay = solver.add_position_task(frame, robot.get_T_world_frame(frame)[:3, 3])
                stay.mask.set_axises("xy", "task")
                stay.configure(f"{target.tcp}_stay", "soft", settings.slide_weight)
                anchors.append((frame, stay))
        else:
            pose = np.eye(4)
            pose[:3, :3], pose[:3, 3] = rotation, target.position
            task = solver.add_frame_task(frame, pose)
            task.configure(target.tcp, "soft", settings.hand_weight, settings.hand_weight)
            checks += [(task.position(), POSITION_TOLERANCE), (task.orientation(), ANGLE_TOLERANCE)]
    return feet, anchors, checks


def placo_peer(problem: Problem, settings: PlacoSettings = DEFAULT_PLACO) -> PeerResult:
    """Solve the trial's targets with placo's KinematicsSolver from our start pose; judge by our function.

    Only ``solver.solve`` and the kinematics updates (plus refreshing the support polygon) are timed.
    """
    import placo

    if problem.reduction is not None:
        raise ValueError("placo_peer needs a problem without variable reduction")
    model = problem.model
    robot = _robot_for(model)
    robot.reset()
    theta0 = problem.start()[: model.n]
    for name, value in zip(model.joint_names, theta0, strict=True):
        robot.set_joint(name, float(value))
    robot.update_kinematics()
    solver = placo.KinematicsSolver(robot)
    solver.mask_fbase(True)
    solver.enable_joint_limits(True)
    if settings.dt > 0:
        solver.enable_velocity_limits(True)
        solver.dt = settings.dt
    feet, anchors, checks = _placo_tasks(solver, robot, problem, settings)
    com = None
    if problem.balance and feet:
        com = solver.add_com_polygon_constraint(_support_polygon(robot, feet), settings.com_margin)
        com.configure("com", "hard", 1.0)
    solver.add_regularization_task(settings.regularization)

    message, iterations, elapsed = "iteration cap", 0, 0.0
    while iterations < settings.max_iterations:
        iterations += 1
        t0 = time.perf_counter()
        try:
            if com is not None:
                com.polygon = _support_polygon(robot, feet)
            for frame, stay in anchors:
                stay.target_world = robot.get_T_world_frame(frame)[:3, 3]
            dq = solver.solve(True)
            robot.update_kinematics()
        except RuntimeError as exc:  # placo raises on an infeasible QP
            elapsed += time.perf_counter() - t0
            message = f"QP failed: {exc}"
            break
        elapsed += time.perf_counter() - t0
        if all(np.abs(task.error()).max() <= settings.stop_fraction * tol for task, tol in checks):
            message = "tasks within tolerance"
            break
        if np.abs(dq).max() < settings.stall:
            message = "stalled"
            break
    theta = np.array([robot.get_joint(name) for name in model.joint_names])
    x = np.concatenate([theta, balancing_forces(problem, theta)]) if problem.balance else theta
    converged, worst, unmet, comfort = judge(problem, x)
    return PeerResult(converged, elapsed, iterations, worst, message, unmet, comfort)
