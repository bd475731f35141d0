"""The behaviour start's per-model values (standing hip, crouch, rested pose) are computed once and handed out as
copies: a caller that changes its start does not change the next solve's."""

from __future__ import annotations

import numpy as np
import pytest

from solver import load_scenario
from solver.errors import ManikinError
from solver.io.scenario.bodies import PRESETS_DIR, load_body
from solver.problem import starts


def test_poses_are_fresh_copies_of_the_once_computed_values() -> None:
    model = load_body(preset="male_50")
    for pose in (starts.rested_pose, starts.crouched_pose):
        first = pose(model)
        expected = first.copy()
        first += 1.0  # a caller's change of its own start
        again = pose(model)
        np.testing.assert_array_equal(again, expected)
        assert again is not pose(model)
    knee = model.joint_names.index("knee_r_flexion")
    assert starts.crouched_pose(model)[knee] > 0.5 and starts.rested_pose(model)[knee] == 0.0
    assert starts.crouched_pose(load_body(preset="snake")) is None
    assert 0.7 < starts._once(model, "hip", starts._standing_hip) < 1.2  # m: the standing hip joint's height


def _start_by_definition(problem, x0: np.ndarray) -> np.ndarray:
    """Problem.start as its docstring reads: joints (a crouch for the zero pose, if the behaviour model gives one) and
    the given forces or an even share of the weight, joined and clipped to x's bounds, then to the variables'."""
    n = problem.model.n
    theta = x0[:n]
    if not theta.any():
        crouch = starts.behaviour_start(problem)
        theta = theta if crouch is None else crouch
    if x0.shape[0] == problem.n_x and problem.contacts.n_vars:
        w = x0[n:]
    else:
        w = problem.contacts.even_weights(problem.body_weight - sum(float(ld.force[2]) for ld in problem.loads))
    return problem.bounds.clip(problem.to_variables(problem.x_bounds.clip(np.concatenate([theta, w]))))


def test_a_start_is_its_definition_and_a_copy() -> None:
    """Joints alone, joints and forces (in and out of bounds, -0.0 at a force's zero bound), the zero pose with and
    without forces: the start joins and clips as the definition, never the caller's own array; NaN or a wrong length
    is refused."""
    scenario = load_scenario(PRESETS_DIR / "scenarios" / "box_lift_motion.toml")
    problem = scenario.problem
    n, rng = problem.model.n, np.random.default_rng(4)
    full = problem.to_x(problem.start(scenario.start))
    wide = full.copy()
    wide[:n] += rng.uniform(-3.0, 3.0, n)  # joints past their limits
    wide[n:] = rng.uniform(-50.0, 900.0, len(wide) - n)
    wide[n] = -0.0
    zero = np.zeros(problem.n_x)
    zero[n:] = 30.0
    for x0 in (full, wide, full[:n], wide[:n], zero, np.zeros(n)):
        got = problem.start(x0)
        assert got is not x0 and not np.shares_memory(got, x0)
        assert got.tobytes() == _start_by_definition(problem, x0).tobytes()
    for bad in (np.full(n, np.nan), full[: n - 1]):
        with pytest.raises(ManikinError):
            problem.start(bad)
