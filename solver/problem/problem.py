"""A pose problem: targets, loops, loads, supports and comfort for one model, and its variable vector.

x = [theta (n joints, rad or m), w (contact edge weights, N)]. The solver works in scaled variables
y = x / scale (forces divided by body weight) on rows divided by their tolerance, so that meters, radians and
newtons compare and "converged" means max |scaled error| <= 1.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence

import numpy as np

from .. import kernels
from ..body.model import GRAVITY, Model
from ..body.state import State
from ..collision.body import capsules_of
from ..comfort import Comfort
from ..constraints import BalanceConstraint, Constraint, FrameConstraint, FrameGroup, lock_operator
from ..constraints.carried_clearance import CarriedClearance
from ..constraints.carried_obstacles import CarriedObstacles
from ..constraints.clearance import FLOOR, Clearance, Closeness, floor_clearance
from ..constraints.inequality import Inequality
from ..constraints.self_clearance import self_clearance
from ..errors import ManikinError
from ..kernels.reduction import comfort_model
from ..kernels.trial import linear_phi, scale_rows
from . import reports, stacked
from .bounds import Bounds
from .parts import standard_comfort, statics_of, variables_of, zero_kinematics
from .specs import (
    ExternalLoad,
    Loop,
    ProblemSpec,
    Target,
    same_but_frames,
    same_frame,
    same_supports,
    validate,
    validate_frames,
)
from .starts import behaviour_start

__all__ = ["ExternalLoad", "Loop", "Problem", "ProblemSpec", "Target"]


class Problem:
    """Everything the solver needs, assembled from plain specifications."""

    def __init__(self, model: Model, spec: ProblemSpec | Sequence[Target] | None = None, *fields, **named) -> None:
        """The problem ``spec`` (:class:`~solver.problem.specs.ProblemSpec`) poses for ``model``. The spec's fields
        may be given instead, as arguments in its order or by name (``Problem(model, targets, balance=False)``: scripts
        written before the spec)."""
        if spec is None or not isinstance(spec, ProblemSpec):
            spec = ProblemSpec(*(() if spec is None else (spec,)), *fields, **named)
        elif fields or named:
            raise TypeError("Problem(model, spec) takes no more arguments: put them in the spec (spec.replace(...))")
        self.spec = spec
        validate(model, spec.targets, spec.loops, spec.loads)
        self.model = model
        self.all_targets = list(spec.targets)
        self.targets = [t for t in spec.targets if t.enabled]
        self.loops = list(spec.loops)
        self.load_specs = list(spec.loads)
        self.balance = balance = spec.balance
        zero = self._zero_kin = zero_kinematics(model)
        held = [t for t in self.targets if t.support] if balance else []
        if balance and not held:
            raise ManikinError("balance needs at least one support target (support = true)")
        self.contacts, self.layout = statics_of(model, held, spec.loads, lambda t: self._rotation_of(t, zero))
        self.loads = list(self.layout.loads)
        n, n_w = model.n, self.contacts.n_vars
        self.n_x = n + n_w
        self.loop_constraints = [self._loop_constraint(lp) for lp in self.loops]
        self.balance_constraint = BalanceConstraint(self.n_x) if balance else None
        self.floor = floor = spec.floor
        self.floor_constraint = floor_clearance(model, self.targets, self.n_x) if floor else None
        self.obstacles = list(spec.obstacles)
        self.obstacle_constraint = Clearance(model, capsules_of(model), self.obstacles, self.n_x) if self.obstacles \
            else None  # fmt: skip
        self.self_collision = spec.self_collision
        self.self_constraint = self_clearance(model, self.n_x) if spec.self_collision else None
        if self.self_constraint is not None and not self.self_constraint.rows:
            self.self_constraint = None  # a body without the named parts (the snake)
        self.carried = carried = spec.carried
        self.carried_constraint = None if carried is None else CarriedClearance(model, capsules_of(model), carried,
                                                                                self.n_x)  # fmt: skip
        around = [*self.obstacles, FLOOR] if floor else self.obstacles
        self.carried_obstacle_constraint = CarriedObstacles(model, carried, around, self.n_x) \
            if carried is not None and around else None  # fmt: skip
        self.extra_constraints = list(spec.extra_constraints)
        self._set_constraints([self._target_constraint(t, zero) for t in self.targets])
        comfort = spec.comfort if spec.comfort is not None else standard_comfort(model, spec.comfort_weights)
        self.comfort = comfort.with_targets(self.targets)  # a term that reads the targets (gaze) aimed at them
        self.body_weight = model.total_mass * float(np.linalg.norm(GRAVITY))
        self.reduction_groups = spec.reduction
        # The solver's variables v: x itself, or beta with x = phi(beta) when reduced.
        self.x_bounds, self.reduction, self.bounds = variables_of(model, n_w, self.body_weight, spec.reduction)
        self.n_var = len(self.bounds)

    def with_targets(self, targets: list[Target]) -> Problem:
        """The same problem (loops, loads, balance, comfort) with other targets.

        When the supports are the same (a motion moving its hands), everything but the target constraints is
        shared with this problem instead of being built again.
        """
        targets = list(targets)
        if self.balance and not same_supports(self.targets, targets):  # built again, with this problem's comfort terms
            return Problem(self.model, self.spec.replace(targets=targets, comfort=self.comfort))
        moved = self._twin()
        moved.spec = self.spec.replace(targets=targets)
        moved.all_targets = targets
        moved.targets = [t for t in targets if t.enabled]
        same = len(targets) == len(self.all_targets) and all(map(same_but_frames, self.all_targets, targets))
        if same and self.frames is not None and len(self.target_constraints) == len(moved.targets):
            kept = list(map(same_frame, targets, self.all_targets))  # each target at its frame before, or moved
            validate_frames([t for t, k in zip(targets, kept, strict=True) if not k])  # the moved ones (next frame)
            kept = [k for t, k in zip(targets, kept, strict=True) if t.enabled]  # moved.targets' (enabled alike)
            pairs = zip(self.target_constraints, moved.targets, kept, strict=True)  # unmoved: kept as it is
            members = [c if k else c.moved(t.rotation if t.rotation is not None else c.target_rotation, t.position)
                       for c, t, k in pairs]  # fmt: skip
            moved.target_constraints = members
            moved.frames = self.frames.moved([*members, *self.loop_constraints])
            moved.constraints = [moved.frames if c is self.frames else c for c in self.constraints]
        else:
            validate(self.model, targets, (), ())
            moved._set_constraints([self._target_constraint(t, self._zero_kin) for t in moved.targets])
        moved.comfort = self.comfort.with_targets(moved.targets)
        return moved

    def with_frames(self, targets: list[FrameConstraint], comfort: Comfort) -> Problem:
        """The same problem with only ``targets`` (some of this one's target constraints) and another comfort."""
        ranked = self._twin()
        ranked.spec = self.spec.replace(comfort=comfort)
        ranked.comfort = comfort
        ranked._set_constraints(targets)
        return ranked

    def with_bounds(self, bounds: Bounds) -> Problem:
        """The same problem with other bounds on its solver variables (e.g. narrowed around the previous frame)."""
        narrowed = self._twin()
        narrowed.bounds = bounds
        return narrowed

    def _twin(self) -> Problem:
        """A shallow copy: copy.copy(self) without its reduce protocol (a motion makes two a frame)."""
        twin = object.__new__(type(self))
        twin.__dict__.update(self.__dict__)
        return twin

    @property
    def scale(self) -> np.ndarray:
        """Scaled-variable unit of each solver variable (see :class:`Bounds`)."""
        return self.bounds.scale

    def _target_constraint(self, t: Target, zero_pose_kin) -> FrameConstraint:
        op = t.operator if t.operator is not None else lock_operator(t.lock)
        rot = self._rotation_of(t, zero_pose_kin)
        return FrameConstraint(t.tcp, self.model.tcp(t.tcp), rot, t.position, op, self.n_x, weight=t.weight)

    def _loop_constraint(self, lp: Loop) -> FrameConstraint:
        op = lp.operator if lp.operator is not None else lock_operator(lp.lock)
        rot = np.eye(3) if lp.offset_rotation is None else lp.offset_rotation
        tcp, other = self.model.tcp(lp.tcp), self.model.tcp(lp.other)
        name = f"loop {lp.tcp}-{lp.other}"
        return FrameConstraint(name, tcp, rot, lp.offset_position, op, self.n_x, reference=other, weight=lp.weight)

    def _set_constraints(self, target_constraints: list[FrameConstraint]) -> None:
        """The stacked constraints: targets and loops as one frame group, balance, the extra constraints; and the
        row scaling."""
        self.target_constraints = list(target_constraints)
        frames = [*target_constraints, *self.loop_constraints]
        self.frames = FrameGroup(frames) if frames else None
        rows = [self.frames, self.balance_constraint, self.floor_constraint, self.obstacle_constraint,
                self.self_constraint, self.carried_constraint, self.carried_obstacle_constraint]  # fmt: skip
        rows += self.extra_constraints
        rows = [c for c in rows if c is not None]
        self.constraints: list[Constraint] = rows
        self._sizes = sizes = [c.rows for c in rows]
        self.row_tolerance = np.concatenate([c.tolerance() for c in rows]) if rows else np.zeros(0)
        # per row: a one-sided constraint's (an Inequality: met rows have zero error, contact rows are held by the step)
        one_sided = [isinstance(c, Inequality) for c in rows]
        self.one_sided = np.repeat(np.array(one_sided, dtype=bool), sizes)
        self.row_weight = np.concatenate([c.row_weight() for c in rows]) if rows else np.zeros(0)
        # per row: an obstacle's clearance (the scene's, not the floor's or the body's own: docs/TUNING.md)
        scene = (self.obstacle_constraint, self.carried_obstacle_constraint)
        obstacles = [any(c is o for o in scene) for c in rows]
        self.obstacle_rows = np.repeat(np.array(obstacles, dtype=bool), sizes)
        self.any_obstacle_rows = any(o and k for o, k in zip(obstacles, sizes, strict=True))
        self.n_rows = len(self.row_tolerance)
        offsets = list(itertools.accumulate(sizes[:-1], initial=0)) if rows else []
        self._row_offsets = np.array(offsets, dtype=int)
        self._row_scale = (self.row_weight / self.row_tolerance)[:, None]  # (rows, 1) of the scaled Jacobian
        # per one-sided constraint (an Inequality): its index and its rows, for scaled_slack (kinds fixed per problem)
        self._one_sided_at = [
            (i, slice(o, o + k)) for i, (side, o, k) in enumerate(zip(one_sided, offsets, sizes, strict=True)) if side
        ]
        # live_jacobian's rows when all may be nonzero, shared (nothing writes to it; read-only would mean new kernels)
        self._all_rows = np.arange(self.n_rows)

    def target_frames(self, state: State) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        """World (rotation (3, 3), position (3,) m) of every target and loop frame at ``state``, by name."""
        return self.frames.target_frames(state) if self.frames is not None else {}

    @staticmethod
    def _rotation_of(target: Target, zero_pose_kin) -> np.ndarray:
        if target.rotation is not None:
            return np.asarray(target.rotation, dtype=float)
        return zero_pose_kin.tcp_frame(zero_pose_kin.model.tcp(target.tcp))[0]

    def variable_names(self) -> list[str]:
        """Names of the solver variables: joints (or reduction groups) then contact force weights."""
        if self.reduction is not None:
            return list(self.reduction.names)
        return list(self.model.joint_names) + [f"force_{k}" for k in range(self.contacts.n_vars)]

    def to_x(self, v: np.ndarray) -> np.ndarray:
        """Full x = [joints, forces] of solver variables v."""
        return v if self.reduction is None else self.reduction.phi(v)

    def to_variables(self, x: np.ndarray) -> np.ndarray:
        """Solver variables closest to a full x."""
        return x if self.reduction is None else self.reduction.from_x(x)

    def state(self, v: np.ndarray) -> State:
        """Evaluation point for solver variables v (kept on the state when dphi/dbeta depends on them)."""
        red = self.reduction
        if red is not None and red.linear and kernels.active():  # phi in one loop (solver.kernels.trial.linear_phi)
            x = np.empty(len(red.offset))
            linear_phi(np.asarray(v, dtype=float), red.offset, *red.kernel_supports, x)
            return self.state_of_x(x)
        state = self.state_of_x(self.to_x(v))
        if self.reduction is not None and not self.reduction.linear:
            state.variables = np.array(v, dtype=float)
        return state

    def reduction_jacobian(self, state: State) -> np.ndarray:
        """dphi/dbeta (n_x, n_var) at ``state``; cached on a state of a nonlinear reduction."""
        red = self.reduction
        if red.linear:
            return red.basis
        if state.reduction_jacobian is None:
            v = state.variables
            state.reduction_jacobian = red.jacobian(red.from_x(state.x) if v is None else v)
        return state.reduction_jacobian

    def joint_change(self, state: State, dv: np.ndarray) -> np.ndarray:
        """(n,) change of every model joint (rad or m), to first order, for a change ``dv`` of the solver variables."""
        red = self.reduction
        if red is None:
            dx = dv
        else:
            dx = red.basis_times(dv) if red.linear else self.reduction_jacobian(state) @ dv
        return dx[: self.model.n]

    def joint_supports(self) -> tuple[np.ndarray, np.ndarray] | None:
        """Per model joint, (the solver variable that moves it, -1 for none; its weight), contiguous int64 and float64
        (n,) for the kernels; None when the reduction is nonlinear. Once per reduction (a copied problem shares it)."""
        red, kept, n = self.reduction, self.__dict__.get("_joint_supports"), self.model.n
        if red is not None and not red.linear:
            return None
        if kept is None or kept[0] is not red:
            column, weight = (np.arange(n), np.ones(n)) if red is None else (a[:n] for a in red.kernel_supports)
            kept = self._joint_supports = (red, (np.ascontiguousarray(column, np.int64), np.ascontiguousarray(weight)))
        return kept[1]

    def state_of_x(self, x: np.ndarray) -> State:
        """Evaluation point for a full x = [joints, forces]."""
        return State(x, self.model.n, self.layout)

    def start(self, x0: np.ndarray | None = None) -> np.ndarray:
        """Valid starting solver variables from ``x0`` (joint values alone, or joints + forces), in bounds.

        Missing or mismatched force values are replaced by an even share of body weight plus loads. With the
        behaviour model on, the zero pose becomes a crouch when a reach target is low (:mod:`.starts`).
        """
        n = self.model.n
        x0 = self.model.zero_pose() if x0 is None else np.asarray(x0, dtype=float)
        # the ufuncs' reductions: ndarray.all and .any without their Python wrappers (a motion starts every frame)
        if x0.shape[0] not in (n, self.n_x) or not np.logical_and.reduce(np.isfinite(x0), axis=None):
            raise ManikinError(f"start pose must be {n} finite joint values (or {self.n_x} with forces)")
        theta = x0[:n]
        x = x0 if x0.shape[0] == self.n_x else None  # joints and forces (none without supports): clipped as given
        if not np.logical_or.reduce(theta, axis=None):  # the zero pose, the default start: perhaps a crouch
            crouch = behaviour_start(self)
            theta, x = (theta, x) if crouch is None else (crouch, None)
        if x is None:
            if x0.shape[0] == self.n_x and self.contacts.n_vars:
                w = x0[n:]
            else:
                down = self.body_weight - sum(float(ld.force[2]) for ld in self.loads)
                w = self.contacts.even_weights(down)
            x = np.concatenate([theta, w])
        return self.bounds.clip(self.to_variables(self.x_bounds.clip(x)))

    def scaled_error(self, state: State) -> np.ndarray:
        """All constraint rows divided by their tolerance and multiplied by their weight."""
        if not self.constraints:
            return np.zeros(0)
        e = np.concatenate([c.error(state) for c in self.constraints])
        e *= self.row_weight  # in place on the fresh array: e * weight / tolerance, the same rounding
        e /= self.row_tolerance
        return e

    def scaled_error_and_worst(self, state: State, unweight: np.ndarray) -> tuple[np.ndarray, float]:
        """(:meth:`scaled_error`, its largest ``|row| * unweight``: 0 without rows), in one loop where the kernels
        run (every trial point of a solve asks for both)."""
        if not self.constraints:
            return np.zeros(0), 0.0
        if kernels.active():
            err = np.concatenate([c.error(state) for c in self.constraints])
            return err, scale_rows(err, self.row_weight, self.row_tolerance, unweight)
        err = self.scaled_error(state)
        return err, float(np.maximum.reduce(np.abs(err) * unweight, initial=0.0))

    def scaled_slack(self, state: State) -> np.ndarray:
        """Per row, how far a met one-sided row is from its floor, scaled as :meth:`scaled_error` (0 elsewhere); once
        per state (the step and the line search ask at the same point; not to be written to)."""
        return stacked.scaled_slack(self, state)

    def scaled_jacobian(self, state: State) -> np.ndarray:
        """d scaled_error / d (v / scale)."""
        live, jac = self.live_jacobian(state)
        out = np.zeros((self.n_rows, self.n_var))
        out[live] = jac
        return out

    def live_jacobian(self, state: State) -> tuple[np.ndarray, np.ndarray]:
        """(the rows that may be nonzero, their rows of :meth:`scaled_jacobian`): met one-sided rows beyond their
        watch band (most clearance rows, far from anything) are left out instead of carried as zeros."""
        return stacked.live_jacobian(self, state)

    def comfort_derivatives(self, state: State) -> tuple[np.ndarray, np.ndarray]:
        """d h / d v and the diagonal curvature model of -h in the solver variables v."""
        grad, curv = self.comfort.derivatives(state)
        if self.reduction is None:
            return grad, curv
        red = self.reduction
        if red.linear:
            return red.times_basis(grad), red.times_basis(curv, squared=True)
        dphi = self.reduction_jacobian(state)
        return dphi.T @ grad, (dphi * dphi).T @ curv

    def comfort_model(self, state: State) -> tuple[np.ndarray, np.ndarray]:
        """(grad f, curv f) of f = -h in the scaled variables v / scale: ``-grad_h * scale`` and ``curv * scale**2``
        of :meth:`comfort_derivatives`, the basis product and the scaling in one loop where the kernels run."""
        red = self.reduction
        if red is not None and red.linear and kernels.active():
            rows, _, weight, starts, complete = red._supports  # the basis by column, built once
            if complete:
                grad, curv = self.comfort.derivatives(state)
                grad_f, curv_f = np.empty(self.n_var), np.empty(self.n_var)
                comfort_model(grad, curv, rows, weight, starts, self.scale, grad_f, curv_f)
                return grad_f, curv_f
        grad_h, curv = self.comfort_derivatives(state)
        return -grad_h * self.scale, curv * self.scale**2

    def comfort_rows(self, state: State) -> np.ndarray | None:
        """Low-rank curvature rows of -h (k, n_var) in the solver variables v, None when comfort has none."""
        rows = self.comfort.curvature_rows(state)
        if rows is None or self.reduction is None:
            return rows
        red = self.reduction
        return red.times_basis(rows) if red.linear else rows @ self.reduction_jacobian(state)

    def report(self, state: State) -> reports.Report:
        """(:meth:`unmet`, :meth:`residuals`, :meth:`closest`) at ``state``, in one pass (what a result reports)."""
        return reports.report(self.constraints, state)

    def closest(self, state: State) -> list[Closeness]:
        """The clearance rows within their margin (the floor's, the obstacles', the body's own, the carried box's and
        any extra :class:`~solver.constraints.clearance.Clearance`), nearest first (:mod:`.reports`)."""
        return reports.closest(self.constraints, state)

    def residuals(self, state: State) -> dict[str, float]:
        return reports.residuals(self.constraints, state)

    def unmet(self, state: State) -> list[str]:
        """Names of the constraints (targets, loops, balance) with some row outside its tolerance."""
        return reports.unmet(self.constraints, state)
