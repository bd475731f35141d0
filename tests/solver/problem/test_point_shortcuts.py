"""What a trial point keeps once (a one-sided row's g - floor, a problem's scaled slack, a constraint's Jacobian rows)
and the carried box's float test of "near nothing" answer as computing again does: on poses with rows met, unmet and
NaN, and on box placements far from, near and at the edge of every obstacle's reach."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from helpers import close_to_rounding

import solver
from solver.collision.carried import carried_frame
from solver.constraints.carried_obstacles import CarriedObstacles
from solver.constraints.inequality import Inequality

SCENARIOS = Path(__file__).resolve().parents[3] / "presets" / "scenarios"


@pytest.fixture(scope="module")
def lift():
    """The box lift: frames, balance, floor, obstacles, the body's own pairs, the carried box and box vs obstacles."""
    return solver.load_scenario(SCENARIOS / "box_lift_motion.toml").problem


def poses(problem) -> list[np.ndarray]:
    """x of the start, a crouch through the floor and the table (rows unmet) and the start with a NaN."""
    start = problem.to_x(problem.start())
    low = start.copy()
    low[: problem.model.n] += np.random.default_rng(3).uniform(-0.4, 0.4, problem.model.n)
    low[2] = -0.8
    nan = start.copy()
    nan[2] = np.nan
    return [start, low, nan]


def test_slack_once_per_state_is_the_definition(lift):
    for x in poses(lift):
        state = lift.state_of_x(x.copy())
        lift.scaled_error(state)  # the rows' g - floor kept by the error first, as a trial point does
        slack = lift.scaled_slack(state)
        assert lift.scaled_slack(state) is slack  # once per state
        fresh = lift.state_of_x(x.copy())
        parts = [np.maximum(c.value(fresh) - c.floor, 0.0) if isinstance(c, Inequality) else np.zeros(c.rows)
                 for c in lift.constraints]  # fmt: skip
        close_to_rounding(slack, np.concatenate(parts) * lift.row_weight / lift.row_tolerance)
        assert slack[~lift.one_sided].tolist() == [0.0] * int((~lift.one_sided).sum())
        for c in lift.constraints:  # the error and the Jacobian rows after the kept gap: those of a fresh state
            close_to_rounding(c.error(state), c.error(lift.state_of_x(x.copy())))
            rows, jac = c.jacobian_rows(state)
            rows_again, jac_again = c.jacobian_rows(lift.state_of_x(x.copy()))
            assert rows.tolist() == rows_again.tolist()
            close_to_rounding(jac, jac_again)
    first, second = (lift.state_of_x(x.copy()) for x in poses(lift)[:2])
    assert lift.scaled_slack(first) is not lift.scaled_slack(second)  # another point, its own
    assert not np.array_equal(lift.scaled_slack(first), lift.scaled_slack(second))


def test_a_state_keeps_its_own_values_when_it_adopts(lift):
    x = poses(lift)[0]
    end = lift.state_of_x(x.copy())
    lift.scaled_error(end)
    start = lift.state_of_x(x.copy())
    c = next(c for c in lift.constraints if isinstance(c, Inequality))
    mine = start.cache[c, "gap"] = np.zeros(c.rows)  # computed here before adopting: stays
    start.adopt(end, {id(c) for c in lift.constraints})
    assert start.cache[c, "gap"] is mine
    assert all(start.cache[key] is value for key, value in end.cache.items() if key != (c, "gap"))


def _placements(box: CarriedObstacles) -> list[tuple[np.ndarray, np.ndarray]]:
    """Box placements (centre, rotation) everywhere around the scene: far from everything, near each obstacle, the
    lowest corner just inside, at and just beyond the floor's reach, and NaN."""
    rng = np.random.default_rng(11)
    out = []
    for _ in range(400):
        first = rng.uniform([-0.8, -1.4, -0.1], [0.8, 0.3, 1.6])
        second = first + rng.normal(size=3) * 0.3
        out.append(carried_frame(first, second))
    floor = next(i for i in box._corners)
    reach = box._reach[floor]
    for first in rng.uniform([-0.5, 0.5, 0.5], [0.5, 1.0, 0.9], (20, 3)):
        centre, rotation = carried_frame(first, first + rng.normal(size=3) * 0.3)
        lowest = centre[2] - np.abs(rotation[2]) @ box.half  # the floor is z = 0, normal up
        for aside in (-1e-12, 0.0, 1e-12, 2e-9, -2e-9):
            out.append((centre + [0.0, 0.0, reach + aside - lowest], rotation))
    centre, rotation = out[0]
    out.append((np.full(3, np.nan), rotation))
    return out


def test_near_nothing_is_what_the_arrays_say(lift):
    box = next(c for c in lift.constraints if isinstance(c, CarriedObstacles))
    assert box._sure is not None
    fired = 0
    for centre, rotation in _placements(box):
        got = box.gaps(centre, rotation)
        sure, box._sure = box._sure, None  # the arrays alone
        try:
            expected = box.gaps(centre, rotation)
        finally:
            box._sure = sure
        fired += got is box._far
        for a, b in zip(got, expected, strict=True):
            close_to_rounding(a, b)
    assert 0 < fired < len(_placements(box))  # both ways taken
