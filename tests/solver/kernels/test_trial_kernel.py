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
