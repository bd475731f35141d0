"""The quasi-Newton memory of the comfort step: a limited-memory BFGS model and its Newton step in a null space."""

from __future__ import annotations

import math

import numpy as np

from . import lapack


class CurvatureMemory:
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
