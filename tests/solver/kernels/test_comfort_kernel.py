"""The comfort terms' compiled loops (joint load, joint range, trunk tilt, contact spread) give the NumPy code's
costs, gradients and curvature models to rounding, at random poses and contact forces, with the behaviour model
on (trunk weight 5: the range term's posture tables) and off (trunk weight 0); on the same kinematics, to the bit
(asserted to 1e-15)."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import states_on_one_kinematics

from solver import Problem, ProblemSpec, Target
from solver.comfort import BEHAVIOUR, STANDARD
from solver.io.scenario.bodies import load_body

pytest.importorskip("numba")

from solver import kernels  # noqa: E402 (after the skip: these tests are about the compiled path)


def _problem(model, weights) -> Problem:
    zero = model.forward(model.zero_pose())
    feet = [Target(f, zero.tcp_frame(model.tcp(f))[1], support=True) for f in ("foot_r", "foot_l")]
    hand = Target("hand_r", np.array([-0.2, -0.45, 0.9]), lock=("x", "y", "z"), support=True)
    return Problem(model, ProblemSpec([*feet, hand], balance=True, comfort_weights=weights))


def _close(got, expected) -> None:
    """Equal to rounding: 1e-11 of the array's size (each path's own forward kinematics, which differ in the last
    bits, and the joint loads and their squared contractions with them)."""
    got, expected = np.asarray(got, dtype=float), np.asarray(expected, dtype=float)
    assert got.shape == expected.shape
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-11 * max(1.0, float(np.abs(expected).max())))


def _both(evaluate, *args):
    """``evaluate(*args)`` with the NumPy code, then with the compiled loops."""
    with kernels.using(False):
        reference = evaluate(*args)
    with kernels.using(True):
        compiled = evaluate(*args)
    return reference, compiled


@pytest.mark.parametrize("preset", ["male_50", "female_5"])
@pytest.mark.parametrize("weights", [BEHAVIOUR, STANDARD], ids=["trunk5", "trunk0"])
def test_every_terms_cost_and_derivatives_match_the_numpy_code(preset: str, weights) -> None:
    model = load_body(preset=preset)
    problem = _problem(model, weights)
    assert problem.contacts.n_vars > 0  # the contact term and the loads' force block see forces
    names = {term.name for weight, term in problem.comfort.terms if weight}
    assert {"range", "load", "contact"} <= names and ("trunk" in names) == (weights is BEHAVIOUR)
    rng = np.random.default_rng(11)
    for _ in range(4):
        theta = np.clip(rng.normal(0.0, 0.6, model.n), model.lower, model.upper)
        theta[: model.n // 3] += rng.normal(0.0, 1.5, model.n // 3)  # some joints past their limits: the linear tail
        w = rng.uniform(0.0, 400.0, problem.contacts.n_vars)
        x = np.concatenate([theta, w])
        for weight, term in problem.comfort.terms:
            if not weight:
                continue
            cost = _both(lambda t, xx: t.cost(problem.state(xx)), term, x)
            _close(cost[1], cost[0])
            (g0, c0), (g1, c1) = _both(lambda t, xx, wt: t.derivatives(problem.state(xx), wt), term, x, weight)
            _close(g1, g0)
            _close(c1, c0)
        value = _both(lambda xx: problem.comfort.value(problem.state(xx)), x)
        _close(value[1], value[0])
        (g0, c0), (g1, c1) = _both(lambda xx: problem.comfort.derivatives(problem.state(xx)), x)
        _close(g1, g0)
        _close(c1, c0)


def _exact(got, expected) -> None:
    """Equal to 1e-15 of the array's size (the loops sum in the NumPy code's order: here, to the bit)."""
    got, expected = np.asarray(got, dtype=float), np.asarray(expected, dtype=float)
    assert got.shape == expected.shape
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-15 * max(1.0, float(np.abs(expected).max())))


@pytest.mark.parametrize("preset", ["male_50", "female_5"])
@pytest.mark.parametrize("weights", [BEHAVIOUR, STANDARD], ids=["trunk5", "trunk0"])
def test_on_the_same_kinematics_every_term_gives_the_numpy_numbers(preset: str, weights) -> None:
    """Costs, gradients and curvatures equal the NumPy code's to 1e-15 (np.tan and the BLAS dots are NumPy's on both
    paths), so the comfort does not pull the two paths' iterates apart on rounding."""
    model = load_body(preset=preset)
    problem = _problem(model, weights)
    rng = np.random.default_rng(13)
    for _ in range(4):
        theta = np.clip(rng.normal(0.0, 0.6, model.n), model.lower, model.upper)
        theta[: model.n // 3] += rng.normal(0.0, 1.5, model.n // 3)  # some joints past their limits: the linear tail
        x = np.concatenate([theta, rng.uniform(0.0, 400.0, problem.contacts.n_vars)])
        reference, compiled = states_on_one_kinematics(problem, x)
        for flag, state in ((False, reference), (True, compiled)):
            with kernels.using(flag):
                state.cache["out"] = [problem.comfort.value(state), *problem.comfort.derivatives(state)]
                for weight, term in problem.comfort.terms:
                    if weight:
                        state.cache["out"] += [term.cost(state), *term.derivatives(state, weight)]
        for got, expected in zip(compiled.cache["out"], reference.cache["out"], strict=True):
            _exact(got, expected)


@pytest.mark.parametrize("posture", [False, True])
def test_the_range_terms_per_joint_values_slopes_and_curvatures_match(posture: bool) -> None:
    from solver.comfort import JointRange

    model = load_body(preset="male_50")
    term = JointRange(model, posture)
    rng = np.random.default_rng(5)
    for _ in range(5):
        lower, upper = np.nan_to_num(model.lower, neginf=-2.0), np.nan_to_num(model.upper, posinf=2.0)
        theta = rng.uniform(lower - 0.3, upper + 0.3)  # inside, near and past the walls
        for derivatives in (False, True):
            reference, compiled = _both(term.per_joint, theta, derivatives)
            assert len(compiled) == len(reference) == (3 if derivatives else 1)
            for got, expected in zip(compiled, reference, strict=True):
                _exact(got, expected)


@pytest.mark.parametrize("count", [0, 3, 7, 8, 9, 16, 31, 128])
def test_the_contact_cost_sums_as_np_sum(count: int) -> None:
    """In order below eight terms, in np.sum's eight lanes from eight to 128 (the term takes NumPy's sum beyond)."""
    from solver.kernels.comfort import contact_cost

    w = np.random.default_rng(count).uniform(0.0, 500.0, count)
    _exact(contact_cost(w, 700.0), np.sum((w / 700.0) ** 2))


def test_the_trunk_term_at_weight_zero() -> None:
    from solver.comfort import TrunkTilt

    model = load_body(preset="male_50")
    problem = _problem(model, BEHAVIOUR)
    term = TrunkTilt(model)
    x = problem.start(np.clip(np.random.default_rng(2).normal(0.0, 0.5, model.n), model.lower, model.upper))
    (g0, c0), (g1, c1) = _both(lambda: term.derivatives(problem.state(x), 0.0))
    assert not np.any(g1) and not np.any(c1) and g1.shape == g0.shape == (len(x),)


def test_the_compiled_path_runs_the_loops_and_the_numpy_path_does_not(monkeypatch) -> None:
    """Every standard term (gaze aside) takes its loop when kernels are on: the comparisons above compare two paths."""
    from solver.comfort import contact_spread, joint_load, joint_range, trunk_tilt

    with kernels.using(True):
        if not kernels.active():
            pytest.skip("compiled kernels are off in this process (MANIKIN_KERNELS=numpy)")
    calls: list[str] = []
    loops = {joint_load: ("load_strains", "load_factors"),
             joint_range: ("range_angles", "range_per_joint", "weighted_pair"),
             trunk_tilt: ("trunk_derivatives",), contact_spread: ("contact_cost", "contact_derivatives")}  # fmt: skip
    for module, names in loops.items():
        for name in names:
            loop = getattr(module, name)
            monkeypatch.setattr(module, name, lambda *args, loop=loop, name=name: calls.append(name) or loop(*args))
    model = load_body(preset="male_50")
    problem = _problem(model, BEHAVIOUR)
    x = problem.start()
    with kernels.using(False):
        problem.comfort.value(problem.state(x)), problem.comfort.derivatives(problem.state(x))
    assert calls == []
    with kernels.using(True):
        problem.comfort.value(problem.state(x)), problem.comfort.derivatives(problem.state(x))
    assert sorted(set(calls)) == sorted(["load_strains", "load_factors", "range_angles", "range_per_joint",
                                         "weighted_pair", "trunk_derivatives", "contact_cost",
                                         "contact_derivatives"])  # fmt: skip
