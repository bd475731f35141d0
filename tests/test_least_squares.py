"""The solver's least-squares step: the Cholesky shortcut for well-conditioned Jacobians equals the SVD path."""

import numpy as np

from solver.solve import DEFAULT_OPTIONS, _certified_inverse_factor, _LeastSquares


def _both(jac: np.ndarray) -> tuple[_LeastSquares, _LeastSquares]:
    fast = _LeastSquares(jac, DEFAULT_OPTIONS)
    plain = _LeastSquares(jac, DEFAULT_OPTIONS)
    plain._inverse = None  # force the SVD path for the same Jacobian
    plain._factor()
    plain.basis = plain.vt[plain._keep]
    return fast, plain


def test_cholesky_shortcut_matches_the_svd_step():
    rng = np.random.default_rng(3)
    jac = rng.standard_normal((8, 30))
    fast, plain = _both(jac)
    assert fast._inverse is not None and not fast._svd
    err, grad, scale = rng.standard_normal(8), rng.standard_normal(30), rng.uniform(0.5, 2.0, 30)
    np.testing.assert_allclose(fast.step(err), plain.step(err), atol=1e-10)
    np.testing.assert_allclose(fast.multipliers(grad), plain.multipliers(grad), atol=1e-10)
    np.testing.assert_allclose(fast.basis.T @ fast.basis, plain.basis.T @ plain.basis, atol=1e-10)
    np.testing.assert_allclose(fast.basis @ fast.basis.T, np.eye(8), atol=1e-10)
    wide = np.linalg.norm(scale * plain.step(err)) * 2.0
    np.testing.assert_allclose(fast.step_within(err, scale, wide), plain.step_within(err, scale, wide), atol=1e-10)
    # a binding trust region falls back to the SVD's damped step
    tight = np.linalg.norm(scale * plain.step(err)) * 0.3
    short = fast.step_within(err, scale, tight)
    assert fast._svd and np.linalg.norm(short) <= tight * (1 + 1e-9)
    np.testing.assert_allclose(short, plain.step_within(err, scale, tight), atol=1e-10)


def test_near_singular_or_bad_jacobians_take_the_svd_path():
    rng = np.random.default_rng(4)
    jac = rng.standard_normal((6, 20))
    jac[5] = jac[4] + 1e-5 * rng.standard_normal(20)  # singular value ratio ~1e-5, below the 1e-3 threshold
    assert _certified_inverse_factor(jac, DEFAULT_OPTIONS.singular_threshold) is None
    lsq = _LeastSquares(jac, DEFAULT_OPTIONS)
    assert lsq._svd and np.all(np.isfinite(lsq.step(rng.standard_normal(6))))
    assert _certified_inverse_factor(np.full((2, 5), np.nan), 1e-3) is None
    assert _certified_inverse_factor(np.zeros((0, 5)), 1e-3) is None
