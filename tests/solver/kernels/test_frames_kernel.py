"""A frame group's errors and Jacobian rows by the compiled kernels equal the NumPy path's to rounding: every lock
kind, relaxed axes (a general operator), several TCPs, loops, random poses and rotation errors near pi."""

from __future__ import annotations

import numpy as np
import pytest

from solver import kernels
from solver.body.reduction import DEFAULT_GROUPS
from solver.body.spatial import exp_so3
from solver.constraints import FrameConstraint, lock_operator
from solver.constraints.frame import FrameGroup
from solver.io.scenario.bodies import load_body
from solver.problem.problem import Loop, Problem, ProblemSpec, Target

pytest.importorskip("numba")

LOCKS = [("x", "y", "z", "rx", "ry", "rz"), ("x", "y", "z"), ("z", "rx", "ry"), ("rx", "ry", "rz"), ("ry",), ()]
# rotation errors: near pi on the symmetric-part branch (not pi itself: its axis sign is rounding's choice), just
# outside that branch, tiny, random. Near pi log_so3 amplifies a rounding of the relative rotation in either path:
# by 1 / sin(angle) through acos on the symmetric-part branch, by 1 / sin(angle)^2 through angle / sin(angle) just
# outside it (1e-8 at pi - 2e-4), so there the tolerance grows by that much.
ANGLES = [np.pi - 1e-6, np.pi - 5e-5, np.pi - 2e-4, 1e-8, None]


def _group(model, n_x: int, theta: np.ndarray, rng: np.random.Generator, angle: float | None) -> FrameGroup:
    """Hands, feet, head and a loop (left hand on the right), targets at ``angle`` (rad) from the TCPs' frames."""
    kin = model.forward(theta)
    members = []
    names = ["hand_r", "foot_l", "foot_r", "head", "pelvis", "knuckles_l"]
    for k, name in enumerate(names):
        tcp = model.tcp(name)
        rotation, position = kin.tcp_frame(tcp)
        axis = rng.normal(size=3)
        turn = rng.uniform(0.0, np.pi) if angle is None else angle
        target_rotation = rotation @ exp_so3(axis / np.linalg.norm(axis) * turn)
        operator = lock_operator(LOCKS[k]) if k < len(LOCKS) - 1 else rng.normal(size=(2, 6))  # relaxed axes
        position = position + rng.normal(scale=0.2, size=3)
        members.append(FrameConstraint(name, tcp, target_rotation, position, operator, n_x, weight=k + 1.0))
    loop_rotation = exp_so3(rng.normal(size=3))
    members.append(
        FrameConstraint(
            "loop", model.tcp("hand_l"), loop_rotation, rng.normal(scale=0.2, size=3),
            lock_operator(LOCKS[0]), n_x, reference=model.tcp("hand_r"),
        )
    )  # fmt: skip
    return FrameGroup(members)


def _evaluate(group: FrameGroup, problem: Problem, theta: np.ndarray, compiled: bool) -> dict[str, np.ndarray]:
    with kernels.using(compiled):
        state = problem.state_of_x(np.concatenate([theta, np.ones(problem.n_x - len(theta))]))
        values = group.evaluate(state)
        return {
            "errors": group.error(state),
            "full": values.full,
            "position": values.position,
            "target_rotation": values.target_rotation,
            "target_position": values.target_position,
            "jacobian": group.jacobian(state),
        }


@pytest.mark.parametrize("angle", ANGLES)
def test_the_kernels_give_the_numpy_errors_and_jacobian_rows(angle: float | None) -> None:
    model = load_body(preset="male_50")
    problem = Problem(model, ProblemSpec(balance=False))
    rng = np.random.default_rng(11)
    for _ in range(4):
        theta = rng.uniform(model.lower, model.upper)
        group = _group(model, problem.n_x, theta, rng, angle)
        near_pi = angle is not None and angle > 3.0
        condition = 1.0 if not near_pi else np.sin(angle) ** (-1 if np.pi - angle <= 1e-4 else -2)
        numpy_got, compiled_got = _evaluate(group, problem, theta, False), _evaluate(group, problem, theta, True)
        for name, expected in numpy_got.items():
            got = compiled_got[name]
            assert got.shape == expected.shape, name
            np.testing.assert_allclose(
                got, expected, rtol=0, atol=1e-12 * condition * max(1.0, np.abs(expected).max()), err_msg=name
            )
        assert not compiled_got["jacobian"][:, model.n :].any()  # the forces do not move a frame


@pytest.mark.parametrize("groups", [DEFAULT_GROUPS, ()])
def test_the_live_jacobian_through_the_reduction_is_the_numpy_one(groups: tuple[str, ...]) -> None:
    """Targets, a loop, balance and the floor: the live rows in the solver's scaled variables (the reduction's basis
    product and the scaling in one kernel), with and without a reduction."""
    model = load_body(preset="male_50")
    rng = np.random.default_rng(5)
    kin = model.forward(model.zero_pose())
    targets = [
        Target(name, kin.tcp_frame(model.tcp(name))[1] + rng.normal(scale=0.1, size=3), lock=lock, support=support)
        for name, lock, support in (
            ("foot_l", ("z", "rx", "ry"), True),
            ("foot_r", ("z", "rx", "ry"), True),
            ("hand_r", LOCKS[0], False),
        )  # fmt: skip
    ]
    loops = [Loop("hand_l", "hand_r", np.array([0.3, 0.0, 0.0]))]
    problem = Problem(model, ProblemSpec(targets, loops, reduction=groups, floor=True))
    for _ in range(4):
        v = problem.start() + rng.normal(scale=0.1, size=problem.n_var)
        got = {}
        for compiled in (False, True):
            with kernels.using(compiled):
                got[compiled] = problem.live_jacobian(problem.state(v))
        np.testing.assert_array_equal(got[True][0], got[False][0])
        expected = got[False][1]
        np.testing.assert_allclose(got[True][1], expected, rtol=0, atol=1e-12 * max(1.0, np.abs(expected).max()))


def test_the_point_rows_kernel_gives_the_numpy_jacobian_rows() -> None:
    """Kinematics.jacobian_rows (the clearance rows' points) and frame_jacobian: per-row points and masks, one point
    and one bool mask for all rows."""
    model = load_body(preset="male_50")
    rng = np.random.default_rng(8)
    for _ in range(4):
        theta = rng.uniform(model.lower, model.upper)
        links = rng.integers(0, model.n, size=7)
        points, rows_lin, rows_ang = rng.normal(size=(3, 7, 3))
        mask = model.descendant[:, links].T.astype(float)
        got = {}
        for compiled in (False, True):
            with kernels.using(compiled):
                kin = model.forward(theta)
                got[compiled] = [
                    kin.jacobian_rows(points, rows_lin, rows_ang, mask),
                    kin.jacobian_rows(points[0], rows_lin, np.zeros_like(rows_lin), mask),
                    kin.frame_jacobian(int(links[0]), points[0]),
                ]
        for expected, value in zip(got[False], got[True], strict=True):
            assert value.shape == expected.shape
            np.testing.assert_allclose(value, expected, rtol=0, atol=1e-12 * max(1.0, np.abs(expected).max()))
