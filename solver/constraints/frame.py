"""A TCP held to a target frame (fixed, or carried by another TCP: a loop), relaxed per axis.

Error (6 rows before relaxation), with the target frame T = (R_T, o_T) and the TCP frame (R, o)::

    position  e_p = R_T^T (o - o_T)          the TCP origin's coordinates in the target frame, m
    rotation  e_r = log(R_T^T R)             the rotation between the frames as a rotation vector in T, rad

A lock on x/y/z/rx/ry/rz keeps that component; ``lock = [z, rx, ry]`` keeps a sole flat on the floor while
it slides and turns. Any linear operator L (k x 6) may replace the lock: the error is L e.
The Jacobian is exact: d e_r = J_l^-1(e_r) R_T^T (omega - omega_ref) (inverse left Jacobian of SO(3)), and
d e_p = R_T^T (v - v_ref(o)), where v_ref(o) is the velocity of the point o carried rigidly by the reference
TCP's link (zero for a fixed target).

A problem's frame constraints are evaluated together by a :class:`FrameGroup`, itself a constraint: one pass for
all TCPs (errors) and one for all rows (Jacobian), kept in the state's cache; each pass is one compiled kernel
(:mod:`solver.kernels.frames`) when kernels are on, else batched NumPy (the reference). A frame constraint
on its own is evaluated as a group of one; grouping never changes a member, so members can be shared freely.
"""

from __future__ import annotations

import functools
import itertools
import math

import numpy as np

from .. import kernels
from ..body.model import Model, Tcp
from ..body.spatial import left_jacobian_inverse_so3, log_so3
from ..body.state import State
from ..errors import ManikinError
from ..kernels.frames import frame_errors, frame_jacobian_rows
from ..options import AXES
from .base import MET_FACTOR, Constraint

POSITION_TOLERANCE = 1e-3  # m
ROTATION_TOLERANCE = np.deg2rad(0.2)  # rad
_FIRST_THREE = np.array([True, True, True, False, False, False])  # the translation components of x y z rx ry rz


def lock_operator(lock: list[str] | tuple[str, ...]) -> np.ndarray:
    """Selection matrix (k x 6) of the locked axes, in the order x y z rx ry rz (read-only)."""
    return _selection(tuple(lock))


@functools.lru_cache(maxsize=128)  # a motion builds its targets' constraints every frame with the same locks
def _selection(lock: tuple[str, ...]) -> np.ndarray:
    unknown = [a for a in lock if a not in AXES]
    if unknown:
        raise ManikinError(f"unknown lock axis {unknown[0]!r}; expected some of {list(AXES)}")
    out = np.eye(6)[[i for i, a in enumerate(AXES) if a in lock]]
    out.setflags(write=False)
    return out


class FrameConstraint(Constraint):
    """Keep ``tcp`` on a target frame: fixed (``rotation``, ``position`` in world) or, when ``reference``
    is given, the reference TCP's frame composed with the offset (``rotation``, ``position`` in it)."""

    def __init__(
        self,
        name: str,
        tcp: Tcp,
        rotation: np.ndarray,
        position: np.ndarray,
        operator: np.ndarray,
        n_x: int,
        reference: Tcp | None = None,
        weight: float = 1.0,
        position_tolerance: float = POSITION_TOLERANCE,
        rotation_tolerance: float = ROTATION_TOLERANCE,
    ) -> None:
        self.name = name
        self.tcp = tcp
        self.target_rotation = np.asarray(rotation, dtype=float)
        self.target_position = np.asarray(position, dtype=float)
        self.operator = op = np.asarray(operator, dtype=float).reshape(-1, 6)
        self.reference = reference
        self.weight = weight
        self.n_x = n_x
        key = (op.shape[0], op.tobytes(), float(position_tolerance).hex(), float(rotation_tolerance).hex())
        self._tolerance, self._is_selection, parts = _relaxation(*key)
        self._locked_parts = [(f"{name}.{part}", components) for part, components in parts]
        self._alone: FrameGroup | None = None  # the group of one that evaluates this constraint on its own

    @property
    def rows(self) -> int:
        return self.operator.shape[0]

    def tolerance(self) -> np.ndarray:
        return self._tolerance

    def moved(self, rotation: np.ndarray, position: np.ndarray) -> FrameConstraint:
        """This constraint with another target frame (``rotation`` (3, 3), ``position`` (3,) m): a keyed target's
        next frame, without building the rest again."""
        out = _shallow_copy(self)
        out.target_rotation = np.asarray(rotation, dtype=float)
        out.target_position = np.asarray(position, dtype=float)
        out._alone = None
        return out

    @property
    def _group(self) -> FrameGroup:
        if self._alone is None:
            self._alone = FrameGroup([self])
        return self._alone

    def target_frame(self, state: State) -> tuple[np.ndarray, np.ndarray]:
        """World (rotation, position) of the target for this state."""
        return self._group.target_frames(state)[self.name]

    def full_error(self, state: State) -> np.ndarray:
        """The 6 unrelaxed components [e_p (m), e_r (rad)]."""
        return self._group.evaluate(state).full[0]

    def error(self, state: State) -> np.ndarray:
        return self._group.error(state)

    def jacobian(self, state: State) -> np.ndarray:
        return self._group.jacobian(state)

    def residuals(self, state: State) -> dict[str, float]:
        return self.residuals_of(self.full_error(state))

    def residuals_of(self, err: np.ndarray, out: dict[str, float] | None = None) -> dict[str, float]:
        """Readable residuals (m, rad) of the 6 unrelaxed error components ``err``, added to ``out`` if given."""
        out = {} if out is None else out
        if not self._is_selection:
            relaxed = self.operator @ err
            out[self.name] = math.sqrt(relaxed.dot(relaxed))
            return out
        for part, components in self._locked_parts:
            kept = err[components]
            out[part] = math.sqrt(kept.dot(kept))  # v @ v's number (matmul of two vectors calls dot), sooner
        return out


@functools.lru_cache(maxsize=256)  # a problem's targets and loops share a few operators (a study builds them a run)
def _relaxation(rows: int, operator: bytes, position_tolerance: str, rotation_tolerance: str) -> tuple:
    """Of a (rows, 6) ``operator`` (its float64 bytes) and the tolerances (m, rad; float.hex): the rows' tolerance
    (read-only), whether it selects components, and (part, the unrelaxed components it measures) of the locked
    translation / rotation."""
    op = np.frombuffer(operator, dtype=float).reshape(rows, 6)
    base_tol = np.array([float.fromhex(position_tolerance)] * 3 + [float.fromhex(rotation_tolerance)] * 3)
    tolerance = np.abs(op) @ base_tol
    tolerance.setflags(write=False)
    locked = op.sum(axis=0) > 0
    position, rotation = locked * _FIRST_THREE, locked * ~_FIRST_THREE
    # a slice when adjacent, else their indices (a slice's view has the values and order of a mask's copy)
    parts = tuple((part, _components(m)) for part, m in (("position", position), ("rotation", rotation)) if m.any())
    return tolerance, bool(np.all((op == 0) | (op == 1))), parts


def _components(mask: np.ndarray) -> slice | np.ndarray:
    """The indices where ``mask`` is set: a slice when they are adjacent (a view, no copy), else an index array."""
    index = np.flatnonzero(mask)
    return slice(int(index[0]), int(index[-1]) + 1) if index[-1] - index[0] + 1 == len(index) else index


def _shallow_copy(obj: object) -> object:
    """``copy.copy(obj)`` of a plain object (a constraint: a __dict__, no __copy__ or __slots__) without the reduce
    protocol: a motion moves its targets' constraints every frame."""
    twin = object.__new__(type(obj))
    twin.__dict__.update(obj.__dict__)
    return twin


class _FrameValues:
    """One state's evaluation of a group: world target frames (C, 3, 3) and (C, 3) m, TCP positions (C, 3) m,
    the unrelaxed errors (C, 6) and the relaxed rows of all members stacked (R,); ``packed``: the compiled kernels'
    (C, 9) [position, full] and (C, 3, 4) [target rotation | position], of which the fields are views."""

    __slots__ = ("target_rotation", "target_position", "position", "full", "errors", "jacobian", "packed")

    def __init__(self, target_rotation, target_position, position, full, errors, packed=None) -> None:
        self.target_rotation = target_rotation
        self.target_position = target_position
        self.position = position
        self.full = full
        self.errors = errors
        self.jacobian: np.ndarray | None = None
        self.packed: tuple[np.ndarray, np.ndarray] | None = packed

    @classmethod
    def of_packed(cls, values: np.ndarray, target: np.ndarray, errors: np.ndarray) -> _FrameValues:
        """The evaluation from the kernel's packed arrays (the fields are views of them)."""
        packed = (values, target)
        return cls(target[:, :, :3], target[:, :, 3], values[:, :3], values[:, 3:], errors, packed)

    def packed_arrays(self) -> tuple[np.ndarray, np.ndarray]:
        """(values (C, 9), target (C, 3, 4)) as :func:`~solver.kernels.frames.frame_errors` fills them."""
        if self.packed is None:
            values = np.concatenate([self.position, self.full], axis=1)
            target = np.concatenate([self.target_rotation, self.target_position[:, :, None]], axis=2)
            self.packed = (values, target)
        return self.packed


class FrameGroup(Constraint):
    """Frame constraints evaluated together as one constraint: their rows stacked in member order, each
    member's residuals and unmet status reported under its own name."""

    name = "frames"

    def __init__(self, members: list[FrameConstraint]) -> None:
        self.members = list(members)
        sizes = [c.rows for c in self.members]
        offsets = list(itertools.accumulate(sizes, initial=0))
        self.member_rows = [slice(a, b) for a, b in zip(offsets[:-1], offsets[1:], strict=True)]
        self._tolerance = np.concatenate([c.tolerance() for c in self.members]) if self.members else np.zeros(0)
        self._met_bound = self._tolerance * MET_FACTOR  # Constraint.met_rows's, once
        weights = np.array([c.weight for c in self.members])  # each member's weight on each of its rows
        self._row_weight = np.repeat(weights, sizes) if sizes else np.zeros(0)
        self.n_x = self.members[0].n_x if self.members else 0
        self.link = np.array([c.tcp.link for c in self.members], dtype=int)
        self.tcp_rotation = np.array([c.tcp.rotation for c in self.members]).reshape(-1, 3, 3)
        self.tcp_position = np.array([c.tcp.position for c in self.members]).reshape(-1, 3)
        self.target_rotation = np.array([c.target_rotation for c in self.members]).reshape(-1, 3, 3)
        self.target_position = np.array([c.target_position for c in self.members]).reshape(-1, 3)
        self.loops = np.array([i for i, c in enumerate(self.members) if c.reference is not None], dtype=int)
        self.reference_link = np.array([self.members[i].reference.link for i in self.loops], dtype=int)
        self.reference_rotation = np.array([self.members[i].reference.rotation for i in self.loops]).reshape(-1, 3, 3)
        self.reference_position = np.array([self.members[i].reference.position for i in self.loops]).reshape(-1, 3)
        # per stacked row: its member, its operator row, and the joints that move it (minus the reference's)
        self.row_member = np.repeat(np.arange(len(self.members)), sizes)
        self.operator = np.concatenate([c.operator for c in self.members]) if self.members else np.zeros((0, 6))
        self.operator_lin = self.operator[:, None, :3]  # (R, 1, 3)
        self.operator_ang = self.operator[:, None, 3:]
        self._compiled_tables: tuple | None = None  # the kernels' constant arrays, built on first use
        # what depends on the TCPs, operators and model alone, built on first use and shared with the moved copies
        # (a motion moves the first frame's group every frame): the row mask, the moving joints, the kernels' tables
        self._shared: dict = {}

    @property
    def rows(self) -> int:
        return len(self._tolerance)

    def tolerance(self) -> np.ndarray:
        return self._tolerance

    def row_weight(self) -> np.ndarray:
        return self._row_weight

    def moved(self, members: list[FrameConstraint]) -> FrameGroup:
        """This group with ``members``: the same constraints in the same order but for their target frames
        (:meth:`FrameConstraint.moved`). What depends on the TCPs, operators and the model is shared."""
        group = _shallow_copy(self)
        group.members = list(members)
        if members:  # joined: np.array of the list without its look at each item's nesting (the same numbers)
            group.target_rotation = np.concatenate([c.target_rotation for c in members], dtype=float).reshape(-1, 3, 3)
            group.target_position = np.concatenate([c.target_position for c in members], dtype=float).reshape(-1, 3)
        else:
            group.target_rotation, group.target_position = np.zeros((0, 3, 3)), np.zeros((0, 3))
        group._compiled_tables = None  # made from the shared ones with these targets
        return group

    def error(self, state: State) -> np.ndarray:
        return self.evaluate(state).errors

    def residuals(self, state: State) -> dict[str, float]:
        full = self.evaluate(state).full
        out: dict[str, float] = {}
        for i, c in enumerate(self.members):
            c.residuals_of(full[i], out)
        return out

    def met_rows(self, state: State) -> np.ndarray:
        return np.abs(self.evaluate(state).errors) <= self._met_bound

    def unmet(self, state: State) -> list[str]:
        met = self.met_rows(state)
        if met.all():  # the usual answer: no test per member
            return []
        return [c.name for c, rows in zip(self.members, self.member_rows, strict=True) if not met[rows].all()]

    def target_frames(self, state: State) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        """Each member's world target frame (rotation (3, 3), position (3,) m) at ``state``."""
        values = self.evaluate(state)
        return {c.name: (values.target_rotation[i], values.target_position[i]) for i, c in enumerate(self.members)}

    def _mask(self, model: Model) -> np.ndarray:
        """(R, n): 1 where a joint moves a row's TCP, minus 1 where it moves the reference TCP (loops)."""
        mask = self._shared.get("row mask")
        if mask is None:
            desc = model.descendant.astype(float)
            mask = desc[:, self.link[self.row_member]].T
            for c, rows in zip(self.members, self.member_rows, strict=True):
                if c.reference is not None:
                    mask[rows] -= desc[:, c.reference.link]
            self._shared["row mask"] = mask
        return mask

    def evaluate(self, state: State) -> _FrameValues:
        """All members' errors at ``state``, computed once per state."""
        values = state.cache.get(self)
        if values is not None:
            return values
        kin = state.kin
        if kernels.active():
            values = state.cache[self] = self._evaluate_compiled(kin)
            return values
        link_rot = kin.rotation[self.link]
        rot = link_rot @ self.tcp_rotation
        pos = kin.position[self.link] + (link_rot @ self.tcp_position[:, :, None])[:, :, 0]
        r_t, o_t = self.target_rotation, self.target_position
        if len(self.loops):
            r_t, o_t = r_t.copy(), o_t.copy()
            ref_rot = kin.rotation[self.reference_link]
            r_ref = ref_rot @ self.reference_rotation
            p_ref = kin.position[self.reference_link] + (ref_rot @ self.reference_position[:, :, None])[:, :, 0]
            r_t[self.loops] = r_ref @ self.target_rotation[self.loops]
            o_t[self.loops] = p_ref + (r_ref @ self.target_position[self.loops][:, :, None])[:, :, 0]
        r_t_inv = r_t.transpose(0, 2, 1)
        full = np.empty((len(self.members), 6))
        full[:, :3] = (r_t_inv @ (pos - o_t)[:, :, None])[:, :, 0]
        relative = r_t_inv @ rot
        for i in range(len(self.members)):
            full[i, 3:] = log_so3(relative[i])
        errors = (self.operator * full[self.row_member]).sum(axis=1)
        values = state.cache[self] = _FrameValues(r_t, o_t, pos, full, errors)
        return values

    def jacobian(self, state: State) -> np.ndarray:
        """(R, n_x): the stacked rows' d error / d x at ``state``, computed once per state."""
        values = self.evaluate(state)
        if values.jacobian is not None:
            return values.jacobian
        kin = state.kin
        if kernels.active():
            out = np.zeros((len(self.row_member), self.n_x))
            frame_jacobian_rows(
                *values.packed_arrays(), *self._tables()[2:], kin.twist, *self._moving_joints(kin.model), out
            )
            values.jacobian = out
            return out
        r_t_inv = values.target_rotation.transpose(0, 2, 1)
        # rows of the rotation part: L_ang J_l^-1(e_r) R_T^T; of the position part: L_lin R_T^T
        ang_map = np.array([left_jacobian_inverse_so3(e) for e in values.full[:, 3:]]) @ r_t_inv
        member = self.row_member
        rows_lin = (self.operator_lin @ r_t_inv[member])[:, 0, :]
        rows_ang = (self.operator_ang @ ang_map[member])[:, 0, :]
        out = np.zeros((len(member), self.n_x))
        out[:, : kin.model.n] = kin.jacobian_rows(values.position[member], rows_lin, rows_ang, self._mask(kin.model))
        values.jacobian = out
        return out

    def _tables(self) -> tuple:
        """The kernels' constants: links (C, 2) (TCP, reference TCP or -1), local frames (C, 3, 3, 4) [R | p] of the
        TCP, the target and the reference TCP, the operator rows (R, 6) and each row's member (R,)."""
        if self._compiled_tables is None:
            shared = self._shared.get("tables")
            if shared is None:  # all but the targets
                count = len(self.members)
                links = np.full((count, 2), -1, dtype=np.int64)
                links[:, 0] = self.link
                links[self.loops, 1] = self.reference_link
                local = np.zeros((count, 3, 3, 4))
                local[:, 2, :, :3] = np.eye(3)
                local[:, 0, :, :3], local[:, 0, :, 3] = self.tcp_rotation, self.tcp_position
                local[self.loops, 2, :, :3] = self.reference_rotation
                local[self.loops, 2, :, 3] = self.reference_position
                operator = np.ascontiguousarray(self.operator, dtype=float)
                shared = self._shared["tables"] = (links, local, operator, self.row_member.astype(np.int64))
            links, local, operator, row_member = shared
            local = local.copy()
            local[:, 1, :, :3], local[:, 1, :, 3] = self.target_rotation, self.target_position
            self._compiled_tables = (links, local, operator, row_member)
        return self._compiled_tables

    def _moving_joints(self, model: Model) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Per member, the joints that move its TCP (sign 1) or only its reference TCP (sign -1): its rows' nonzeros in
        :meth:`_mask` (none for a member without rows), as (joint_start (C + 1,), joint, sign)."""
        moving = self._shared.get("moving")
        if moving is None:
            first = np.array([rows.start if rows.stop > rows.start else -1 for rows in self.member_rows], dtype=int)
            per_member = self._mask(model)[np.maximum(first, 0)] * (first >= 0)[:, None]  # (C, n)
            member, joint = np.nonzero(per_member)
            start = np.searchsorted(member, np.arange(len(first) + 1)).astype(np.int64)
            joint, sign = joint.astype(np.int64), per_member[member, joint]
            moving = self._shared["moving"] = (start, joint, sign)
        return moving

    def _evaluate_compiled(self, kin) -> _FrameValues:
        """:meth:`evaluate` by the compiled kernel."""
        count = len(self.members)
        values, target, errors = np.empty((count, 9)), np.empty((count, 3, 4)), np.empty(len(self.row_member))
        rotation, position = np.ascontiguousarray(kin.rotation), np.ascontiguousarray(kin.position)
        frame_errors(rotation, position, *self._tables(), target, values, errors)
        return _FrameValues.of_packed(values, target, errors)
