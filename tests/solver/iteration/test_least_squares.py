"""The solver's least-squares step against a reference built from numpy's SVD: Tikhonov-damped steps and
multipliers, the undamped row-space basis, the trust region, and rank-deficient or empty Jacobians."""

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from solver.iteration import TUNING, LeastSquares


def _reference(jac: np.ndarray):
    """(u, s, vt, d^2): numpy's SVD and the damping the solver documents (max_damping^2 ||J J^T||_F)."""
    u, s, vt = np.linalg.svd(jac, full_matrices=False)
    damp2 = TUNING.max_damping**2 * np.linalg.norm(jac @ jac.T)
    return u, s, vt, damp2


def _damped_step(jac: np.ndarray, err: np.ndarray, extra2: float = 0.0) -> np.ndarray:
    u, s, vt, damp2 = _reference(jac)
    return -vt.T @ (s / (s * s + damp2 + extra2) * (u.T @ err))


def _projector(basis: np.ndarray) -> np.ndarray:
    return basis.T @ basis


def test_well_conditioned_step_basis_and_multipliers_match_the_svd():
    rng = np.random.default_rng(3)
    jac = rng.standard_normal((8, 30))
    lsq = LeastSquares(jac, TUNING.max_damping)
    err, grad = rng.standard_normal(8), rng.standard_normal(30)
    np.testing.assert_allclose(lsq.step(err), _damped_step(jac, err), atol=1e-10)
    # with singular values far above the damping the step is the minimum-norm solution of J dx = -err
    np.testing.assert_allclose(lsq.step(err), -np.linalg.pinv(jac) @ err, rtol=1e-4)
    np.testing.assert_allclose(lsq.basis @ lsq.basis.T, np.eye(8), atol=1e-10)
    _, _, vt, _ = _reference(jac)
    np.testing.assert_allclose(_projector(lsq.basis), _projector(vt), atol=1e-10)
    u, s, vt, damp2 = _reference(jac)
    np.testing.assert_allclose(lsq.multipliers(grad), -u @ (s / (s * s + damp2) * (vt @ grad)), atol=1e-10)


def test_near_singular_jacobian_is_damped_not_blown_up():
    rng = np.random.default_rng(4)
    jac = rng.standard_normal((6, 20))
    jac[5] = jac[4] + 1e-5 * rng.standard_normal(20)  # singular value ratio ~1e-5, far below the damping
    err = rng.standard_normal(6)
    lsq = LeastSquares(jac, TUNING.max_damping)
    step = lsq.step(err)
    np.testing.assert_allclose(step, _damped_step(jac, err), rtol=1e-5, atol=1e-8)
    _, s, _, damp2 = _reference(jac)
    assert np.linalg.norm(step) <= np.linalg.norm(err) / (2.0 * math.sqrt(damp2)) * (1 + 1e-9)  # Tikhonov's bound
    assert np.linalg.norm(step) < 1e-3 * np.linalg.norm(np.linalg.pinv(jac) @ err)  # the undamped step explodes
    # the basis still spans the whole (numerical) row space: the null-space projection removes every row
    np.testing.assert_allclose(lsq.basis @ lsq.basis.T, np.eye(6), atol=1e-5)


@pytest.mark.parametrize("shape, rank", [((6, 20), 4), ((12, 7), 7), ((5, 9), 0)])
def test_rank_deficient_or_tall_jacobians_take_the_eigendecomposition(shape, rank):
    rng = np.random.default_rng(rank)
    m, n = shape
    jac = rng.standard_normal((m, rank)) @ rng.standard_normal((rank, n)) if rank else np.zeros(shape)
    lsq = LeastSquares(jac, TUNING.max_damping)
    assert lsq.uses_eigendecomposition
    err, grad = rng.standard_normal(m), rng.standard_normal(n)
    assert lsq.basis.shape == (rank, n)
    np.testing.assert_allclose(lsq.basis @ lsq.basis.T, np.eye(rank), atol=1e-8)
    if rank:
        _, _, vt, _ = _reference(jac)
        np.testing.assert_allclose(_projector(lsq.basis), _projector(vt[:rank]), atol=1e-8)
        np.testing.assert_allclose(lsq.step(err), _damped_step(jac, err), rtol=1e-6, atol=1e-9)
    for value in (lsq.step(err), lsq.multipliers(grad), lsq.step_within(err, np.ones(n), 0.1)):
        assert np.all(np.isfinite(value))


def test_empty_jacobian():
    lsq = LeastSquares(np.zeros((0, 5)), TUNING.max_damping)
    assert lsq.basis.shape == (0, 5)
    assert np.all(lsq.step(np.zeros(0)) == 0.0) and lsq.multipliers(np.ones(5)).shape == (0,)


@pytest.mark.parametrize("shrink", [0.9, 0.3, 0.01])
def test_trust_region_step_is_the_levenberg_marquardt_step_of_that_length(shrink):
    rng = np.random.default_rng(5)
    jac = rng.standard_normal((10, 40)) * np.geomspace(1e-2, 1.0, 10)[:, None]
    err, col_scale = rng.standard_normal(10), rng.uniform(0.2, 3.0, 40)
    lsq = LeastSquares(jac, TUNING.max_damping)
    free = col_scale * lsq.step(err)
    wide = np.linalg.norm(free) * 1.5
    np.testing.assert_allclose(lsq.step_within(err, col_scale, wide), free, atol=1e-12)
    radius = np.linalg.norm(free) * shrink
    short = lsq.step_within(err, col_scale, radius)
    assert radius * 0.9 <= np.linalg.norm(short) <= radius * (1 + 1e-9)
    # the reference: the LM parameter whose damped step has exactly that length in the scaled variables
    lm = brentq(lambda e: np.linalg.norm(col_scale * _damped_step(jac, err, e)) - radius, 0.0, 1e8)
    reference = col_scale * _damped_step(jac, err, lm)
    cosine = short @ reference / (np.linalg.norm(short) * np.linalg.norm(reference))
    assert cosine > 0.995, cosine


def test_rows_without_entries_take_no_part():
    """A met one-sided constraint has a zero Jacobian row: the factors are those of the other rows (Cholesky, not the
    eigendecomposition a singular J J^T would need), the step and basis are theirs, its multiplier is 0."""
    rng = np.random.default_rng(8)
    jac = rng.standard_normal((6, 25))
    padded = np.zeros((9, 25))
    rows = [0, 2, 3, 5, 6, 8]
    padded[rows] = jac
    err = np.zeros(9)
    err[rows] = rng.standard_normal(6)
    grad = rng.standard_normal(25)
    alone, both = LeastSquares(jac, TUNING.max_damping), LeastSquares(padded, TUNING.max_damping)
    assert not both.uses_eigendecomposition
    np.testing.assert_allclose(both.step(err), alone.step(err[rows]), atol=1e-12)
    np.testing.assert_allclose(both.step_within(err, np.ones(25), 0.1), alone.step_within(err[rows], np.ones(25), 0.1))
    np.testing.assert_allclose(_projector(both.basis), _projector(alone.basis), atol=1e-12)
    multipliers = both.multipliers(grad)
    np.testing.assert_allclose(multipliers[rows], alone.multipliers(grad), atol=1e-12)
    assert not multipliers[[1, 4, 7]].any()
    nothing = LeastSquares(np.zeros((3, 25)), TUNING.max_damping)
    assert not nothing.step(np.zeros(3)).any() and nothing.basis.shape == (0, 25)
