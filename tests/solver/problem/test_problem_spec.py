"""ProblemSpec: what a problem is made of as one frozen value; Problem(model, spec), and the older argument forms
(the spec's fields as arguments) giving the same problem."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from solver import ExternalLoad, Loop, Problem, ProblemSpec, Target, scenario_to_dict
from solver.collision import Box
from solver.comfort import Comfort, ComfortWeights
from solver.errors import ScenarioError
from solver.io.scenario.bodies import load_body
from solver.problem.priorities import ranked


@pytest.fixture(scope="module")
def male50():
    return load_body(preset="male_50")


def _pieces(model):
    zero = model.forward(model.zero_pose())
    feet = [Target(f, zero.tcp_frame(model.tcp(f))[1], support=True) for f in ("foot_r", "foot_l")]
    hand = Target("hand_r", np.array([-0.25, -0.45, 1.1]), lock=("x", "y", "z"))
    loop = Loop("hand_l", "hand_r", np.array([0.3, 0.0, 0.0]))
    load = ExternalLoad("hand_r", np.array([0.0, 0.0, -50.0]))
    table = Box([0.0, -0.6, 0.7], [1.0, 0.4, 0.05], name="table")
    return [*feet, hand], [loop], [load], table


def test_a_spec_is_a_frozen_value_of_tuples(male50) -> None:
    targets, loops, loads, table = _pieces(male50)
    spec = ProblemSpec(targets, loops, loads, obstacles=[table], reduction=["lumbar"])
    assert spec.targets == tuple(targets) and spec.loops == tuple(loops) and spec.obstacles == (table,)
    assert spec.reduction == ("lumbar",) and spec.comfort is None and spec.weights == ComfortWeights()
    with pytest.raises(dataclasses.FrozenInstanceError):
        spec.balance = False  # type: ignore[misc]
    other = spec.replace(balance=False, targets=targets[:2])
    assert other.balance is False and other.targets == tuple(targets[:2]) and spec.balance is True


def _rows(problem: Problem, x: np.ndarray) -> np.ndarray:
    return problem.scaled_error(problem.state_of_x(x))


def test_the_older_argument_forms_make_the_same_spec_and_problem(male50) -> None:
    targets, loops, loads, table = _pieces(male50)
    weights = ComfortWeights(range=0.5)
    spec = ProblemSpec(targets, loops, loads, True, weights, ("lumbar",), obstacles=(table,), self_collision=False)
    new = Problem(male50, spec)
    positional = Problem(male50, targets, loops, loads, True, weights, ("lumbar",), obstacles=[table],
                         self_collision=False)  # fmt: skip
    named = Problem(male50, targets=targets, loops=loops, loads=loads, comfort_weights=weights, reduction=["lumbar"],
                    obstacles=[table], self_collision=False)  # fmt: skip
    x = new.to_x(new.start())
    for old in (positional, named):
        for field in dataclasses.fields(ProblemSpec):
            assert getattr(old.spec, field.name) == getattr(spec, field.name), field.name
        assert old.n_rows == new.n_rows and old.comfort.weights == weights
        np.testing.assert_array_equal(_rows(old, x), _rows(new, x))  # the same rows, built the same way
    bare = Problem(male50, balance=False)
    assert bare.spec.targets == () and bare.balance is False


def test_a_spec_takes_no_more_arguments(male50) -> None:
    with pytest.raises(TypeError, match="spec"):
        Problem(male50, ProblemSpec(), balance=False)


def test_with_targets_and_with_frames_keep_the_spec(male50) -> None:
    targets, _, _, _ = _pieces(male50)
    problem = Problem(male50, ProblemSpec(targets))
    moved_hand = dataclasses.replace(targets[2], position=np.array([-0.2, -0.5, 1.0]))
    moved = problem.with_targets([*targets[:2], moved_hand])  # same supports: the rows shared
    assert moved.spec.targets[2] is moved_hand and moved.all_targets[2] is moved_hand
    one_foot = problem.with_targets([targets[0], dataclasses.replace(targets[1], support=False), targets[2]])
    assert one_foot.spec.targets[1].support is False and one_foot.comfort is problem.comfort  # built again
    solo = ranked(problem)
    assert solo is not None and solo.spec.comfort is solo.comfort and solo.spec.targets == problem.spec.targets


def test_the_scenario_writer_reads_the_spec(male50) -> None:
    targets, loops, loads, table = _pieces(male50)
    problem = Problem(male50, ProblemSpec(targets, loops, loads, comfort_weights=ComfortWeights(contact=0.5),
                                          obstacles=[table], floor=False))  # fmt: skip
    data = scenario_to_dict(problem, {"preset": "male_50"})
    assert data["comfort"] == {"range": 1.0, "load": 1.0, "contact": 0.5, "trunk": 5.0, "gaze": 0.0}  # defaults
    assert data["floor"] == {"enabled": False} and [o["name"] for o in data["obstacles"]] == ["table"]
    assert len(data["targets"]) == 3 and len(data["loops"]) == 1 and len(data["loads"]) == 1
    own = Problem(male50, problem.spec.replace(comfort=Comfort([])))
    with pytest.raises(ScenarioError, match="comfort"):
        scenario_to_dict(own, {"preset": "male_50"})


@pytest.mark.parametrize("kernels_on", [True, False])
def test_moving_targets_gives_the_rows_of_a_problem_built_with_them(male50, kernels_on, monkeypatch) -> None:
    """A motion's next frame moves its targets only (with_targets keeps every constraint and moves the frame group):
    the rows and Jacobian are those of a problem built afresh with the moved targets, the loop's too; a changed lock
    builds the target rows again."""
    from solver import kernels

    monkeypatch.setattr(kernels, "active", lambda: kernels_on)
    targets, loops, _, _ = _pieces(male50)
    targets[2] = dataclasses.replace(targets[2], rotation=np.eye(3))
    problem = Problem(male50, ProblemSpec(targets, loops))
    x = problem.to_x(problem.start())
    problem.scaled_jacobian(problem.state_of_x(x))  # the group's kernel tables exist before the move
    turn = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    hand = dataclasses.replace(targets[2], position=np.array([-0.25, -0.45, 1.05]), rotation=turn)
    foot = dataclasses.replace(targets[0], position=targets[0].position + [0.01, 0.02, 0.0])
    for moved_targets in ([foot, targets[1], hand], [targets[0], targets[1], dataclasses.replace(hand, lock=("x",))]):
        moved = problem.with_targets(moved_targets)
        assert (moved.frames.loops is problem.frames.loops) == (moved_targets[2].lock == targets[2].lock)  # shared
        fresh = Problem(male50, ProblemSpec(moved_targets, loops))
        state, state_fresh = moved.state_of_x(x), fresh.state_of_x(x)
        np.testing.assert_allclose(moved.scaled_error(state), fresh.scaled_error(state_fresh), rtol=0, atol=1e-12)
        np.testing.assert_allclose(moved.scaled_jacobian(state), fresh.scaled_jacobian(state_fresh), rtol=0, atol=1e-9)
        assert moved.residuals(state) == pytest.approx(fresh.residuals(state_fresh), abs=1e-12)
    again = problem.with_targets(targets)  # back where it was: the first problem's rows
    np.testing.assert_allclose(again.scaled_error(again.state_of_x(x)), problem.scaled_error(problem.state_of_x(x)),
                               rtol=0, atol=1e-12)  # fmt: skip


def test_a_mirror_or_a_skewed_target_rotation_is_refused_when_built_and_when_moved(male50) -> None:
    from solver.errors import ManikinError

    targets, _, _, _ = _pieces(male50)
    targets[2] = dataclasses.replace(targets[2], rotation=np.eye(3))
    problem = Problem(male50, ProblemSpec(targets))
    for bad in (np.diag([1.0, 1.0, -1.0]), np.array([[1.0, 0.1, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])):
        wrong = [*targets[:2], dataclasses.replace(targets[2], rotation=bad)]
        with pytest.raises(ManikinError, match=r"target hand_r rotation: expected a rotation matrix"):
            Problem(male50, ProblemSpec(wrong))
        with pytest.raises(ManikinError, match=r"target hand_r rotation: expected a rotation matrix"):
            problem.with_targets(wrong)  # only the frame moved: checked all the same
