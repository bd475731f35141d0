"""What a problem builds from its model and plain inputs alone (comfort terms, contacts and statics layout, bounds,
the floor's and the body's own clearance) is built once per model and key: a problem built again gets what a new
build gives, a changed input gets its own, and a clearance's state while solved stays its own."""

from __future__ import annotations

import gc
import weakref

import numpy as np
import pytest

from solver.body.contacts import Support, build_contacts
from solver.body.statics import Load, StaticsLayout
from solver.collision.body import capsules_of
from solver.comfort import Comfort
from solver.comfort.standard import STANDARD_TERMS, StandardTerm
from solver.comfort.trunk_tilt import TrunkTilt
from solver.constraints import FrameConstraint, lock_operator, per_model
from solver.io.scenario.bodies import PRESETS_DIR, load_body
from solver.io.scenario.read import load_scenario
from solver.problem.problem import ExternalLoad, Problem

LIFT = PRESETS_DIR / "scenarios" / "box_lift.toml"


@pytest.fixture(scope="module")
def lift() -> Problem:
    return load_scenario(LIFT).problem


def fresh_statics(problem: Problem) -> tuple:
    """The contact set and layout of ``problem`` built anew, as Problem built them before the cache."""
    model, zero = problem.model, problem.model.forward(problem.model.zero_pose())

    def rotation(t):  # the target's, else its TCP's in the zero pose
        return np.asarray(t.rotation, dtype=float) if t.rotation is not None else zero.tcp_frame(model.tcp(t.tcp))[0]

    supports = [Support(model.tcp(t.tcp), rotation(t), t.friction, t.sole) for t in problem.targets if t.support]
    contacts = build_contacts(model, supports)
    loads = [Load(model.tcp(ld.tcp), np.asarray(ld.force, dtype=float)) for ld in problem.spec.loads]
    return contacts, StaticsLayout(model, contacts, loads)


def same_arrays(a: object, b: object) -> None:
    """Every array attribute of ``a`` equals ``b``'s, bit for bit."""
    for name, value in vars(a).items():
        if isinstance(value, np.ndarray):
            np.testing.assert_array_equal(value, getattr(b, name), err_msg=name)


def test_a_problem_built_again_shares_the_parts_and_they_are_what_a_new_build_gives(lift):
    again = Problem(lift.model, lift.spec)
    assert again.layout is lift.layout and again.contacts is lift.contacts and again.x_bounds is lift.x_bounds
    contacts, layout = fresh_statics(lift)
    same_arrays(lift.contacts, contacts)
    same_arrays(lift.layout, layout)
    assert [type(t) for _, t in lift.comfort.terms] == [type(t) for _, t in Comfort.standard(lift.model).terms]
    assert again.floor_constraint is not lift.floor_constraint  # a copy of the template: its own last query
    assert again.self_constraint is not lift.self_constraint


@pytest.mark.parametrize("change", ["load", "friction", "rotation", "sole", "weights", "reduction"])
def test_a_changed_input_is_not_served_the_parts_of_another(lift, change):
    spec = lift.spec
    feet = [i for i, t in enumerate(spec.targets) if t.support]
    targets = list(spec.targets)
    if change == "load":
        spec = spec.replace(loads=[ExternalLoad(ld.tcp, np.asarray(ld.force) * 2.0) for ld in spec.loads])
    elif change in ("friction", "rotation", "sole"):
        foot = targets[feet[0]]
        value = dict(friction=0.3, rotation=np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]),
                     sole=np.array([[0.1, 0.05], [-0.05, 0.05], [-0.05, -0.05], [0.1, -0.05]]))[change]  # fmt: skip
        targets[feet[0]] = type(foot)(**{**vars(foot), change: value})
        spec = spec.replace(targets=targets)
    elif change == "weights":
        spec = spec.replace(comfort_weights=spec.comfort_weights.replace(load=0.25))
    else:
        spec = spec.replace(reduction=("lumbar", "thoracic"))
    changed = Problem(lift.model, spec)
    contacts, layout = fresh_statics(changed)
    same_arrays(changed.contacts, contacts)
    same_arrays(changed.layout, layout)
    if change in ("load", "friction", "rotation", "sole"):
        assert changed.layout is not lift.layout
    if change == "weights":
        assert changed.comfort.weights["load"] == 0.25 and lift.comfort.weights["load"] != 0.25
    if change == "reduction":
        assert changed.reduction is not None and lift.reduction is None and changed.n_var < lift.n_var


def test_a_term_registered_later_is_in_the_next_problem_s_comfort(lift, monkeypatch):
    monkeypatch.setitem(STANDARD_TERMS, "extra", StandardTerm(TrunkTilt, 1.0))
    assert len(Problem(lift.model, lift.spec).comfort.terms) == len(STANDARD_TERMS) == len(lift.comfort.terms) + 1


def test_a_clearance_s_last_query_stays_with_its_problem(lift):
    again = Problem(lift.model, lift.spec)
    state = lift.state(lift.start())
    lift.floor_constraint.error(state)
    lift.self_constraint.error(state)
    assert lift.floor_constraint.__dict__.get("_last") is not None
    assert again.floor_constraint.__dict__.get("_last") is None
    assert again.self_constraint.__dict__.get("_last") is None
    np.testing.assert_array_equal(again.floor_constraint.error(again.state(again.start())),
                                  lift.floor_constraint.error(state))  # fmt: skip


def test_per_model_keeps_a_few_keys_of_a_few_models():
    model = load_body(preset="snake")
    for i in range(per_model.ENTRIES + 3):
        per_model.per_model(model, ("test", i), lambda i=i: i)
    assert per_model.per_model(model, ("test", per_model.ENTRIES + 2), lambda: -1) == per_model.ENTRIES + 2
    assert per_model.per_model(model, ("test", 0), lambda: -1) == -1  # the oldest was dropped: built again
    gone = weakref.ref(model)
    Problem(model, load_scenario(PRESETS_DIR / "scenarios" / "snake_pose_a.toml").problem.spec)
    del model
    for _ in range(per_model.MODELS):  # as many other models: the first one is let go with what it kept
        per_model.per_model(load_body(preset="snake"), "test", lambda: 0)
    capsules_of.cache_clear()  # its own few models
    gc.collect()
    assert gone() is None and len(per_model._PER_MODEL) == per_model.MODELS


def test_frame_constraints_with_other_tolerances_get_their_own_row_tolerance(lift):
    tcp, op = lift.model.tcp("hand_r"), lock_operator(("x", "y", "z", "rx"))
    a = FrameConstraint("a", tcp, np.eye(3), np.zeros(3), op, lift.n_x)
    b = FrameConstraint("b", tcp, np.eye(3), np.zeros(3), op, lift.n_x, position_tolerance=2e-3)
    np.testing.assert_array_equal(a.tolerance(), [1e-3, 1e-3, 1e-3, np.deg2rad(0.2)])
    np.testing.assert_array_equal(b.tolerance(), [2e-3, 2e-3, 2e-3, np.deg2rad(0.2)])
    assert [p for p, _ in a._locked_parts] == ["a.position", "a.rotation"] and not a.tolerance().flags.writeable
