"""The comfort model in the solver's scaled variables by one kernel (solver/kernels/reduction.py ``comfort_model``)
is the NumPy path's: the basis product summed as ``np.add.reduceat`` sums (to the bit), then scaled."""

from __future__ import annotations

import numpy as np
import pytest

from solver import kernels
from solver.body.reduction import DEFAULT_GROUPS
from solver.io.scenario.bodies import load_body
from solver.problem.problem import Problem, ProblemSpec, Target

pytest.importorskip("numba")


def test_comfort_model_sums_as_reduceat() -> None:
    """Columns of 1 to 20 entries (NumPy sums more than eight pairwise in eight lanes), values over 16 decades."""
    from solver.kernels.reduction import comfort_model

    rng = np.random.default_rng(3)
    for _ in range(200):
        lengths = rng.integers(1, 21, size=rng.integers(1, 12))
        starts = np.concatenate([[0], np.cumsum(lengths)[:-1]]).astype(np.int64)
        n_x = int(lengths.sum()) + 5
        rows = rng.permutation(n_x)[: lengths.sum()].astype(np.int64)
        weight = rng.normal(size=len(rows))
        grad, curv = (rng.normal(size=n_x) * 10.0 ** rng.integers(-8, 8, size=n_x) for _ in range(2))
        scale = rng.uniform(0.1, 3.0, size=len(starts))
        grad_f, curv_f = np.empty(len(starts)), np.empty(len(starts))
        comfort_model(grad, curv, rows, weight, starts, scale, grad_f, curv_f)
        np.testing.assert_array_equal(grad_f, -np.add.reduceat(grad[rows] * weight, starts) * scale)
        np.testing.assert_array_equal(curv_f, np.add.reduceat(curv[rows] * (weight * weight), starts) * scale**2)


@pytest.mark.parametrize("groups", [DEFAULT_GROUPS, ()])
def test_problem_comfort_model_is_the_numpy_one(groups: tuple[str, ...]) -> None:
    """Problem.comfort_model with and without the kernels, with and without a reduction, on random poses."""
    model = load_body(preset="male_50")
    rng = np.random.default_rng(8)
    kin = model.forward(model.zero_pose())
    targets = [
        Target(name, kin.tcp_frame(model.tcp(name))[1] + rng.normal(scale=0.1, size=3), support=support)
        for name, support in (("foot_l", True), ("foot_r", True), ("hand_r", False))
    ]
    problem = Problem(model, ProblemSpec(targets, reduction=groups))
    for _ in range(4):
        v = problem.start() + rng.normal(scale=0.1, size=problem.n_var)
        with kernels.using(True):
            state = problem.state(v)
            got = problem.comfort_model(state)
            grad_h, curv = problem.comfort_derivatives(state)  # the NumPy sums of the same dh/dx
            np.testing.assert_array_equal(got[0], -grad_h * problem.scale)
            np.testing.assert_array_equal(got[1], curv * problem.scale**2)
        with kernels.using(False):
            expected = problem.comfort_model(problem.state(v))
        for mine, want in zip(got, expected, strict=True):
            np.testing.assert_allclose(mine, want, rtol=0, atol=1e-12 * max(1.0, np.abs(want).max()))
