"""A trial point's scaled error and its largest row by one kernel (solver/kernels/trial.py) are the NumPy path's."""

from __future__ import annotations

import numpy as np
import pytest

from solver import kernels
from solver.io.scenario.bodies import load_body
from solver.iteration.trial import Evaluator
from solver.problem.problem import Problem, ProblemSpec, Target

pytest.importorskip("numba")


def test_scale_rows_is_numpy_scaling_and_max() -> None:
    """Random rows, weights and tolerances (to the bit), no rows (0) and a NaN row (NaN; every row still scaled)."""
    from solver.kernels.trial import scale_rows

    rng = np.random.default_rng(4)
    for size in (0, 1, 7, 30):
        raw, weight, tolerance = rng.normal(size=size), rng.uniform(0.1, 3, size), rng.uniform(1e-3, 1, size)
        unweight = 1.0 / weight
        err = raw.copy()
        worst = scale_rows(err, weight, tolerance, unweight)
        expected = raw * weight / tolerance
        np.testing.assert_array_equal(err, expected)
        assert worst == float(np.max(np.abs(expected) * unweight, initial=0.0))
    err = np.array([1.0, np.nan, 3.0])
    assert np.isnan(scale_rows(err, np.ones(3), np.full(3, 0.5), np.ones(3)))
    np.testing.assert_array_equal(err, [2.0, np.nan, 6.0])


def test_evaluator_trials_are_the_numpy_ones() -> None:
    """Evaluator (scaled error, merit, worst row) with and without the kernels on random poses."""
    model = load_body(preset="male_50")
    rng = np.random.default_rng(6)
    kin = model.forward(model.zero_pose())
    targets = [
        Target(name, kin.tcp_frame(model.tcp(name))[1] + rng.normal(scale=0.1, size=3), support=support)
        for name, support in (("foot_l", True), ("foot_r", True), ("hand_r", False), ("hand_l", False))
    ]
    problem = Problem(model, ProblemSpec(targets, floor=True))
    for _ in range(4):
        v = problem.start() + rng.normal(scale=0.1, size=problem.n_var)
        trials = {}
        for compiled in (False, True):
            with kernels.using(compiled):
                trials[compiled] = Evaluator(problem, True)(v)
        want, got = trials[False], trials[True]
        np.testing.assert_allclose(got.err, want.err, rtol=0, atol=1e-12 * max(1.0, np.abs(want.err).max()))
        assert abs(got.worst - want.worst) <= 1e-12 * max(1.0, want.worst)
        assert abs(got.merit - want.merit) <= 1e-12 * max(1.0, want.merit)


def test_step_point_is_numpy_clip_of_the_step() -> None:
    """Both forms of a line search's trial point (to the bit), with NaN, -0.0 and points on and past the bounds."""
    from solver.kernels.trial import step_point

    rng = np.random.default_rng(9)
    n = 40
    lower, upper = -rng.uniform(0.1, 1, n), rng.uniform(0.1, 1, n)
    lower[0] = 0.0
    scale = rng.uniform(0.2, 2, n)
    for alpha in (1.0, 0.37, 1e-3):
        x = rng.uniform(-1.2, 1.2, n)
        x[0], x[1] = -0.0, np.nan
        direction, task = rng.normal(size=n), rng.normal(size=n)
        direction[0] = task[0] = 0.0
        out = np.empty(n)
        step_point(x, alpha, direction, np.zeros(0), scale, lower, upper, out)
        np.testing.assert_array_equal(out, np.clip(x + alpha * direction * scale, lower, upper))
        assert not np.signbit(out[0])  # np.clip takes the bound 0.0 for -0.0
        step_point(x, alpha, direction, task, scale, lower, upper, out)
        np.testing.assert_array_equal(out, np.clip(x + (task + alpha * direction) * scale, lower, upper))


@pytest.mark.parametrize("groups", [("lumbar", "thoracic", "cervical", "grasp"), ()])
def test_problem_state_by_linear_phi_is_the_numpy_one(groups: tuple[str, ...]) -> None:
    """Problem.state's x through a linear reduction by the kernel is Reduction.phi's (to the bit)."""
    from solver.kernels.trial import linear_phi

    model = load_body(preset="male_50")
    problem = Problem(
        model, ProblemSpec([Target("hand_r", np.array([0.3, -0.4, 1.0]))], balance=False, reduction=groups)
    )
    rng = np.random.default_rng(2)
    for _ in range(4):
        v = problem.start() + rng.normal(scale=0.2, size=problem.n_var)
        with kernels.using(True):
            got = problem.state(v).x
        with kernels.using(False):
            np.testing.assert_array_equal(got, problem.state(v).x)
    if groups:
        red = problem.reduction
        beta = rng.normal(size=red.n)
        out = np.empty(len(red.offset))
        linear_phi(beta, red.offset, *red.kernel_supports, out)
        np.testing.assert_array_equal(out, red.phi(beta))
