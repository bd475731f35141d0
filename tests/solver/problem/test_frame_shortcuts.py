"""The per-frame shortcuts of a motion's problem (issue 37): each gives what the longer way gives. A keyed target's
pose, the moved target and spec, the frame checks of moved targets only, the narrowed bounds and the per-frame steps
kept from the last frame."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from solver.body.spatial import exp_so3, matrix_to_quat, quat_to_matrix, slerp
from solver.errors import ManikinError
from solver.io.scenario.bodies import load_body
from solver.motion import frames
from solver.options import MotionLimits
from solver.problem.bounds import Bounds
from solver.problem.problem import Problem, ProblemSpec, Target
from solver.problem.specs import same_frame, validate, validate_frames
from solver.problem.tracks import Key, Track, targets_at


@pytest.fixture(scope="module")
def male50():
    return load_body(preset="male_50")


def _feet_and_hand(model) -> list[Target]:
    zero = model.forward(model.zero_pose())
    feet = [Target(f, zero.tcp_frame(model.tcp(f))[1], support=True) for f in ("foot_r", "foot_l")]
    return [*feet, Target("hand_r", np.array([-0.25, -0.45, 1.1]), np.eye(3), lock=("x", "y", "z"))]


def test_a_tracks_pose_is_the_slerp_of_its_keys_at_every_frame():
    """Rotating keys, two keys of one rotation (a half turn: its quaternion has zeros) and a key without rotation:
    the same numbers as interpolating each frame afresh (the comparison is exact: the same operations on the same
    numbers; a held rotation is the slerp's at every t, to the bit)."""
    turn, half = exp_so3([0.3, -0.2, 1.1]), np.diag([1.0, -1.0, -1.0])
    keys = (Key(0, np.zeros(3), np.eye(3)), Key(10, np.array([0.1, 0.2, 0.3]), turn), Key(20, np.ones(3), half),
            Key(30, np.array([0.5, 0.0, 1.0]), half), Key(40, np.zeros(3)))  # fmt: skip
    track = Track(0, keys)
    for frame in np.arange(-2.0, 43.0, 0.7):
        position, rotation = track.pose_at(frame)
        i = min(max(int(np.searchsorted([k.frame for k in keys], frame, side="right")) - 1, 0), len(keys) - 2)
        a, b = keys[i], keys[i + 1]
        t = min(max((frame - a.frame) / (b.frame - a.frame), 0.0), 1.0)
        if 0.0 < t < 1.0 and b.rotation is not None:
            assert np.array_equal(position, (1.0 - t) * a.position + t * b.position)
            expected = quat_to_matrix(slerp(matrix_to_quat(a.rotation), matrix_to_quat(b.rotation), t))
            assert np.array_equal(rotation, expected), frame
    targets = [Target("hand_r", np.zeros(3), lock=("x", "y"), weight=2.0), Target("hand_l", np.ones(3))]
    moved = targets_at(targets, [track], 15.0)
    assert moved[1] is targets[1]
    again = dataclasses.replace(targets[0], position=track.pose_at(15.0)[0], rotation=track.pose_at(15.0)[1])
    assert vars(moved[0]).keys() == vars(again).keys() and type(moved[0]) is Target
    for name, value in vars(again).items():
        assert np.array_equal(getattr(moved[0], name), value) if isinstance(value, np.ndarray) else \
            getattr(moved[0], name) == value, name  # fmt: skip


def test_a_tracks_position_blended_in_floats_is_numpys_blend():
    """At a frame given as a Python int or float (a motion's frames) the keyed position is blended in Python floats:
    to the bit NumPy's (1 - t) a + t b, a float64 3-vector; keys not all float64 3-vectors take NumPy's way."""
    rng = np.random.default_rng(7)
    floats = tuple(Key(f, rng.normal(scale=0.5, size=3)) for f in (0, 7, 9, 30, 1000))
    ints = (Key(0, np.array([0, 1, 2])), Key(10, np.array([3, -4, 5])))  # integer positions: NumPy's way

    def blend(keys: tuple[Key, ...], frame: float) -> np.ndarray:  # with NumPy, as the keys are
        if not keys[0].frame < frame < keys[-1].frame:
            return (keys[0] if frame <= keys[0].frame else keys[-1]).position
        i = max(i for i, k in enumerate(keys) if k.frame <= frame)
        t = (frame - keys[i].frame) / (keys[i + 1].frame - keys[i].frame)
        return (1.0 - t) * keys[i].position + t * keys[i + 1].position

    assert Track(0, floats)._floats is not None and Track(0, ints)._floats is None
    for keys in (floats, ints):
        track = Track(0, keys)
        for frame in [*range(-3, 1004), *rng.uniform(-5.0, 1005.0, 500).tolist()]:
            position, expected = track.pose_at(frame)[0], blend(keys, frame)
            assert position.dtype == expected.dtype and position.tobytes() == expected.tobytes(), frame


def test_a_spec_replaced_is_what_dataclasses_replace_makes(male50):
    targets = _feet_and_hand(male50)
    spec = ProblemSpec(targets, balance=True, reduction=["spine"])
    changes = {"targets": list(reversed(targets)), "loops": [], "floor": False, "reduction": ["spine", "neck"]}
    for name, value in changes.items():
        new, old = spec.replace(**{name: value}), dataclasses.replace(spec, **{name: value})
        assert all(getattr(new, f.name) == getattr(old, f.name) for f in dataclasses.fields(ProblemSpec)), name
        assert isinstance(new.targets, tuple) and isinstance(new.reduction, tuple)
    assert spec.replace(targets=[]).targets == () and spec.targets == tuple(targets)  # the spec itself unchanged
    with pytest.raises(TypeError):
        spec.replace(colour="red")


def _outcome(check, targets) -> str:
    try:
        check(targets)
    except ManikinError as error:
        return str(error)
    return "accepted"


def test_the_frame_checks_accept_and_refuse_what_the_full_checks_do(male50):
    """Positions and rotations checked in Python floats first: whatever they do not surely accept goes through the
    full checks, so the same targets are refused with the same message naming the first bad one (a rotation just
    within the tolerance, a list, float32 numbers: accepted as before)."""
    r = exp_so3([0.2, 0.1, -0.4])
    edge = r @ np.diag([1.0 + 0.549995e-5, 1.0, 1.0])  # R^T R off by 1.09999e-5 on its diagonal: within 1.1e-5
    positions = [np.array([0.1, 0.2, 0.3]), [0.1, 0.2, 0.3], np.array([0.1, 0.2, 0.3], np.float32),
                 np.array([np.nan, 0.0, 0.0]), np.array([1000.5, 0.0, 0.0]), np.array([-np.inf, 0.0, 0.0]),
                 np.array([1.0, 2.0]), np.array([1000.0, -1000.0, 0.0])]  # fmt: skip
    rotations = [None, r, edge, r @ np.diag([1.0 + 1e-5, 1.0, 1.0]), np.diag([1.0, 1.0, -1.0]), r * np.nan,
                 np.eye(2), r.astype(np.float32), r.tolist()]  # fmt: skip
    outcomes = set()
    for p in positions:
        for rot in rotations:
            targets = [Target("hand_l", np.zeros(3)), Target("hand_r", p, rot), Target("head", [np.inf, 0.0, 0.0])]
            outcome = _outcome(validate_frames, targets)
            assert outcome == _outcome(lambda ts: validate(male50, ts, (), ()), targets), (p, rot)
            outcomes.add(outcome.split(":")[0])
    assert outcomes == {"target hand_r position", "target hand_r rotation", "target head position"}
    assert _outcome(validate_frames, [Target("hand_r", np.zeros(3), edge)]) == "accepted"


def test_a_target_checked_before_is_not_checked_again():
    """The very object at its index in ``checked`` (a problem's targets, checked when it was made) is skipped; the
    same object at another index, or an equal new one, is checked."""
    bad = Target("hand_r", np.array([np.nan, 0.0, 0.0]))
    fine = Target("hand_l", np.zeros(3))
    validate_frames([fine, bad], [fine, bad])
    for checked in ([bad, fine], [fine, dataclasses.replace(bad)], []):
        with pytest.raises(ManikinError, match="target hand_r position"):
            validate_frames([fine, bad], checked)


def test_moving_some_targets_keeps_the_constraints_of_the_others(male50):
    """with_targets: a target that is the very object it was keeps its constraint object (its frame unchanged); the
    rows are those of a problem built afresh with the moved targets."""
    targets = _feet_and_hand(male50)
    problem = Problem(male50, ProblemSpec(targets))
    hand = targets[2].at(np.array([-0.2, -0.4, 1.0]), exp_so3([0.0, 0.3, 0.0]))
    moved = problem.with_targets([targets[0], targets[1], hand])
    kept = [a is b for a, b in zip(moved.target_constraints, problem.target_constraints, strict=True)]
    assert kept == [True, True, False]
    fresh = Problem(male50, ProblemSpec([targets[0], targets[1], hand]))
    x = problem.to_x(problem.start())
    np.testing.assert_allclose(moved.scaled_error(moved.state_of_x(x)), fresh.scaled_error(fresh.state_of_x(x)),
                               rtol=0, atol=1e-12)  # fmt: skip


def test_bounds_narrowed_are_read_only_and_leave_the_wider_bounds_alone():
    wide = Bounds([-1.0, -2.0, 0.0], [1.0, 2.0, np.inf], [0.5, 1.0, 700.0], [True, True, False])
    center, step = np.array([0.9, -0.5, 100.0]), np.array([0.35, 0.35, np.inf])
    narrow = wide.around(center, step)
    expected = Bounds(np.maximum(wide.lower, center - step), np.minimum(wide.upper, center + step), wide.scale,
                      wide.is_joint)  # fmt: skip
    for name in ("lower", "upper", "scale", "is_joint"):
        value = getattr(narrow, name)
        np.testing.assert_array_equal(value, getattr(expected, name))
        assert not value.flags.writeable and value.dtype == getattr(expected, name).dtype
    np.testing.assert_array_equal(narrow.lower, [0.55, -0.85, 0.0])
    np.testing.assert_array_equal(wide.lower, [-1.0, -2.0, 0.0])
    assert not np.shares_memory(narrow.lower, center) and not np.shares_memory(narrow.upper, center)


def test_the_per_frame_steps_kept_are_those_computed_afresh(male50):
    """kept_steps keeps the last answer for the same model, reduction, variable count and limits: asked in turn for
    problems with and without a reduction and for two limits, each answer is the one computed afresh, and so are the
    bounds of each bounded problem (around the same joint values again: the narrowed bounds kept from the last)."""
    targets = _feet_and_hand(male50)
    plain = Problem(male50, ProblemSpec(targets))
    reduced = Problem(male50, ProblemSpec(targets, reduction=("lumbar", "thoracic", "shoulder")))
    moved = plain.with_targets([*targets[:2], targets[2].at(np.array([-0.2, -0.4, 1.0]), None)])
    limits = MotionLimits(), MotionLimits(0.2, 0.05)
    for problem, limit in [(plain, limits[0]), (moved, limits[0]), (reduced, limits[0]), (reduced, limits[1]),
                           (plain, limits[1]), (plain, limits[1]), (plain, limits[0])]:  # fmt: skip
        steps = frames.kept_steps(problem, limit)
        np.testing.assert_array_equal(steps, frames.variable_steps(problem, limit))
        assert not steps.flags.writeable and len(steps) == problem.n_var
        start = problem.to_x(problem.start())
        for x in (start, start.copy(), start + 0.01, start + 0.01):  # a frame that did not move: the bounds kept
            narrowed = frames.bounded(problem, x, limit).bounds
            afresh = problem.bounds.around(problem.to_variables(x), frames.variable_steps(problem, limit))
            np.testing.assert_array_equal(narrowed.lower, afresh.lower)
            np.testing.assert_array_equal(narrowed.upper, afresh.upper)


def test_targets_read_again_at_the_same_frames_keep_their_constraints(male50):
    """Equal positions and rotations in new target objects (a bake reads the scene every frame): the constraints
    are kept; a moved one is moved, a bad one still refused."""
    problem = Problem(male50, _feet_and_hand(male50))
    again = [dataclasses.replace(t, position=np.array(t.position, dtype=float)) for t in problem.all_targets]
    same = problem.with_targets(again)
    assert all(a is b for a, b in zip(same.target_constraints, problem.target_constraints, strict=True))
    moved = [*again[:2], dataclasses.replace(again[2], position=again[2].position + 0.01)]
    shifted = problem.with_targets(moved)
    assert shifted.target_constraints[:2] == problem.target_constraints[:2]
    assert shifted.target_constraints[2] is not problem.target_constraints[2]
    np.testing.assert_array_equal(shifted.target_constraints[2].target_position, moved[2].position)
    bad = [*again[:2], dataclasses.replace(again[2], position=np.array([np.nan, 0.0, 1.0]))]
    with pytest.raises(ManikinError, match="hand_r position"):
        problem.with_targets(bad)


def test_a_target_keeps_its_constraint_when_specs_same_frame_says_so(male50):
    """with_targets (through specs.same_frame, in Python floats) keeps a target's constraint exactly when
    np.array_equal says the frame is the same: -0.0 equals 0.0, other dtypes and plain lists
    alike; a NaN is refused."""
    problem = Problem(male50, _feet_and_hand(male50))
    feet, lock = problem.all_targets[:2], problem.all_targets[2].lock
    positions = [np.zeros(3), -np.zeros(3), np.array([0.0, 0.5, 1.0]), np.array([0, 0, 0]), [0.0, -0.0, 0.0],
                 np.array([0.0, 0.5, 1.0], dtype=np.float32), np.array([0.0, 0.5, 1.0 + 1e-16])]  # fmt: skip
    rotations = [None, np.eye(3), np.where(np.eye(3) == 1.0, 1.0, -0.0), np.diag([1.0, -1.0, -1.0]), np.eye(3).tolist()]
    hands = [Target("hand_r", p, r, lock=lock) for p in positions for r in rotations]
    for a in hands:
        before = problem.with_targets([*feet, a])
        for b in hands:
            after = before.with_targets([*feet, b])
            kept = after.target_constraints[2] is before.target_constraints[2]
            same = (
                (a.rotation is None) == (b.rotation is None)
                and np.array_equal(a.position, b.position)
                and (a.rotation is None or np.array_equal(a.rotation, b.rotation))
            )
            assert kept == same == same_frame(a, b), (a.position, a.rotation, b.position, b.rotation)
    before = problem.with_targets([*feet, hands[0]])
    with pytest.raises(ManikinError, match="hand_r position"):
        before.with_targets([*feet, Target("hand_r", np.array([np.nan, 0.0, 0.0]), lock=lock)])
