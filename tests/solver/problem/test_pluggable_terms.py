"""A new constraint or comfort term plugs in through its interface alone: no change to the iteration."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import finite_difference

from solver import Problem, ProblemSpec, Target, solve
from solver.body.state import State
from solver.comfort import Comfort, ComfortTerm, ComfortWeights
from solver.constraints import Inequality
from solver.io.scenario.bodies import load_body


class HandAbove(Inequality):
    """The right palm's height above ``height`` (m): one row."""

    name = "hand_r above"

    def __init__(self, model, height: float, n_x: int) -> None:
        self.tcp, self.n_x = model.tcp("hand_r"), n_x
        self.floor = np.array([height])

    @property
    def rows(self) -> int:
        return 1

    def tolerance(self) -> np.ndarray:
        return np.array([1e-3])

    def value(self, state: State) -> np.ndarray:
        return state.kin.tcp_frame(self.tcp)[1][2:3]

    def value_jacobian(self, state: State) -> np.ndarray:
        out = np.zeros((1, self.n_x))
        n = state.kin.model.n
        out[:, :n] = state.kin.frame_jacobian(self.tcp.link, state.kin.tcp_frame(self.tcp)[1])[2:3]
        return out


class ElbowStraight(ComfortTerm):
    """A made-up preference: the right elbow straight (cost = flexion^2, rad^2)."""

    name = "elbow"

    def __init__(self, model) -> None:
        self.joint = model.joint_index("elbow_r_flexion")

    def cost(self, state: State) -> float:
        return float(state.theta[self.joint] ** 2)

    def derivatives(self, state: State, weight: float) -> tuple[np.ndarray, np.ndarray]:
        grad, curv = np.zeros(state.n_x), np.zeros(state.n_x)
        grad[self.joint] = weight * 2.0 * state.theta[self.joint]
        curv[self.joint] = weight * 2.0
        return grad, curv


@pytest.fixture(scope="module")
def male50():
    return load_body(preset="male_50")


def _feet(model) -> list[Target]:
    zero = model.forward(model.zero_pose())
    return [
        Target(f, zero.tcp_frame(model.tcp(f))[1], lock=("x", "y", "z", "rx", "ry", "rz"), support=True)
        for f in ("foot_l", "foot_r")
    ]


def test_an_inequality_is_zero_while_met_and_its_jacobian_is_exact_while_violated(male50):
    plain = Problem(male50, ProblemSpec(_feet(male50)))
    above = HandAbove(male50, 1.2, plain.n_x)
    x = plain.start()
    state = plain.state(x)
    assert above.value(state)[0] < 1.2 and above.error(state)[0] < 0  # arms hanging: violated
    numeric = finite_difference(lambda xx: above.error(plain.state(xx)), x)
    np.testing.assert_allclose(above.jacobian(state), numeric, atol=1e-6)
    met = HandAbove(male50, 0.1, plain.n_x)
    assert met.error(state)[0] == 0.0 and not met.jacobian(state).any()
    assert met.residuals(state) == {"hand_r above.shortfall": 0.0}


def test_the_solver_meets_an_extra_inequality_it_knows_nothing_about(male50):
    """Comfort alone lets the arm hang (palm ~0.8 m); with the inequality the palm ends at or above 1.2 m."""
    free = solve(Problem(male50, ProblemSpec(_feet(male50))))
    height = free.state.kin.tcp_frame(male50.tcp("hand_r"))[1][2]
    assert free.converged and height < 1.0
    problem = Problem(male50, ProblemSpec(_feet(male50), extra_constraints=[HandAbove(male50, 1.2, free.problem.n_x)]))
    held = solve(problem)
    assert held.converged and "hand_r above.shortfall" in held.residuals
    assert held.state.kin.tcp_frame(male50.tcp("hand_r"))[1][2] >= 1.2 - 1e-3


def test_a_new_comfort_term_plugs_in_with_an_exact_gradient(male50):
    targets = [*_feet(male50), Target("hand_r", np.array([-0.25, -0.3, 1.0]), lock=("x", "y", "z"))]
    standard = Problem(male50, ProblemSpec(targets))
    terms = [*Comfort.standard(male50, ComfortWeights()).terms, (5.0, ElbowStraight(male50))]
    problem = Problem(male50, ProblemSpec(targets, comfort=Comfort(terms)))
    elbow = male50.joint_index("elbow_r_flexion")
    x = problem.start()
    x[: male50.n] = 0.7 * male50.neutral + 0.3 * np.clip(0.5 * (male50.lower + male50.upper), -1, 1)  # inside ranges
    x[elbow] = 0.4
    numeric = finite_difference(lambda xx: [problem.comfort.value(problem.state(xx))], x)[0]
    atol = 1e-7 * np.abs(numeric).max()
    np.testing.assert_allclose(problem.comfort.gradient(problem.state(x)), numeric, rtol=1e-5, atol=atol)
    plain, straight = solve(standard), solve(problem)
    assert plain.converged and straight.converged and "elbow" in straight.comfort_parts
    assert abs(straight.theta[elbow]) < abs(plain.theta[elbow])
