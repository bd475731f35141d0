"""Damped least squares on one scaled Jacobian: the task step, its trust region, the row-space basis, multipliers."""

from __future__ import annotations

import math

import numpy as np

from . import lapack


class LeastSquares:
    """Damped least squares on one Jacobian J (m x n): steps, row-space basis, multipliers.

    Everything comes from G = J J^T (m is ~24, n ~100..190). Steps and multipliers use (G + d^2 I)^-1 with a
    Tikhonov damping d = ``max_damping`` * s_max (s_max^2 estimated by ||G||_F, at most sqrt(m) times larger), which
    only changes singular values within ~10 d of it: the damped least squares of Nakamura & Hanafusa near
    singularities, negligible elsewhere. The row-space basis for the null-space projection is L^-1 J, G = L L^T,
    undamped. A trust region adds Levenberg-Marquardt damping found by Newton's method on the secular equation
    (Moré & Sorensen), each trial one Cholesky of an m x m matrix. When G is numerically singular (or too
    ill-conditioned for Cholesky to be trusted) its eigendecomposition stands in for the factors.
    """

    def __init__(
        self,
        jac: np.ndarray,
        max_damping: float,
        rows: np.ndarray | None = None,
        total: int | None = None,
        used: np.ndarray | None = None,
    ) -> None:
        """``jac`` holds rows ``rows`` (indices) of a Jacobian of ``total`` rows, the others zero (default: all
        rows); errors passed in and multipliers given back have all ``total`` rows. ``used``: the rows of ``jac``
        with an entry, when the caller knows them already."""
        self._rows = jac.shape[0] if total is None else total
        rows = np.arange(jac.shape[0]) if rows is None else np.asarray(rows)
        # rows without any entry (a one-sided constraint while it is met) take no part: kept, they would make G
        # singular and send every step down the eigendecomposition path
        if used is None:
            used = jac.any(axis=1) if jac.size else np.zeros(jac.shape[0], dtype=bool)
        if used.all():
            self._active = rows
        else:
            self._active = rows[used]
            jac = jac[used]
        self._jac = jac
        m = jac.shape[0]
        gram = jac @ jac.T
        self._gram = gram
        self._damp2 = max_damping**2 * math.sqrt(float(np.vdot(gram, gram)))
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

    @classmethod
    def from_factors(
        cls, jac: np.ndarray, basis: np.ndarray, active: np.ndarray, factor: np.ndarray, damp2: float, total: int
    ) -> LeastSquares:
        """The least squares a compiled step has factored (``solver.kernels.bounded_step``): ``jac`` holds the rows
        ``active`` (indices among ``total``) that take part, ``basis`` = L^-1 J, ``factor`` the lower Cholesky factor
        of J J^T + ``damp2`` I."""
        self = cls.__new__(cls)
        self._rows, self._active, self._jac, self.basis = total, active, jac, basis
        self._gram = None  # built when another damping than damp2 is asked for
        self._damp2 = damp2
        self._eig = None if len(jac) else (np.zeros(0), np.zeros((0, 0)))  # no rows: as __init__ makes it
        self._factors = {damp2: factor}
        return self

    def _solve(self, rhs: np.ndarray, extra2: float = 0.0) -> np.ndarray:
        """(G + (d^2 + extra2) I)^-1 rhs."""
        shift = self._damp2 + extra2
        if self._eig is not None:
            lam, u = self._eig
            denom = lam + shift
            return u @ np.divide(u.T @ rhs, denom, out=np.zeros_like(lam), where=denom > 0)
        factor = self._factors.get(shift)
        if factor is None:
            if self._gram is None:
                self._gram = self._jac @ self._jac.T
            shifted = self._gram.copy()
            shifted.flat[:: len(shifted) + 1] += shift
            factor, info = lapack.dpotrf(shifted, lower=1, overwrite_a=1)
            if info != 0:  # cannot happen for shift >= 0 once G itself factored; stay finite regardless
                return np.zeros_like(rhs)
            self._factors[shift] = factor
        return lapack.dpotrs(factor, rhs, lower=1)[0]

    def _own(self, err: np.ndarray) -> np.ndarray:
        """``err`` on the rows that take part."""
        return err[self._active]

    def step(self, err: np.ndarray, extra2: float = 0.0) -> np.ndarray:
        """-J^T (G + d^2 I)^-1 err (plus ``extra2``, a squared LM damping)."""
        return -self._jac.T @ self._solve(self._own(err), extra2)

    def step_within(self, err: np.ndarray, col_scale: np.ndarray, radius: float) -> np.ndarray:
        """The step, in variables ``col_scale * y``, with LM damping raised until its 2-norm <= radius."""
        err = self._own(err)
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
        """lambda with g + J^T lambda ~ 0 (damped least squares); 0 on rows that take no part."""
        own = -self._solve(self._jac @ g)
        out = np.zeros(self._rows)
        out[self._active] = own
        return out

    @property
    def uses_eigendecomposition(self) -> bool:
        """True when J J^T was too ill-conditioned for Cholesky and its eigendecomposition stands in."""
        return self._eig is not None
