"""Self-collision (issue 20): the documented pair list, exact Jacobians against finite differences, the zero pose
allowed, and a reach across the body that would drive the forearm through the trunk kept outside it."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import finite_difference

from solver import solve
from solver.collision.body import capsules_of
from solver.collision.self_pairs import REACHING, SHANKS, THIGHS, self_pairs
from solver.io.scenario.bodies import load_body
from solver.problem.problem import Problem, ProblemSpec, Target


@pytest.fixture(scope="module")
def male50():
    return load_body(preset="male_50")


def feet(model) -> list[Target]:
    zero = model.forward(model.zero_pose())
    return [Target(f, zero.tcp_frame(model.tcp(f))[1], support=True) for f in ("foot_r", "foot_l")]


@pytest.mark.parametrize("preset", ["male_50", "female_5", "male_95"])
def test_every_human_has_the_documented_pairs_and_the_zero_pose_keeps_them(preset):
    model = load_body(preset=preset)
    capsules = capsules_of(model)
    pairs = self_pairs(model, capsules)
    names = [(capsules.names[i], capsules.names[j]) for i, j in zip(pairs.first, pairs.second, strict=True)]
    trunk = {"pelvis", "head", "l5", "t1", "t12"}
    for part in REACHING:
        others = {b for a, b in names if a == part}
        assert trunk | set(THIGHS) <= others and not others & {"upper_arm_r", "upper_arm_l", part}
    assert SHANKS in names and len(names) == len(set(names))
    assert (pairs.least <= 0).all() and pairs.least.min() > -0.05  # only the rough capsules' rest overlap
    problem = Problem(model, ProblemSpec(feet(model)))
    state = problem.state_of_x(problem.start())
    assert not problem.self_constraint.unmet(state)


def test_the_snake_has_no_pairs():
    snake = load_body(preset="snake")
    assert len(self_pairs(snake, capsules_of(snake))) == 0
    assert Problem(snake, ProblemSpec([Target("floor", np.zeros(3), support=True)])).self_constraint is None


def test_self_clearance_jacobian_matches_finite_differences(male50):
    """A random pose with arms folded into the body: several rows violated, the exact Jacobian of every row (met
    or not) equals the finite differences of the distances."""
    problem = Problem(male50, ProblemSpec(feet(male50)))
    rows = problem.self_constraint
    rng = np.random.default_rng(5)
    for _ in range(3):
        x = problem.start() + np.r_[rng.uniform(-0.8, 0.8, male50.n), np.zeros(problem.n_x - male50.n)]
        x = problem.x_bounds.clip(x)
        state = problem.state_of_x(x)
        value = rows.value(state)
        assert np.isfinite(value).all()
        jac = rows.value_jacobian(state)
        numeric = finite_difference(lambda v: rows.value(problem.state_of_x(v)), x, 1e-7)
        np.testing.assert_allclose(jac, numeric, atol=1e-5 * max(1.0, np.abs(jac).max()))
    assert (jac[:, : male50.n] != 0).any()


def test_a_reach_across_the_body_keeps_the_forearm_out_of_the_trunk(male50):
    """The right hand to a point behind the left hip: without self-collision the arm passes through the trunk;
    with it (the default) no pair is closer than allowed (recomputed from the capsules), feet and balance hold."""
    targets = [*feet(male50), Target("hand_r", np.array([0.12, 0.2, 0.95]), lock=("x", "y", "z"))]
    loose = solve(Problem(male50, ProblemSpec(targets, self_collision=False)))
    checked = Problem(male50, ProblemSpec(targets))
    before = checked.self_constraint.value(checked.state_of_x(loose.x)) - checked.self_constraint.floor
    assert before.min() < -0.03  # the free solve goes through the body
    result = solve(checked)
    assert result.broken == []
    capsules = capsules_of(male50)
    p0, p1 = capsules.world(male50.forward(result.theta))
    pairs = self_pairs(male50, capsules)
    for i, j, least in zip(pairs.first, pairs.second, pairs.least, strict=True):
        gap = _segment_gap(p0[i], p1[i], p0[j], p1[j]) - capsules.radius[i] - capsules.radius[j]
        assert gap >= least - 1e-3, (capsules.names[i], capsules.names[j], gap)
    assert any(c.other in {"pelvis", "l5", "l4", "l3", "l2", "l1", "thigh_l"} for c in result.problem.closest(
        result.state))  # fmt: skip


def _segment_gap(a0, a1, b0, b1, samples: int = 400) -> float:
    """Distance between two segments by dense sampling (independent of the solver's closed form), m."""
    s = np.linspace(0.0, 1.0, samples)[:, None]
    pa, pb = a0 + s * (a1 - a0), b0 + s * (b1 - b0)
    return float(np.min(np.linalg.norm(pa[:, None] - pb[None], axis=-1)))
