"""A motion's next frame starts where the last one ended: its start state adopts what that end state computed
(State.adopt). What it adopts must be what computing it again gives, and only what does not depend on the
targets that moved."""

from __future__ import annotations

import numpy as np
import pytest

from solver import load_scenario
from solver.io.scenario.bodies import PRESETS_DIR
from solver.iteration import solve
from solver.iteration.result import Result
from solver.iteration.trial import Evaluator
from solver.motion.frames import bounded, solve_frames
from solver.options import DEFAULT_LIMITS
from solver.problem.problem import Problem
from tests.helpers import close_to_rounding


@pytest.fixture(scope="module")
def lift():
    """The box lift (floor, obstacles, self-collision, carried box, balance) and two of its frames, the second's
    problem sharing all but its frame group with the first's."""
    scenario = load_scenario(PRESETS_DIR / "scenarios" / "box_lift_motion.toml")
    first = scenario.problem_at(scenario.frames[0])
    result = solve(first, scenario.start, scenario.options)
    second = bounded(scenario.problem_at(scenario.frames[3]), result.x, DEFAULT_LIMITS)
    return scenario, first, result, second


def _linearized(problem, state):
    """Everything a linearisation asks of ``state``: errors, live Jacobian rows, comfort model."""
    err, worst = problem.scaled_error_and_worst(state, 1.0 / problem.row_weight)
    live, jac = problem.live_jacobian(state)
    grad, curv = problem.comfort_model(state)
    return err, worst, live, jac, grad, curv


def test_adopted_values_are_those_computed_again(lift):
    _, first, result, second = lift
    end = result.state  # the solve's last evaluation, kept by the Result
    assert any(key[0] is c for c in first.constraints for key in end.cache if isinstance(key, tuple))
    warm = second.state_of_x(end.x.copy()).adopt(end)
    shared = [c for c in second.constraints if c in first.constraints]
    assert shared and second.frames not in shared  # the moved targets' group is new, the rest shared
    for c in shared:  # carried over where the first frame computed it
        if (c, "jacobian rows") in end.cache:
            assert (c, "jacobian rows") in warm.cache
    assert (second.frames, "jacobian rows") not in warm.cache
    cold = second.state_of_x(end.x.copy())
    moved = first.scaled_error(end) - second.scaled_error(cold)  # the targets moved: what depends on them differs
    assert np.abs(moved).max() > 1e-3
    for got, expected in zip(_linearized(second, warm), _linearized(second, cold), strict=True):
        close_to_rounding(got, expected)


def test_adopt_takes_nothing_from_another_point(lift):
    _, _, result, second = lift
    moved = result.state.x.copy()
    moved[10] += 1e-3
    other = second.state_of_x(moved).adopt(result.state)
    assert not other.cache and "kin" not in other.__dict__


def test_a_warm_solve_gives_the_cold_one(lift):
    _, _, result, second = lift
    cold = solve(second, result.x)
    warm = solve(second, result.x, warm=result.state)
    assert (warm.converged, warm.iterations, warm.unmet) == (cold.converged, cold.iterations, cold.unmet)
    close_to_rounding(warm.x, cold.x)
    close_to_rounding(list(warm.residuals.values()), list(cold.residuals.values()))
    assert warm.comfort == pytest.approx(cold.comfort, rel=1e-12)


def test_cached_derivatives_are_not_written_to(lift):
    _, _, result, second = lift
    state = Evaluator(second, True)(second.to_variables(result.x)).state
    grad, curv = (a.copy() for a in second.comfort.derivatives(state))
    second.comfort_model(state)
    second.comfort_derivatives(state)
    again = second.comfort.derivatives(state)
    assert np.array_equal(again[0], grad) and np.array_equal(again[1], curv)


def test_a_result_from_an_adopted_state_reports_what_a_fresh_one_does(lift):
    _, first, result, second = lift
    end = result.state
    for problem in (first, second):  # first: the values kept (closest, residuals, unmet, wrenches) are reused
        Result.from_state(problem, end, 1, 0.0)
    warm = Result.from_state(second, second.state_of_x(end.x.copy()).adopt(end), 1, 0.0)
    cold = Result.from_state(second, second.state_of_x(end.x.copy()), 1, 0.0)
    assert (warm.unmet, list(warm.residuals)) == (cold.unmet, list(cold.residuals))
    close_to_rounding(list(warm.residuals.values()), list(cold.residuals.values()))
    assert [(c.part, c.other) for c in warm.closest] == [(c.part, c.other) for c in cold.closest]
    close_to_rounding([c.distance for c in warm.closest], [c.distance for c in cold.closest])
    for got, expected in zip(warm.contacts, cold.contacts, strict=True):
        assert got["tcp"] == expected["tcp"]
        for key in ("point", "force", "moment"):
            close_to_rounding(got[key], expected[key])
    assert warm.com is result.com  # kept under a name: a held pose's frames share it
    close_to_rounding(cold.com, second.state_of_x(end.x.copy()).kin.body_com())
    moved = end.x.copy()
    moved[10] += 1e-3  # another point: its own com, not the one kept
    close_to_rounding(Result.from_state(second, second.state_of_x(moved).adopt(end), 1, 0.0).com,
                      second.state_of_x(moved).kin.body_com())  # fmt: skip


def test_moved_frame_groups_share_what_does_not_depend_on_the_targets(lift):
    scenario, first, result, _ = lift
    later = [scenario.problem_at(frame) for frame in scenario.frames[5:8]]
    base = scenario.problem.frames
    assert all(p.frames._shared is base._shared for p in later)  # one row mask, moving joints and tables for all
    for problem in later:
        fresh = Problem(problem.model, problem.spec)  # built afresh with this frame's targets
        state, again = problem.state_of_x(result.x.copy()), fresh.state_of_x(result.x.copy())
        close_to_rounding(problem.frames.error(state), fresh.frames.error(again))
        close_to_rounding(problem.frames.jacobian(state), fresh.frames.jacobian(again))


def test_a_held_pose_does_not_carry_every_earlier_frame_along(lift):
    """After the last key the targets hold: each frame ends where it started, and its start takes only the values
    of objects its own problem uses (not every earlier frame's moved frame group)."""
    scenario = lift[0]
    held = list(range(scenario.frames[-1], scenario.frames[-1] + 30))
    sizes = [len(result.state.cache) for _, result in solve_frames(scenario.problem_at, held, scenario.start)]
    assert max(sizes[10:]) <= max(sizes[:10])


def test_a_results_comfort_is_the_total_of_its_parts(lift):
    """From a trial point evaluated with comfort (its parts and cost f = -h kept) and from a fresh state, a result's
    comfort is the comfort's total of its parts, to the bit."""
    _, _, result, second = lift
    evaluate = Evaluator(second, True)
    trial = evaluate(second.to_variables(result.x))
    evaluate.cost(trial.state)
    parts = second.comfort.parts(second.state_of_x(result.x.copy()))
    for state in (trial.state, second.state_of_x(result.x.copy())):
        got = Result.from_state(second, state, 0, 0.0)
        assert got.comfort_parts == parts and got.comfort == second.comfort.total(parts)
