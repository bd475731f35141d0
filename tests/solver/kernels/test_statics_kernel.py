"""The statics' compiled loops over the tree equal the NumPy prefix-sum version to rounding: subtree wrenches, axis
loads, balance error and Jacobian, moment derivatives, load Jacobian and contractions, and the joints' twists; on the
same kinematics they sum in the NumPy path's order, so they give its numbers to the bit (asserted to 1e-15)."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import random_tree, states_on_one_kinematics

from solver import kernels
from solver.body.spatial import exp_so3
from solver.io.scenario.bodies import load_body
from solver.problem.problem import ExternalLoad, Problem, ProblemSpec, Target

pytest.importorskip("numba")


def _random_tree_problem(seed: int, rng: np.random.Generator, supports: bool) -> Problem:
    """A random tree (prismatic root slides and a prismatic interior joint), two soles and a point support, a load."""
    model = random_tree(seed)
    targets = [
        Target(f"t{k}", rng.normal(size=3), exp_so3(rng.normal(size=3)), support=supports, friction=0.5)
        for k in range(3)
    ]
    loads = [ExternalLoad("t3", np.array([3.0, -2.0, -40.0]))] if supports else []
    return Problem(model, ProblemSpec(targets, (), loads, balance=supports, floor=False, self_collision=False))


def _box_lift(preset: str) -> Problem:
    """Both feet on the floor and a 20 kg box's weight split between the hands."""
    model = load_body(preset=preset)
    zero = model.forward(model.zero_pose())
    feet = [
        Target(f, zero.tcp_frame(model.tcp(f))[1], lock=("z", "rx", "ry"), support=True, friction=0.6)
        for f in ("foot_l", "foot_r")
    ]
    box = [ExternalLoad(f"hand_{s}", np.array([0.0, 0.0, -98.1])) for s in ("l", "r")]
    return Problem(model, ProblemSpec(feet, (), box, floor=False, self_collision=False))


def _everything(problem: Problem, x: np.ndarray, coef: np.ndarray, weight: np.ndarray) -> dict[str, np.ndarray]:
    state = problem.state(x)
    out = _statics_outputs(state, coef, weight)
    out["twist"], out["origin_velocity"] = state.kin.twist, state.kin.origin_velocity
    out["balance_d_theta"], out["balance_d_w"] = state.statics.balance_jacobian()
    out["load_d_theta"], out["load_d_w"] = state.statics.axis_load_jacobian()
    fresh = problem.state(x)  # the contractions and the twist first, as the comfort term and the frames ask
    out["contraction_linear_fresh"] = fresh.statics.axis_load_contractions(coef, weight)[0]
    out["origin_velocity_first"] = fresh.kin.origin_velocity
    return out


def _compare(problem: Problem, rng: np.random.Generator, poses: int = 4) -> None:
    model = problem.model
    for _ in range(poses):
        theta = np.clip(rng.uniform(-1.0, 1.0, model.n), model.lower, model.upper)
        x = np.concatenate([theta, rng.uniform(0.0, 50.0, problem.contacts.n_vars)])
        coef, weight = rng.normal(size=model.n), rng.random(model.n)
        with kernels.using(False):
            numpy_values = _everything(problem, x, coef, weight)
        with kernels.using(True):
            loop_values = _everything(problem, x, coef, weight)
        for name, expected in numpy_values.items():
            got = loop_values[name]
            assert got.shape == expected.shape, name
            scale = max(1.0, float(np.abs(expected).max(initial=0.0)))
            np.testing.assert_allclose(got, expected, rtol=0, atol=1e-12 * scale, err_msg=name)


def _statics_outputs(state, coef: np.ndarray, weight: np.ndarray) -> dict[str, np.ndarray]:
    statics = state.statics
    out = dict(
        axis_loads=statics.axis_loads(),
        balance_error=statics.balance_error(),
        sub_force=statics.sub_force,
        sub_outer=statics.sub_outer,
        corner_points=statics.corner_points,
        load_points=statics.load_points,
        moment_derivatives=statics.moment_derivatives(),
        balance_rows=statics.balance_rows(),
        edge_moment_arms=statics.edge_moment_arms,
    )
    out["contraction_linear"], out["contraction_squared"] = statics.axis_load_contractions(coef, weight)
    return out


@pytest.mark.parametrize("case", ["tree0", "tree1", "tree2", "male_50", "female_5"])
def test_on_the_same_kinematics_the_kernels_give_the_numpy_numbers(case: str) -> None:
    """The numbers that steer a solve (balance rows, joint loads, the comfort's contractions) equal the NumPy path's
    to 1e-15 of their size (here, to the bit), so the two paths' iterates do not drift apart on rounding."""
    rng = np.random.default_rng(60)
    problem = _random_tree_problem(int(case[-1]), rng, True) if case.startswith("tree") else _box_lift(case)
    model = problem.model
    for _ in range(4):
        theta = np.clip(rng.uniform(-1.0, 1.0, model.n), model.lower, model.upper)
        x = np.concatenate([theta, rng.uniform(0.0, 300.0, problem.contacts.n_vars)])
        coef, weight = rng.normal(size=model.n), rng.random(model.n)
        reference, compiled = states_on_one_kinematics(problem, x)
        with kernels.using(False):
            expected = _statics_outputs(reference, coef, weight)
        with kernels.using(True):
            got = _statics_outputs(compiled, coef, weight)
        for name, value in expected.items():
            assert got[name].shape == value.shape, name
            scale = max(1.0, float(np.abs(value).max(initial=0.0)))
            np.testing.assert_allclose(got[name], value, rtol=0, atol=1e-15 * scale, err_msg=name)


@pytest.mark.parametrize("seed", range(3))
def test_random_trees_with_soles_points_and_a_load(seed: int) -> None:
    rng = np.random.default_rng(40 + seed)
    _compare(_random_tree_problem(seed, rng, supports=True), rng)


def test_no_supports_and_no_loads() -> None:
    rng = np.random.default_rng(7)
    _compare(_random_tree_problem(5, rng, supports=False), rng, poses=2)


@pytest.mark.parametrize("preset", ["male_50", "female_5"])
def test_box_lift_on_the_human(preset: str) -> None:
    _compare(_box_lift(preset), np.random.default_rng(11))


def test_the_totals_keep_their_meaning_when_kernels_switch_between_calls() -> None:
    """A state built on one path answers every later question on that path, whatever the switch says then."""
    rng = np.random.default_rng(3)
    problem = _random_tree_problem(1, rng, supports=True)
    x = np.concatenate([np.zeros(problem.model.n), np.full(problem.contacts.n_vars, 10.0)])
    with kernels.using(False):
        state = problem.state(x)
        expected = state.statics.balance_jacobian()[0]
    with kernels.using(True):
        np.testing.assert_allclose(state.statics.balance_jacobian()[0], expected, rtol=0, atol=1e-12)
