"""The compiled step (solver/kernels/bounded_step.py, and the loops of solver/kernels/step.py where it needs an
eigendecomposition) gives the NumPy path's step: on the iterates of real solves.

The whole-step kernel factors with its own loops and Numba's BLAS, so its sums run in another order than LAPACK's:
it agrees to what the step's conditioning allows. Measured on these calls: the NumPy path's own step moves by up to
1e-11 (task), 2e-10 (comfort) and 9e-9 relative (predicted gain) when the Jacobian is perturbed by 1e-15 relative;
the kernel differs from it by 6e-12, 7e-11 and 1e-8. The tolerances below sit one decade above; the element-wise
loops (the fallback) agree to 1e-12.
"""

from __future__ import annotations

import copy
import dataclasses
from pathlib import Path

import numpy as np
import pytest

from bench import random_targets as rt
from solver import SolverOptions, kernels, load_scenario, solve
from solver.io.scenario.bodies import load_body
from solver.iteration import TUNING, loop
from solver.iteration import step as step_module

pytest.importorskip("numba")

SCENARIOS = Path(__file__).resolve().parents[3] / "presets" / "scenarios"
FIELDS = ("task", "comfort", "free", "root_metric", "free_gradient", "multipliers")


@pytest.fixture(scope="module")
def step_calls() -> list[tuple]:
    """The arguments of every compute_step of a few random-benchmark solves (NumPy path), comfort on and off, and of
    two shipped scenarios whose clearance rows are watched (held on their floor by the step)."""
    model = load_body(preset=rt.PRESET)
    box = rt.workspace_box(model)
    balance, groups = rt.CONFIGS["physics + reduction"]
    calls: list[tuple] = []
    original = loop.compute_step

    def record(problem, at, lin, mu, radius, tuning, memory):
        calls.append((problem, at, lin, mu, radius, tuning, copy.copy(memory)))
        return original(problem, at, lin, mu, radius, tuning, memory)

    loop.compute_step = record
    try:
        with kernels.using(False):
            for level, seed in ((1, 7000), (4, 7001), (5, 7002)):
                problem = rt.trial_problem(model, rt.draw_targets(model, box, rt.LEVELS[level], seed), balance, groups)
                for comfort in (True, False):
                    solve(problem, options=SolverOptions(optimize_comfort=comfort, max_iterations=25))
            for name in ("cabinet_reach", "box_lift_high"):
                scenario = load_scenario(SCENARIOS / f"{name}.toml")
                solve(scenario.problem, scenario.start, scenario.options)
    finally:
        loop.compute_step = original
    return calls


def _both(call: tuple, tuning=None) -> tuple:
    problem, at, lin, mu, radius, default, memory = call
    args = (problem, at, lin, mu, radius, tuning or default, memory)
    with kernels.using(False):
        reference = step_module.compute_step(*args)
    with kernels.using(True):
        compiled = step_module.compute_step(*args)
    return reference, compiled


WHOLE = {"task": 1e-10, "comfort": 1e-9, "multipliers": 1e-10, "predicted_gain": 1e-7, "penalty": 1e-9}  # see above


def _assert_same(reference, compiled, tolerances: dict | None = None) -> None:
    tolerances = tolerances or {}
    for name in FIELDS:
        want, got = getattr(reference, name), getattr(compiled, name)
        assert got.shape == want.shape, name
        size = max(float(np.abs(want).max(initial=0.0)), 1.0)
        np.testing.assert_allclose(got, want, rtol=0, atol=tolerances.get(name, 1e-12) * size, err_msg=name)
    assert compiled.least_squares.uses_eigendecomposition == reference.least_squares.uses_eigendecomposition
    for name in ("predicted_gain", "saturated_gain", "penalty"):
        want, got = getattr(reference, name), getattr(compiled, name)
        floor = 1e-6 if name in tolerances else 1.0  # the whole step's gains: relative, down to small ones
        assert abs(got - want) <= tolerances.get(name, 1e-12) * max(abs(want), floor), name


@pytest.fixture
def whole_step_statuses(monkeypatch) -> list[int]:
    """What each call of the whole-step kernel returned (OK, or NEEDS_EIGEN: the element-wise loops took over)."""
    statuses: list[int] = []
    kernel = step_module.fused.bounded_step

    def counted(*args):
        statuses.append(kernel(*args))
        return statuses[-1]

    monkeypatch.setattr(step_module.fused, "bounded_step", counted)
    return statuses


def test_compiled_step_is_the_numpy_step(step_calls, whole_step_statuses) -> None:
    assert len(step_calls) > 20
    assert any(call[2].comfort_on for call in step_calls) and not all(call[2].comfort_on for call in step_calls)
    saturated = watched = trust = 0
    for call in step_calls:
        reference, compiled = _both(call)
        _assert_same(reference, compiled, WHOLE)
        saturated += reference.saturated_gain > 0.0
        problem, at, lin, _, radius = call[:5]
        watched += bool((problem.one_sided[lin.live] & (at.err[lin.live] == 0.0)).any())
        trust += float(np.linalg.norm(reference.task[reference.free])) > 0.99 * radius
    assert saturated and watched and trust  # saturation on bounds, watched clearance rows, the trust region bound
    assert whole_step_statuses.count(step_module.fused.OK) >= 0.9 * len(whole_step_statuses) > 0


def test_elementwise_loops_are_the_numpy_step(step_calls, monkeypatch) -> None:
    """Where the whole-step kernel needs an eigendecomposition, the element-wise loops give the NumPy step to 1e-12."""
    monkeypatch.setattr(step_module.fused, "bounded_step", lambda *args: step_module.fused.NEEDS_EIGEN)
    for call in step_calls[::2]:
        _assert_same(*_both(call))


def test_whole_step_without_rows_or_with_an_empty_row(step_calls) -> None:
    """No constraint rows at all (the step is comfort alone), and a row without any entry (it takes no part)."""
    for call in step_calls[:: max(len(step_calls) // 6, 1)]:
        problem, at, lin, *rest = call
        empty = dataclasses.replace(lin, jac=lin.jac[:0], live=lin.live[:0])
        _assert_same(*_both((problem, at, empty, *rest)), WHOLE)
        jac = lin.jac.copy()
        jac[0] = 0.0
        _assert_same(*_both((problem, at, dataclasses.replace(lin, jac=jac), *rest)), WHOLE)


def test_compiled_step_out_of_clamping_rounds(step_calls) -> None:
    """With one clamping round every step that leaves the bounds has its comfort part shortened instead."""
    tuning = dataclasses.replace(TUNING, clamping_rounds=1)
    for call in step_calls[::3]:
        _assert_same(*_both(call, tuning), WHOLE)


def test_comfort_scatter_follows_numpy_on_nan() -> None:
    """NumPy's largest |entry| of a comfort part with a NaN is NaN, so the part is not scaled (the step then replaces
    the NaN): the loop must not scale it either."""
    from solver.kernels.step import scatter_scaled

    free = np.array([True, False, True])
    out = np.array([0.0, 7.0, 0.0])
    scatter_scaled(np.array([np.nan, 10.0]), np.ones(2), free, out, 1.0)
    np.testing.assert_array_equal(out, [np.nan, 7.0, 10.0])
    out = np.array([0.0, 7.0, 0.0])
    scatter_scaled(np.array([1.0, 10.0]), np.array([1.0, 2.0]), free, out, 1.0)
    np.testing.assert_allclose(out, np.array([1.0, 7.0, 5.0]) / 7.0, rtol=1e-15)


def test_turn_share_is_the_line_search_turn_limit(step_calls) -> None:
    """turn_share (the far line search's joint turn limit in one loop) gives NumPy's largest |joint change| / limit
    for the steps of real solves, with the reduction (a basis) and without it (x itself), and keeps a NaN."""
    from solver.kernels.step import turn_share

    limit = np.where(step_calls[0][0].model.prismatic, TUNING.max_slide, TUNING.max_turn)
    reduced = unreduced = 0
    for problem, at, lin, *_ in step_calls[::2]:
        direction = np.random.default_rng(len(lin.live)).normal(size=problem.n_var)
        for change in (direction, at.x / problem.scale):
            move = np.abs(problem.joint_change(at.state, change * problem.scale)) / limit
            want = float(np.max(move, initial=0.0))
            got = turn_share(change, problem.scale, *problem.joint_supports(), limit)
            assert abs(got - want) <= 1e-12 * max(want, 1.0)
        reduced += problem.reduction is not None
        unreduced += problem.reduction is None
    assert reduced and unreduced
    problem = step_calls[0][0]
    change = np.ones(problem.n_var)
    change[int(problem.joint_supports()[0].max())] = np.nan
    assert np.isnan(turn_share(change, problem.scale, *problem.joint_supports(), limit))


def test_nearly_dependent_rows_take_the_eigendecomposition(step_calls, whole_step_statuses) -> None:
    """Two nearly equal rows make J J^T too ill-conditioned for Cholesky: the kernel says so, and the element-wise
    loops around LAPACK's eigendecomposition give the NumPy step to 1e-12."""
    for problem, at, lin, *rest in step_calls[::4]:
        jac = lin.jac.copy()
        jac[1] = jac[0] * (1.0 + 1e-4) + 1e-4 * jac[1]
        reference, compiled = _both((problem, at, dataclasses.replace(lin, jac=jac), *rest))
        assert reference.least_squares.uses_eigendecomposition
        _assert_same(reference, compiled)
    assert step_module.fused.NEEDS_EIGEN in whole_step_statuses


def test_null_space_newton_kernel_is_the_numpy_one() -> None:
    """The kernel's null-space Newton step against solver.iteration.curvature_memory's, with quasi-Newton columns
    whose Woodbury system is well posed, indefinite (some fall back to -q: not a descent direction) or singular."""
    from solver.iteration.curvature_memory import null_space_newton as reference
    from solver.kernels.bounded_step import null_space_newton

    rng = np.random.default_rng(38)
    fallbacks = 0
    for draw in range(200):
        k, rows = 40, 8
        basis = np.linalg.qr(rng.normal(size=(k, rows)))[0].T  # (rows, k), orthonormal rows
        grad, v = rng.normal(size=k), rng.normal(size=(k, 4))
        middle = np.diag(rng.uniform(0.05, 50.0, 4) * rng.choice((-1.0, 1.0), 4))
        if draw == 0:  # a singular Woodbury system: the plain projected gradient
            v, middle = np.zeros((k, 4)), np.zeros((4, 4))
        want = reference(grad, basis, (v, middle))
        q = grad - basis.T @ (basis @ grad)
        fallbacks += bool(np.allclose(want, -q, rtol=0, atol=1e-13))
        got = null_space_newton(np.ascontiguousarray(np.column_stack((grad, v))), np.ascontiguousarray(basis.T), middle)
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-9 * max(float(np.abs(want).max()), 1.0))
    assert 1 < fallbacks < 100  # the -q fallback and the Woodbury step both taken


def test_slack_is_measured_only_when_a_watched_row_is_pushed_that_far(step_calls, monkeypatch) -> None:
    """compute_step measures the watched rows' slack (>= 0) only when the step pushes one of them past -overshoot:
    where it skips, no row would have been held (what measuring gives), on both paths."""
    counted: list[int] = []
    measure = type(step_calls[0][0]).scaled_slack
    monkeypatch.setattr(
        type(step_calls[0][0]), "scaled_slack", lambda self, state: counted.append(1) or measure(self, state)
    )
    watched_calls = skipped = 0
    for compiled in (False, True):
        for problem, at, lin, mu, radius, tuning, memory in step_calls:
            watched = problem.one_sided[lin.live] & (at.err[lin.live] == 0.0) & lin.jac.any(axis=1)
            if not watched.any():
                continue
            watched_calls += 1
            before = len(counted)
            with kernels.using(compiled):
                step = step_module.compute_step(problem, at, lin, mu, radius, tuning, copy.copy(memory))
            if len(counted) > before:
                continue
            skipped += 1
            reach = lin.jac @ (step.task + step.comfort)
            slack = measure(problem, at.state)[lin.live]
            assert not (watched & (reach < -(slack + tuning.hold_overshoot))).any()
    assert watched_calls and skipped  # the shortcut taken (on main every watched call measured the slack)


def test_without_keeps_every_other_field(step_calls) -> None:
    """_without and the compiled watched rows build the Linearization themselves (no dataclasses.replace): every
    field but the rows' is carried, and the compiled one drops the rows NumPy's does."""
    problem, at, lin = next(call[:3] for call in step_calls if len(call[2].live) > 2)
    rows = np.zeros(len(lin.live), dtype=bool)
    rows[1] = True
    want = dataclasses.replace(lin, jac=lin.jac[~rows], live=lin.live[~rows])
    err = at.err.copy()
    err[lin.live] = 1.0  # no row watched but row 1: one-sided, met, with an entry
    err[lin.live[1]] = 0.0
    one_sided = np.zeros_like(problem.one_sided)
    one_sided[lin.live[1]] = True
    jac = lin.jac.copy()
    jac[1, 0] = 1.0
    want_compiled = dataclasses.replace(lin, jac=jac[~rows], live=lin.live[~rows])
    fake = type("Rows", (), {"one_sided": one_sided})()
    watched, released = step_module._watched_compiled(
        fake, dataclasses.replace(at, err=err), dataclasses.replace(lin, jac=jac)
    )
    np.testing.assert_array_equal(watched, rows)
    for kept, expected in ((step_module._without(lin, rows), want), (released, want_compiled)):
        for field in dataclasses.fields(step_module.Linearization):
            got, value = getattr(kept, field.name), getattr(expected, field.name)
            assert (got is value) or np.array_equal(got, value), field.name
