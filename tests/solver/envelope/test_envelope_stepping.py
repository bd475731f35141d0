"""Reach envelopes with stepping feet (``--feet step``): each sole stays flat on the floor and inside its stance
bounds, the reach is never shorter than with the feet planted (per ray and over a coarse sphere), and the pose at the
reach is in static balance, checked here from the solved contact forces and the body's masses alone."""

from __future__ import annotations

import numpy as np
import pytest

from solver import load_preset, solve
from solver.envelope import direction_sphere, reach_row, search_ray, sweep_envelope
from solver.envelope.reach import reach_setup
from solver.stance.limits import ROWS, StanceBounds, stance_limits

G = 9.81
FEET = ("foot_l", "foot_r")
DIRECTIONS = {"ahead": (0.0, -1.0, 0.0), "out right, low": (-1.0, 0.0, -0.4), "behind across": (0.3, 1.0, -0.3)}


@pytest.fixture(scope="module")
def model():
    return load_preset("male_50")


def test_the_stance_rows_derivatives_match_finite_differences(model):
    problem = reach_setup(model, "right", feet="step").problem(np.array([-0.2, -1.2, 1.3]))
    rows = next(c for c in problem.constraints if isinstance(c, StanceBounds))
    x = problem.to_x(problem.start(None)).copy()
    x[: model.n] += np.random.default_rng(3).normal(0.0, 0.2, model.n)
    g0, jac = rows.value(problem.state_of_x(x)), rows.value_jacobian(problem.state_of_x(x))
    for i in range(model.n):
        shifted = x.copy()
        shifted[i] += 1e-6
        numeric = (rows.value(problem.state_of_x(shifted)) - g0) / 1e-6
        assert np.allclose(jac[:, i], numeric, atol=2e-5), (model.joint_names[i], jac[:, i], numeric)
    assert rows.rows == len(ROWS) and rows.value(problem.state_of_x(problem.start(None))).min() > 0.0  # start: met


def stance_of(model, pose: np.ndarray) -> dict:
    """Where each sole is in ``pose``: (rotation, position) by foot."""
    kin = model.forward(pose)
    return {f: kin.tcp_frame(model.tcp(f)) for f in FEET}


def assert_within_bounds(model, pose: np.ndarray) -> None:
    """Both soles flat on the floor, each within a step of its start, turned at most the limit, a step apart at
    most and not crossed (1 mm, 0.25 degree: the targets' tolerances)."""
    limits = stance_limits(model)
    start, now = stance_of(model, model.zero_pose()), stance_of(model, pose)
    for f in FEET:
        rotation, position = now[f]
        assert abs(position[2]) < 1e-3 and rotation[2, 2] > np.cos(np.radians(0.25)), f"{f} is not flat on the floor"
        assert np.linalg.norm((position - start[f][1])[:2]) <= limits.step + 1e-3
        turn = np.degrees(np.arccos(np.clip(rotation[:, 1] @ start[f][0][:, 1], -1.0, 1.0)))
        assert turn <= np.degrees(limits.yaw) + 0.2
    apart = now["foot_l"][1] - now["foot_r"][1]
    assert np.linalg.norm(apart[:2]) <= limits.step + 1e-3
    for f in FEET:  # the left foot on the left of the right one, seen across either sole
        assert apart @ now[f][0][:, 0] >= limits.width - 1e-3


def assert_in_balance(model, result, hand_point: np.ndarray, load_kg: float) -> None:
    """The contact forces carry the body's weight and the load, and their moments about the world origin cancel
    the weights' (within the balance rows' tolerance, 1 N and 0.1 N*m; the body's centre of mass from its links'
    masses, not the solver's statics)."""
    kin = result.state.kin
    com = (model.mass @ kin.com) / model.mass.sum()
    weight = np.array([0.0, 0.0, -model.mass.sum() * G])
    load = np.array([0.0, 0.0, -load_kg * G])
    forces = sum(np.asarray(c["force"]) for c in result.contacts)
    assert np.allclose(forces, -(weight + load), atol=1.0), (forces, weight + load)
    moments = sum(np.cross(c["point"], c["force"]) + np.asarray(c["moment"]) for c in result.contacts)
    moments += np.cross(com, weight) + np.cross(hand_point, load)  # the load hangs from the hand
    assert np.allclose(moments, 0.0, atol=0.1), moments
    for c in result.contacts:  # every sole pushes (never pulls; one may carry nothing) with its centre of pressure
        rotation, position = kin.tcp_frame(model.tcp(c["tcp"]))  # under it
        assert c["force"][2] >= 0.0
        local = rotation.T @ (np.asarray(c["point"]) - position)
        corners = model.tcp(c["tcp"]).sole
        assert corners[:, 0].min() - 1e-6 <= local[0] <= corners[:, 0].max() + 1e-6
        assert corners[:, 1].min() - 1e-6 <= local[1] <= corners[:, 1].max() + 1e-6


@pytest.mark.parametrize("load_kg", [0.0, 10.0])
@pytest.mark.parametrize("way", list(DIRECTIONS))
def test_a_stepping_reach_is_farther_in_bounds_and_in_balance(model, way, load_kg):
    d = np.array(DIRECTIONS[way]) / np.linalg.norm(DIRECTIONS[way])
    planted = search_ray(reach_setup(model, "right", load_kg), d, 0.5)
    setup = reach_setup(model, "right", load_kg, feet="step")
    stepping = search_ray(setup, d, planted.radius, planted.pose, known=True)
    assert planted.reached and stepping.radius >= planted.radius + 0.2  # a step takes the hand well farther
    point = setup.shoulder + stepping.radius * d
    result = solve(setup.problem(point), stepping.pose)  # solved again, comfort on, from the search's pose
    assert result.converged and not result.broken, result.verdict()
    assert np.linalg.norm(result.state.kin.tcp_frame(model.tcp("hand_r"))[1] - point) < 2e-3
    assert_within_bounds(model, result.state.theta)
    assert_in_balance(model, result, point, load_kg)


def test_a_far_reach_ahead_uses_the_whole_step(model):
    row = reach_row("male_50", DIRECTIONS["ahead"], feet="step")
    assert row["feet"] == "step" and row["reach_m"] >= row["planted_reach_m"] + 0.3
    moved = max(np.hypot(row[f"{f}_x"] - x0, row[f"{f}_y"]) for f, x0 in (("foot_l", 0.083), ("foot_r", -0.083)))
    assert 0.9 * stance_limits(model).step <= moved <= stance_limits(model).step + 1e-3  # the bound holds it
    planted = reach_row("male_50", DIRECTIONS["ahead"])
    assert planted["planted_reach_m"] == planted["reach_m"] == row["planted_reach_m"]
    assert (planted["foot_r_x"], planted["foot_r_y"]) == pytest.approx((-0.083, 0.0), abs=2e-3)  # planted: held
    assert abs(planted["foot_r_yaw_deg"]) < 0.25


@pytest.mark.slow  # two envelopes (12 directions, planted and stepping): ~10 s
def test_the_stepping_envelope_is_nowhere_smaller_than_the_planted_one(model):
    sphere = direction_sphere(1)
    planted = sweep_envelope(model, sphere, "right")
    stepping = sweep_envelope(model, sphere, "right", feet="step")
    assert np.all(stepping.balanced >= planted.balanced)
    assert np.array_equal(stepping.planted, planted.balanced)  # the planted search inside it is the same
    assert np.all(stepping.kinematic >= stepping.balanced)
    assert stepping.balanced.mean() > planted.balanced.mean() + 0.2
    for i in (0, 4, 9):  # every stepping pose keeps the soles in bounds
        assert_within_bounds(model, np.array(stepping.poses["balanced"][i]))
