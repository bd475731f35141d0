"""Priorities: an unreachable reach target ends as close as it can get with the feet on their targets and the body in
balance (recomputed independently), the result says which target is short and by how much, and only what truly
cannot hold (a load no stance can take) is reported broken."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from helpers import finite_difference
from physics_check import G, check_physics
from scipy.optimize import minimize

from solver import load_scenario, solve
from solver.constraints import FrameGroup
from solver.errors import ManikinError, ScenarioError
from solver.io.scenario.bodies import load_body
from solver.io.scenario.write import dumps_scenario, scenario_to_dict
from solver.iteration import StopReason
from solver.problem.priorities import REACH_WEIGHT, ReachShortfall, ranked
from solver.problem.problem import ExternalLoad, Problem, ProblemSpec, Target

PLANTED = ("x", "y", "z", "rx", "ry", "rz")


@pytest.fixture(scope="module")
def male50():
    return load_body(preset="male_50")


def planted_feet(model) -> list[Target]:
    zero = model.forward(model.zero_pose())
    out = []
    for name in ("foot_r", "foot_l"):
        position = zero.tcp_frame(model.tcp(name))[1]
        out.append(Target(name, position, lock=PLANTED, support=True))
    return out


def reach(model, point, **kwargs) -> Problem:
    hand = Target("hand_r", np.asarray(point, float), lock=("x", "y", "z"), **kwargs)
    return Problem(model, ProblemSpec([*planted_feet(model), hand]))


def hand_position(result) -> np.ndarray:
    model = result.problem.model
    return model.forward(result.theta).tcp_frame(model.tcp("hand_r"))[1]


def check_held(result) -> None:
    """Feet on their targets and balance, recomputed by the physics check on the result without its reach targets."""
    problem = result.problem
    hard = [t for t in problem.targets if t.effective_priority == 1]
    held = Problem(problem.model, ProblemSpec(hard, problem.loops, problem.load_specs, problem.balance))
    check_physics(dataclasses.replace(result, problem=held))


def test_reach_shortfall_derivatives_match_finite_differences(male50):
    """Gradient against differences of the cost; curvature rows R against J^T H J with J and H both by differences
    (J of the scaled errors, H of the smooth distance in the errors themselves)."""
    targets = [
        Target("hand_r", np.array([-0.3, -0.6, 1.2]), lock=PLANTED),
        Target("hand_l", np.array([0.4, -0.2, 0.9]), lock=("x", "z"), weight=2.0),
    ]
    problem = Problem(male50, ProblemSpec([*planted_feet(male50), *targets]))
    term = ReachShortfall(FrameGroup(problem.target_constraints[2:]))
    rng = np.random.default_rng(3)
    x = problem.start() + np.r_[rng.uniform(-0.2, 0.2, male50.n), np.zeros(problem.n_x - male50.n)]
    x[:3] = 0.0
    state = problem.state_of_x(x)
    assert term.cost(state) > 100.0  # far off: the distance-like regime
    grad, curv = term.derivatives(state, 1.0)
    np.testing.assert_allclose(grad, finite_difference(lambda v: term.cost(problem.state_of_x(v)), x), rtol=1e-5,
                               atol=1e-3 * np.abs(grad).max())  # fmt: skip
    assert not curv.any()
    jac = finite_difference(lambda v: term.scaled_error(problem.state_of_x(v)), x)
    e = term.scaled_error(state)
    sizes = [6, 2]

    def smooth_distance_gradient(err: np.ndarray) -> np.ndarray:  # d/de of sum_t sqrt(1 + |e_t|^2) - 1
        parts = np.split(err, np.cumsum(sizes)[:-1])
        return np.concatenate([p / np.sqrt(1.0 + p @ p) for p in parts])

    hess = finite_difference(smooth_distance_gradient, e, 1e-3)
    rows = term.curvature_rows(state, 2.5)
    expected = 2.5 * jac.T @ (0.5 * (hess + hess.T)) @ jac
    np.testing.assert_allclose(rows.T @ rows, expected, atol=1e-3 * np.abs(expected).max())


def test_a_reach_too_far_keeps_the_feet_and_the_balance(male50):
    """The 1.6 m forward reach of the issue: before priorities a foot ended 165 mm off and balance 71 N off."""
    target = np.array([-0.2, -1.6, 1.0])
    result = solve(reach(male50, target))
    assert not result.converged and result.unmet == ["hand_r"]
    assert result.broken == [] and result.stop is StopReason.CLOSEST
    check_held(result)
    distance = float(np.linalg.norm(hand_position(result) - target))
    assert result.shortfall["hand_r"]["position_m"] == pytest.approx(distance, abs=1e-9)
    assert 0.2 < distance < 0.6
    assert f"short: hand_r by {distance * 1e3:.1f} mm" in result.summary()
    assert "held: supports, loops, balance and clearances" in result.summary()


def test_a_target_999_m_away_does_not_lift_the_body(male50):
    """It lifted the whole body about 9 m into the air; now the hand reaches forward as far as balance allows."""
    result = solve(reach(male50, [-0.2, -999.0, 1.0]))
    check_held(result)
    pelvis = male50.forward(result.theta).tcp_frame(male50.tcp("pelvis"))[1]
    assert 0.6 < pelvis[2] < 1.2
    assert hand_position(result)[1] < -0.8  # reached forward (front is -y)
    assert all(np.isfinite(v) for v in result.residuals.values())


@pytest.mark.parametrize("point", [[-0.2, -1.6, 1.0], [0.9, -0.9, 2.3], [0.0, -0.3, 3.5]])
def test_no_nearby_pose_that_holds_the_feet_and_balance_does_better(male50, point):
    """From the answer, SLSQP minimises the same ranked objective (100 per millimetre of shortfall, plus comfort)
    under the same priority-1 rows and bounds; where it still holds them, it gains less than 4 mm's worth."""
    problem = reach(male50, point)
    result = solve(problem)
    check_held(result)
    hard = ranked(problem)
    scale = hard.scale

    def at(z):
        return hard.state(z * scale)

    z0 = hard.to_variables(result.x) / scale
    bounds = list(zip(hard.bounds.lower / scale, hard.bounds.upper / scale, strict=True))
    better = minimize(
        lambda z: -hard.comfort.value(at(z)), z0, jac=lambda z: -hard.comfort_derivatives(at(z))[0] * scale,
        method="SLSQP", bounds=bounds, constraints=[{"type": "eq", "fun": lambda z: hard.scaled_error(at(z)),
                                                     "jac": lambda z: hard.scaled_jacobian(at(z))}],
        options={"maxiter": 100, "ftol": 1e-10},
    )  # fmt: skip
    assert np.abs(hard.scaled_error(at(better.x))).max() <= 1.0
    gained = hard.comfort.value(at(better.x)) - hard.comfort.value(at(z0))
    assert gained < 4.0 * REACH_WEIGHT, f"SLSQP gained {gained / REACH_WEIGHT:.2f} mm's worth"


def test_a_target_of_priority_1_is_held_like_a_support(male50):
    """A hand that must hold (priority 1) and cannot: nothing is traded for it, and the result says what broke."""
    result = solve(reach(male50, [-0.2, -1.6, 1.0], priority=1))
    assert not result.converged
    assert "hand_r" in result.broken
    assert "NOT held (priority 1)" in result.summary() and "hand_r" not in result.shortfall


def test_a_load_no_stance_can_hold_is_reported_broken(male50):
    """5 kN pulling the hand forward is beyond friction (0.6 x body weight): balance breaks, and the result says so."""
    problem = reach(male50, [-0.2, -0.5, 1.0])
    pull = ExternalLoad("hand_r", np.array([0.0, -5000.0, 0.0]))
    loaded = Problem(male50, ProblemSpec(problem.targets, loads=[pull]))
    result = solve(loaded)
    assert not result.converged and "balance" in result.broken
    assert "NOT held (priority 1): " in result.summary()
    assert np.isfinite(result.x).all()


def test_a_reachable_target_is_met_exactly_as_before(male50):
    result = solve(reach(male50, [-0.25, -0.45, 1.1]))
    assert result.converged and result.stop is StopReason.CONVERGED and not result.shortfall
    check_physics(result)
    assert abs(result.com[2] + G[2] * 0) > 0  # a real pose, not the start


def test_priority_must_be_1_or_2(male50):
    with pytest.raises(ManikinError, match="priority must be 1"):
        reach(male50, [0.0, -0.5, 1.0], priority=3)


def test_the_scenario_file_reads_and_writes_priority(tmp_path):
    base = load_scenario("presets/scenarios/box_lift.toml")
    text = dumps_scenario(scenario_to_dict(base.problem, {"preset": "male_50"}))
    assert "priority" not in text  # only what was set is written
    path = tmp_path / "p.toml"
    path.write_text(text.replace('tcp = "hand_r"', 'tcp = "hand_r"\npriority = 1', 1))
    scenario = load_scenario(path)
    assert [t.priority for t in scenario.problem.targets][:2] == [1, None]
    assert "priority = 1" in dumps_scenario(scenario_to_dict(scenario.problem, {"preset": "male_50"}))
    path.write_text(text.replace('tcp = "hand_r"', 'tcp = "hand_r"\npriority = "high"', 1))
    with pytest.raises(ScenarioError, match=r"priority: expected 1 \(must hold\) or 2"):
        load_scenario(path)


def test_ergo_flags_frames_that_did_not_converge(male50, tmp_path):
    """ergo scores the closest pose but says, in the JSON, the CSV and its summary, that it is not a converged one;
    where balance broke it calls the loads not physical instead of printing them."""
    from solver import write_result
    from solver.ergonomics import ErgoOptions, run
    from solver.ergonomics.report import summary_lines

    short = solve(reach(male50, [-0.2, -1.6, 1.0]))
    loaded = reach(male50, [-0.2, -0.5, 1.0])
    pull = ExternalLoad("hand_r", np.array([0.0, -5000.0, 0.0]))
    broken = solve(Problem(male50, ProblemSpec(loaded.targets, loads=[pull])))
    fine = solve(reach(male50, [-0.25, -0.45, 1.1]))
    path = write_result(tmp_path / "r.json", [(1, fine), (2, short), (3, broken)])
    report = run(path, tmp_path / "r_ergo.json", ErgoOptions(), plots=False)
    assert report["not_converged"] == [2, 3] and report["not_held"] == [3]
    status = [f["status"] for f in report["frames"]]
    assert status[:2] == ["converged", "out of reach: hand_r"]
    assert status[2].startswith("NOT held: ") and "balance" in status[2]
    csv_text = (tmp_path / "r_ergo.csv").read_text()
    assert ",out of reach: hand_r," in csv_text and ',"NOT held: ' in csv_text
    lines = summary_lines(report)
    assert "[NOT converged: out of reach: hand_r]" in lines[1]
    assert "L4/L5 not physical" in lines[2]
    assert any(line.startswith("NOT converged: 2 of 3 frames [2, 3]") for line in lines)
