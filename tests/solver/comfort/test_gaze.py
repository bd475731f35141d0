"""The gaze term (issue 35, part 2: the head looks at the hands): gradient and curvature against finite differences,
where it aims, when it is zero, and that a solve turns the head toward a low hand."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import finite_difference

import solver.comfort.gaze as gaze
from solver import Problem, ProblemSpec, Target
from solver.comfort import BEHAVIOUR, STANDARD, Comfort, Gaze
from solver.io.scenario.bodies import load_body
from solver.iteration import solve


@pytest.fixture(scope="module")
def male50():
    return load_body(preset="male_50")


def _targets(model, hands=(("hand_r", (-0.2, -0.45, 1.0)),)) -> list[Target]:
    zero = model.forward(model.zero_pose())
    feet = [Target(f, zero.tcp_frame(model.tcp(f))[1], support=True) for f in ("foot_r", "foot_l")]
    return [*feet, *(Target(t, np.array(p), lock=("x", "y", "z")) for t, p in hands)]


ON = BEHAVIOUR.replace(gaze=1.0)  # the term is off by default (its fit found no gain): switched on here


def _problem(model, targets, terms=None, weights=ON) -> Problem:
    return Problem(model, ProblemSpec(targets, balance=True, comfort=terms, comfort_weights=weights))


@pytest.mark.parametrize("seed", range(3))
def test_gaze_gradient_and_curvature_match_finite_differences(male50, seed) -> None:
    behind = _targets(male50, (("hand_r", (-0.3, 0.4, 0.4)),))  # well past the eyes' share: the cost is not 0
    problem = _problem(male50, behind, Comfort([(2.5, Gaze(male50))]))
    term = problem.comfort.terms[0][1]
    rng = np.random.default_rng(seed)
    theta = np.clip(rng.normal(0.0, 0.3, male50.n), male50.lower + 0.01, male50.upper - 0.01)
    theta[:3] = rng.normal(0.0, 0.2, 3)  # the root's position moves the eyes too
    x = problem.start(theta)
    state = problem.state(x)
    assert term.cost(state) > 0.05
    grad, curv = term.derivatives(state, 2.5)
    numeric = finite_difference(lambda xx: [2.5 * term.cost(problem.state(xx))], x)[0]
    np.testing.assert_allclose(grad, numeric, rtol=1e-5, atol=1e-7)
    assert np.all(curv >= 0.0) and np.any(curv > 0.0)
    h = 1e-4  # the diagonal curvature is the exact second derivative where it is positive
    checked = 0
    for j in np.flatnonzero(curv > 1e-3)[:16]:
        e = np.zeros_like(x)
        e[j] = h
        second = 2.5 * (term.cost(problem.state(x + e)) - 2 * term.cost(state) + term.cost(problem.state(x - e)))
        assert curv[j] == pytest.approx(second / h**2, rel=1e-3, abs=1e-6)
        checked += 1
    assert checked >= 5


def test_gaze_aims_at_the_mean_of_the_hand_targets_and_is_one_fifteen_degrees_past_the_eyes_share(male50) -> None:
    hands = (("hand_r", (-0.2, -0.5, 0.9)), ("hand_l", (0.2, -0.5, 0.7)))
    problem = _problem(male50, _targets(male50, hands))
    term = next(t for _, t in problem.comfort.terms if t.name == "gaze")
    np.testing.assert_allclose(term.point, [0.0, -0.5, 0.8])
    state = problem.state(problem.start())
    _, v, u, _ = term.geometry(state)
    psi = np.arccos(np.clip(v @ u, -1, 1))
    free = gaze.EYES_TAKE
    expected = (max(np.cos(free) - np.cos(psi), 0.0) / (np.cos(free) - np.cos(free + np.radians(15.0)))) ** 2
    assert psi > free and term.cost(state) == pytest.approx(expected)
    # moved to other targets (a motion's next frame), the term follows them
    moved = problem.with_targets(_targets(male50, (("hand_r", (0.0, -0.6, 1.4)),)))
    np.testing.assert_allclose(next(t for _, t in moved.comfort.terms if t.name == "gaze").point, [0.0, -0.6, 1.4])


def test_gaze_is_zero_without_a_hand_target_with_a_user_gaze_or_with_the_behaviour_model_off(male50) -> None:
    def cost(problem):
        parts = problem.comfort.parts(problem.state(problem.start()))
        return parts["gaze"]

    assert cost(_problem(male50, _targets(male50))) > 0.0
    assert cost(_problem(male50, _targets(male50, ()))) == 0.0  # feet only
    oriented = [*_targets(male50)[:2], Target("hand_r", np.array([0.0, -0.5, 1.0]), lock=("rx", "ry", "rz"))]
    assert cost(_problem(male50, oriented)) == 0.0  # a target that holds no position
    look = Target("eyes", np.array([0.0, -0.1, 1.6]), np.eye(3), lock=("rx", "rz"))
    assert cost(_problem(male50, [*_targets(male50), look])) == 0.0  # the user's gaze wins
    assert cost(_problem(male50, _targets(male50), weights=STANDARD)) == 0.0
    assert cost(_problem(male50, _targets(male50), weights=BEHAVIOUR)) == 0.0  # the default: off
    assert cost(_problem(male50, _targets(male50), weights=STANDARD.replace(gaze=1.0))) == 0.0  # trunk 0: off


def test_a_solve_turns_the_head_toward_a_low_hand(male50) -> None:
    targets = _targets(male50, (("hand_r", (-0.15, -0.35, 0.5)),))
    on_problem = _problem(male50, targets)
    term = next(t for _, t in on_problem.comfort.terms if t.name == "gaze")
    off = solve(_problem(male50, targets, weights=BEHAVIOUR.replace(gaze=0.0)), male50.zero_pose())
    on = solve(on_problem, male50.zero_pose())
    assert off.converged and on.converged
    before = term.cost(on_problem.state(on_problem.start(off.theta)))
    assert before > 1.0 and on.comfort_parts["gaze"] < 0.5 * before
