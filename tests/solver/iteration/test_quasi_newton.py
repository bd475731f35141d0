"""The quasi-Newton comfort model: compact L-BFGS form and the null-space Newton step, against dense algebra."""

import numpy as np
import pytest
from scipy.linalg import null_space

from solver.iteration import CurvatureMemory, null_space_newton


def _pairs(rng: np.random.Generator, n: int, k: int) -> list[tuple[np.ndarray, np.ndarray]]:
    """k pairs (s, y = H s + small noise) of a random positive definite H, so s.y > 0."""
    root = rng.normal(size=(n, n))
    hessian = root @ root.T / n + np.eye(n)
    out = []
    for _ in range(k):
        s = rng.normal(size=n)
        out.append((s, hessian @ s + 0.01 * rng.normal(size=n)))
    return out


def _dense_bfgs(b0: np.ndarray, pairs) -> np.ndarray:
    """The textbook BFGS recursion from diag(b0)."""
    b = np.diag(b0)
    for s, y in pairs:
        bs = b @ s
        b = b - np.outer(bs, bs) / (s @ bs) + np.outer(y, y) / (y @ s)
    return b


@pytest.mark.parametrize("seed", range(5))
def test_compact_form_is_the_bfgs_recursion(seed):
    rng = np.random.default_rng(seed)
    n, k = 12, 4
    pairs = _pairs(rng, n, k)
    memory = CurvatureMemory(size=k)
    for s, y in pairs:
        memory.add(s, y)
    b0 = rng.uniform(0.5, 3.0, n)
    u, middle = memory.compact(b0)
    compact = np.diag(b0) - u @ np.linalg.solve(middle, u.T)
    np.testing.assert_allclose(compact, _dense_bfgs(b0, pairs), rtol=1e-9, atol=1e-9)
    s, y = pairs[-1]
    np.testing.assert_allclose(compact @ s, y, rtol=1e-9, atol=1e-9)  # secant condition
    assert np.all(np.linalg.eigvalsh(compact) > 0)


def test_memory_keeps_the_newest_pairs_and_skips_negative_curvature():
    rng = np.random.default_rng(7)
    memory = CurvatureMemory(size=2)
    assert memory.compact(np.ones(5)) is None
    pairs = _pairs(rng, 5, 3)
    for s, y in pairs:
        memory.add(s, y)
    memory.add(pairs[0][0], -pairs[0][1])  # s.y < 0: skipped
    memory.add(pairs[0][0], np.full(5, np.nan))  # not finite: skipped
    assert len(memory.steps) == 2
    np.testing.assert_array_equal(memory.steps[-1], pairs[-1][0])
    np.testing.assert_array_equal(memory.changes[0], pairs[1][1])


@pytest.mark.parametrize("seed", range(5))
def test_null_space_newton_matches_the_dense_solution(seed):
    rng = np.random.default_rng(seed)
    n, rows, k = 15, 4, 3
    basis = np.linalg.qr(rng.normal(size=(n, rows)))[0].T  # orthonormal rows
    memory = CurvatureMemory(size=k)
    for s, y in _pairs(rng, n, k):
        memory.add(s, y)
    v, middle = memory.compact(np.ones(n))
    grad = rng.normal(size=n)
    z = null_space_newton(grad, basis, (v, middle))
    model = np.eye(n) - v @ np.linalg.solve(middle, v.T)
    zb = null_space(basis)  # columns span {z : basis z = 0}
    expected = -zb @ np.linalg.solve(zb.T @ model @ zb, zb.T @ grad)
    np.testing.assert_allclose(z, expected, rtol=1e-8, atol=1e-10)
    np.testing.assert_allclose(basis @ z, 0.0, atol=1e-10)
    assert z @ grad < 0


def test_null_space_newton_without_memory_is_the_projected_gradient():
    rng = np.random.default_rng(3)
    basis = np.linalg.qr(rng.normal(size=(8, 2)))[0].T
    grad = rng.normal(size=8)
    z = null_space_newton(grad, basis, None)
    np.testing.assert_allclose(z, -(grad - basis.T @ (basis @ grad)))
