"""Variable reduction x = phi(beta): the map, its Jacobian through the solver, bounds, scenario switch."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from conftest import finite_difference

from solver.bodies import load_body
from solver.errors import ScenarioError
from solver.problem import Problem, Target
from solver.reduction import GROUPS
from solver.scenario import load_scenario
from solver.solve import solve

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def male50():
    return load_body(preset="male_50")


def reach(model, groups=GROUPS):
    zero = model.forward(model.zero_pose())
    feet = [
        Target(f, zero.tcp_frame(model.tcp(f))[1], lock=("z", "rx", "ry"), support=True) for f in ("foot_l", "foot_r")
    ]
    hand = Target("hand_r", np.array([-0.2, -0.45, 1.1]), lock=("x", "y", "z"))
    return Problem(model, [*feet, hand], reduction=groups)


def test_groups_shrink_the_variables(male50):
    p = reach(male50)
    assert p.n_x - p.n_var >= 63 + 2 * 19  # 72 spine joints -> 9, 2 x 20 finger joints -> 1 each
    names = p.variable_names()
    assert {"lumbar_rx", "thoracic_ry", "cervical_rz", "grasp_l", "grasp_r"} <= set(names)
    assert names[:6] == list(male50.joint_names[:6])  # exterior joints first, unchanged


def test_phi_keeps_joints_inside_their_ranges(male50):
    p = reach(male50)
    rng = np.random.default_rng(0)
    for _ in range(20):
        v = rng.uniform(np.maximum(p.lower, -3), np.minimum(p.upper, 3))
        x = p.to_x(v)
        assert np.all(x >= p.x_lower - 1e-12) and np.all(x <= p.x_upper + 1e-12)
        np.testing.assert_allclose(p.to_variables(x), v, atol=1e-12)


def test_reduced_jacobian_and_gradient_match_finite_differences(male50):
    p = reach(male50)
    rng = np.random.default_rng(1)
    margin = np.minimum(0.01, 0.25 * (p.upper - p.lower))  # finite differences must stay inside the ranges
    v = np.clip(p.start() + rng.normal(scale=0.05, size=p.n_var), p.lower + margin, p.upper - margin)
    state = p.state(v)
    numeric = finite_difference(lambda vv: p.scaled_error(p.state(vv)), v) * p.scale[None, :]
    np.testing.assert_allclose(p.scaled_jacobian(state), numeric, atol=1e-4 * np.abs(numeric).max())
    grad, _ = p.comfort_derivatives(state)
    numeric_h = finite_difference(lambda vv: [p.comfort.value(p.state(vv))], v)[0]
    np.testing.assert_allclose(grad, numeric_h, rtol=1e-5, atol=1e-6)


def test_reduced_solve_meets_targets_and_couples_the_spine(male50):
    result = solve(reach(male50))
    assert result.converged, result.summary()
    theta = dict(zip(male50.joint_names, result.theta, strict=True))
    lumbar = [theta[f"l{i}_rx"] for i in range(1, 6)]
    np.testing.assert_allclose(lumbar, lumbar[0], atol=1e-12)  # equal ranges -> equal share
    assert all(abs(theta[f"{f}_r_mcp_abduction"]) < 1e-12 for f in ("index", "middle", "ring", "little"))


def test_scenario_switch(tmp_path):
    text = (ROOT / "presets/scenarios/box_lift.toml").read_text()
    for value, expected in (("true", GROUPS), ('["lumbar", "grasp"]', ("lumbar", "grasp")), ("false", ())):
        path = tmp_path / "s.toml"
        path.write_text(text.replace("reduction = false", f"reduction = {value}"))
        assert load_scenario(path).problem.reduction_groups == expected
    path.write_text(text.replace("reduction = false", 'reduction = ["shoulder"]'))
    with pytest.raises(ScenarioError, match="reduction"):
        load_scenario(path)
