"""A TCP held to a target frame (fixed, or carried by another TCP: a loop), relaxed per axis.

Error (6 rows before relaxation), with the target frame T = (R_T, o_T) and the TCP frame (R, o):
    position  e_p = R_T^T (o - o_T)          the TCP origin's coordinates in the target frame, m
    rotation  e_r = log(R_T^T R)             the rotation between the frames as a rotation vector in T, rad
A lock on x/y/z/rx/ry/rz keeps that component; ``lock = [z, rx, ry]`` keeps a sole flat on the floor while
it slides and turns. Any linear operator L (k x 6) may replace the lock: the error is L e.
The Jacobian is exact: d e_r = J_l^-1(e_r) R_T^T (omega - omega_ref) (inverse left Jacobian of SO(3)), and
d e_p = R_T^T (v - v_ref(o)), where v_ref(o) is the velocity of the point o carried rigidly by the reference
TCP's link (zero for a fixed target).
"""

from __future__ import annotations

import numpy as np

from ..errors import ManikinError
from ..model import Tcp
from ..spatial import left_jacobian_inverse_so3, log_so3
from ..state import State
from .base import Constraint

AXES = ("x", "y", "z", "rx", "ry", "rz")
POSITION_TOLERANCE = 1e-3  # m
ROTATION_TOLERANCE = np.deg2rad(0.2)  # rad


def lock_operator(lock: list[str] | tuple[str, ...]) -> np.ndarray:
    """Selection matrix (k x 6) of the locked axes, in the order x y z rx ry rz."""
    unknown = [a for a in lock if a not in AXES]
    if unknown:
        raise ManikinError(f"unknown lock axis {unknown[0]!r}; expected some of {list(AXES)}")
    return np.eye(6)[[i for i, a in enumerate(AXES) if a in lock]]


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
        self.operator = np.asarray(operator, dtype=float).reshape(-1, 6)
        self.reference = reference
        self.weight = weight
        self.n_x = n_x
        base_tol = np.array([position_tolerance] * 3 + [rotation_tolerance] * 3)
        self._tolerance = np.abs(self.operator) @ base_tol
        self._is_selection = bool(np.all((self.operator == 0) | (self.operator == 1)))
        # a fixed target's linear Jacobian rows do not depend on the state
        self._fixed_rows_lin = None if reference is not None else self.operator[:, :3] @ self.target_rotation.T

    @property
    def rows(self) -> int:
        return self.operator.shape[0]

    def tolerance(self) -> np.ndarray:
        return self._tolerance

    def target_frame(self, state: State) -> tuple[np.ndarray, np.ndarray]:
        """World (rotation, position) of the target for this state."""
        if self.reference is None:
            return self.target_rotation, self.target_position
        r_ref, p_ref = state.kin.tcp_frame(self.reference)
        return r_ref @ self.target_rotation, p_ref + r_ref @ self.target_position

    def _evaluate(self, state: State) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(target rotation, TCP position m, the 6 unrelaxed components), computed once per state."""
        cached = state.constraint_cache.get(self)
        if cached is None:
            r_t, o_t = self.target_frame(state)
            r, o = state.kin.tcp_frame(self.tcp)
            cached = (r_t, o, np.concatenate([r_t.T @ (o - o_t), log_so3(r_t.T @ r)]))
            state.constraint_cache[self] = cached
        return cached

    def full_error(self, state: State) -> np.ndarray:
        """The 6 unrelaxed components [e_p (m), e_r (rad)]."""
        return self._evaluate(state)[2]

    def error(self, state: State) -> np.ndarray:
        return self.operator @ self.full_error(state)

    def jacobian(self, state: State) -> np.ndarray:
        kin = state.kin
        r_t, o, full_error = self._evaluate(state)
        op = self.operator
        rows_lin = op[:, :3] @ r_t.T if self._fixed_rows_lin is None else self._fixed_rows_lin
        rows_ang = op[:, 3:] @ (left_jacobian_inverse_so3(full_error[3:]) @ r_t.T)
        full = np.zeros((self.rows, self.n_x))
        n = kin.model.n
        full[:, :n] = kin.jacobian_rows(self.tcp.link, o, rows_lin, rows_ang)
        if self.reference is not None:
            full[:, :n] -= kin.jacobian_rows(self.reference.link, o, rows_lin, rows_ang)
        return full

    def residuals(self, state: State) -> dict[str, float]:
        err = self.full_error(state)
        if not self._is_selection:
            return {self.name: float(np.linalg.norm(self.operator @ err))}
        locked = self.operator.sum(axis=0) > 0
        out = {}
        if locked[:3].any():
            out[f"{self.name}.position"] = float(np.linalg.norm(err[:3][locked[:3]]))
        if locked[3:].any():
            out[f"{self.name}.rotation"] = float(np.linalg.norm(err[3:][locked[3:]]))
        return out
