"""Issue 37: the body's own clearance rows skip their distance query when the capsules' movement since the last exact
query proves every row clear; what the iteration sees (errors, Jacobian rows, the closest pairs) is the same as a
fresh, exact query's, and the query is really skipped. The floor (measured inline, shared capsule ends) is checked
against a fresh query too."""

from __future__ import annotations

import numpy as np
import pytest

from solver.io.scenario.bodies import load_body
from solver.problem.problem import Problem, ProblemSpec, Target


@pytest.fixture(scope="module")
def model():
    return load_body(preset="male_50")


def _problem(model) -> Problem:
    zero = model.forward(model.zero_pose())
    feet = [Target(f, zero.tcp_frame(model.tcp(f))[1], support=True) for f in ("foot_r", "foot_l")]
    return Problem(model, ProblemSpec(feet))


def _seen(constraint, state):
    rows, jac = constraint.jacobian_rows(state)
    closest = [(c.pair, c.distance) for c in constraint.closest(state)]
    return constraint.error(state), rows, jac, closest


@pytest.mark.parametrize("size", [0.02, 0.2, 0.8])
def test_bounded_rows_give_what_an_exact_query_gives(model, size):
    """A random walk of poses (small to large moves, arms folded into the body at the largest): at every pose the
    constraints that carry a reference from the earlier poses report exactly what fresh ones (no reference) do."""
    kept, rng = _problem(model), np.random.default_rng(int(size * 100))
    x = kept.start()
    for _ in range(25):
        x = kept.x_bounds.clip(x + np.r_[rng.uniform(-size, size, model.n), np.zeros(kept.n_x - model.n)] * 0.3)
        fresh = _problem(model)
        for mine, theirs in ((kept.floor_constraint, fresh.floor_constraint),
                             (kept.self_constraint, fresh.self_constraint)):  # fmt: skip
            got, want = _seen(mine, kept.state_of_x(x)), _seen(theirs, fresh.state_of_x(x))
            np.testing.assert_array_equal(got[0], want[0])
            np.testing.assert_array_equal(got[1], want[1])
            np.testing.assert_allclose(got[2], want[2], rtol=1e-12, atol=1e-12)
            assert [p for p, _ in got[3]] == [p for p, _ in want[3]]
            np.testing.assert_allclose([d for _, d in got[3]], [d for _, d in want[3]], rtol=1e-12, atol=1e-15)


def test_a_small_move_far_from_everything_skips_the_query(model, monkeypatch):
    """A pose with every pair > 1 cm clear measured once; 0.002 rad per joint later nothing of the body's own pairs
    is within its watch band, so the pairs are not measured again (before issue 37 every new pose measured all 85)."""
    problem = _problem(model)
    rows = problem.self_constraint
    rng = np.random.default_rng(1)
    for _ in range(200):  # a random pose (the zero pose has hands at the thighs: no slack)
        start = problem.x_bounds.clip(problem.start() + np.r_[rng.uniform(-0.5, 0.5, model.n),
                                                              np.zeros(problem.n_x - model.n)])  # fmt: skip
        if (rows.value(problem.state_of_x(start)) - rows.floor).min() > 0.01:
            break
    else:
        pytest.fail("no pose with every pair clear by 1 cm")
    calls = []
    original = type(rows)._distances
    monkeypatch.setattr(type(rows), "_distances", lambda self, state: calls.append(1) or original(self, state))
    moved = start.copy()
    moved[: model.n] += 0.002  # rad: a few mm at the hands
    state = problem.state_of_x(problem.x_bounds.clip(moved))
    assert not rows.error(state).any()
    assert rows.jacobian_rows(state)[0].size == 0
    assert calls == []
    assert rows.unmet(state) == []
    rows.value(state)  # asked for the values themselves, it measures
    assert calls == [1]
