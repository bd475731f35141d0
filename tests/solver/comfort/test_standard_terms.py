"""The standard comfort terms' registry: ComfortWeights has one weight per registered term, the scenario's
[comfort] table and the results go by it, and a term registered (one line) is read, weighted and reported."""

from __future__ import annotations

import pickle

import numpy as np
import pytest

from solver import ComfortWeights, Problem, ProblemSpec, Target, load_scenario, scenario_to_dict, solve
from solver.body.state import State
from solver.comfort import DEFAULT_COMFORT, STANDARD_TERMS, Comfort, ComfortTerm, StandardTerm
from solver.errors import ScenarioError
from solver.io.scenario.bodies import PRESETS_DIR, load_body
from solver.io.scenario.write import dumps_scenario


def test_the_standard_terms_and_their_defaults() -> None:
    assert {name: term.weight for name, term in STANDARD_TERMS.items()} == {"range": 1.0, "load": 1.0, "contact": 0.01,
                                                                          "trunk": 5.0, "gaze": 0.0}
    assert all(term.factory.name == name for name, term in STANDARD_TERMS.items())  # the results' keys


def test_weights_by_name_in_order_and_as_a_mapping() -> None:
    w = ComfortWeights(1.0, 0.5)
    assert (w.range, w.load, w.contact) == (1.0, 0.5, 0.01) and w == ComfortWeights(load=0.5)
    assert dict(w) == {"range": 1.0, "load": 0.5, "contact": 0.01, "trunk": 5.0, "gaze": 0.0} and w["contact"] == 0.01
    assert hash(w) == hash(ComfortWeights(load=0.5)) and w != DEFAULT_COMFORT
    assert w.replace(contact=0.2) == ComfortWeights(1.0, 0.5, 0.2) and w.contact == 0.01
    assert pickle.loads(pickle.dumps(w)) == w
    assert repr(w) == "ComfortWeights(range=1.0, load=0.5, contact=0.01, trunk=5.0, gaze=0.0)"
    with pytest.raises(AttributeError):
        w.range = 2.0
    for args, named in (((1, 2, 3, 4, 5, 6), {}), ((), {"elbow": 1.0}), ((1,), {"range": 2})):
        with pytest.raises(TypeError):
            ComfortWeights(*args, **named)


def test_every_preset_scenario_reads_the_same_weights() -> None:
    """What the reader gave before the registry: range, load, contact from [comfort], defaults 1, 1, 0.01."""
    import tomllib

    for path in sorted((PRESETS_DIR / "scenarios").glob("*.toml")):
        table = tomllib.loads(path.read_text(encoding="utf-8")).get("comfort", {})
        before = tuple(table.get(k, d) for k, d in (("range", 1.0), ("load", 1.0), ("contact", 0.01)))
        weights = load_scenario(path).problem.comfort.weights
        assert (weights.range, weights.load, weights.contact) == before, path.name


def test_an_unknown_comfort_key_is_one_line(tmp_path) -> None:
    path = tmp_path / "bad.toml"
    path.write_text('[manikin]\npreset = "male_50"\n[comfort]\nelbow = 1.0\n[[targets]]\ntcp = "hand_r"\n'
                    "position = [0.0, -0.4, 1.0]\n[solver]\nbalance = false\n", encoding="utf-8")  # fmt: skip
    with pytest.raises(ScenarioError, match="elbow") as info:
        load_scenario(path)
    assert "\n" not in str(info.value)


class ElbowStraight(ComfortTerm):
    """A made-up standard term: the right elbow straight (cost = flexion^2, rad^2)."""

    name = "elbow"

    def __init__(self, model) -> None:
        self.joint = model.joint_index("elbow_r_flexion")

    def cost(self, state: State) -> float:
        return float(state.theta[self.joint] ** 2)

    def derivatives(self, state: State, weight: float) -> tuple[np.ndarray, np.ndarray]:
        grad, curv = np.zeros(state.n_x), np.zeros(state.n_x)
        grad[self.joint], curv[self.joint] = weight * 2.0 * state.theta[self.joint], weight * 2.0
        return grad, curv


def test_a_registered_term_is_read_weighted_written_and_reported(tmp_path, monkeypatch) -> None:
    """What ``register(ElbowStraight, 0.5)`` in solver/comfort/standard.py does, done for this test alone."""
    monkeypatch.setitem(STANDARD_TERMS, "elbow", StandardTerm(ElbowStraight, 0.5))
    assert ComfortWeights().elbow == 0.5 and ComfortWeights(1.0, 1.0, 0.01, 0.0, 0.0, 2.0).elbow == 2.0
    model = load_body(preset="male_50")
    zero = model.forward(model.zero_pose())
    feet = [Target(f, zero.tcp_frame(model.tcp(f))[1], support=True) for f in ("foot_r", "foot_l")]
    hand = Target("hand_r", np.array([-0.25, -0.45, 1.1]), lock=("x", "y", "z"))
    problem = Problem(model, ProblemSpec([*feet, hand], comfort_weights=ComfortWeights(elbow=4.0)))
    assert [term.name for _, term in problem.comfort.terms] == ["range", "load", "contact", "trunk", "gaze", "elbow"]
    assert problem.comfort.terms[-1][0] == 4.0
    path = tmp_path / "elbow.toml"
    path.write_text(dumps_scenario(scenario_to_dict(problem, {"preset": "male_50"})), encoding="utf-8")
    assert "elbow = 4.0" in path.read_text(encoding="utf-8")
    again = load_scenario(path).problem
    assert again.comfort.weights == problem.comfort.weights
    result = solve(again)
    assert result.converged and set(result.comfort_parts) == {"range", "load", "contact", "trunk", "gaze", "elbow"}
    straight = Comfort.standard(model, ComfortWeights(elbow=0.0))  # zero weight: not part of comfort
    assert straight.parts(result.state)["elbow"] == 0.0
