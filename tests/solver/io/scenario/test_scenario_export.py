"""Scenario export (solver/io/scenario/write.py): what scenario_to_dict and dumps_scenario write reads back the same."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from solver import Problem, dumps_scenario, load_scenario, scenario_to_dict, solve, write_scenario
from solver.body.contacts import support_polygon
from solver.errors import ScenarioError
from solver.io.scenario.bodies import PRESETS_DIR

BOX_LIFT = PRESETS_DIR / "scenarios" / "box_lift.toml"


def _same_problem(a, b) -> None:
    assert len(a.all_targets) == len(b.all_targets) and len(a.loops) == len(b.loops)
    for ta, tb in zip(a.all_targets, b.all_targets, strict=True):
        assert (ta.tcp, ta.lock, ta.support, ta.enabled) == (tb.tcp, tb.lock, tb.support, tb.enabled)
        np.testing.assert_allclose(ta.position, tb.position, atol=1e-12)
        assert (ta.rotation is None) == (tb.rotation is None)
        if ta.rotation is not None:
            np.testing.assert_allclose(ta.rotation, tb.rotation, atol=1e-12)
    for la, lb in zip(a.load_specs, b.load_specs, strict=True):
        assert la.tcp == lb.tcp
        np.testing.assert_allclose(la.force, lb.force, atol=1e-12)
    assert a.balance == b.balance and a.comfort.weights == b.comfort.weights


def test_box_lift_round_trip(tmp_path: Path) -> None:
    sc = load_scenario(BOX_LIFT)
    result = solve(sc.problem, sc.start, sc.options)
    options = dataclasses.replace(sc.options, restarts=3)
    data = scenario_to_dict(sc.problem, {"preset": "male_50"}, options, start=result.x, name="box lift again")
    again = load_scenario(write_scenario(tmp_path / "again.toml", data))
    assert again.path.read_text(encoding="utf-8") == dumps_scenario(data)
    _same_problem(sc.problem, again.problem)
    np.testing.assert_allclose(again.start[: sc.model.n], result.theta, atol=1e-12)
    assert again.options.max_iterations == sc.options.max_iterations
    assert again.options.restarts == 3


def test_loops_operators_and_odd_strings(tmp_path: Path) -> None:
    sc = load_scenario(BOX_LIFT)
    data = scenario_to_dict(sc.problem, {"preset": "male_50"}, name='quote " and ä')
    data["loops"] = [
        dict(tcp="hand_l", other="hand_r", offset_position=[0.4, 0.0, 0.0], offset_rotation=[0.0, 0.0, 1.0, 0.0],
             operator=[[1, 0, 0, 0, 0, 0], [0, 1, 0, 0, 0, 0]], weight=2.0)
    ]  # fmt: skip
    path = tmp_path / "loop.toml"
    path.write_text(dumps_scenario(data), encoding="utf-8")
    again = load_scenario(path)
    assert again.problem.loops[0].operator.shape == (2, 6)
    written = dumps_scenario(scenario_to_dict(again.problem, {"preset": "male_50"}))
    assert "operator = [[1.0, 0.0, 0.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0, 0.0, 0.0]]" in written


def test_non_finite_values_are_refused() -> None:
    with pytest.raises(ScenarioError):
        dumps_scenario({"manikin": {"preset": "male_50"}, "comfort": {"range": float("nan")}})


def test_support_polygon_is_the_convex_hull() -> None:
    square = np.array([[0, 0, 0], [1, 0, 0.2], [1, 1, 0], [0, 1, 0], [0.5, 0.5, 0], [0.5, 0, 0]], dtype=float)
    np.testing.assert_allclose(support_polygon(square), [[0, 0], [1, 0], [1, 1], [0, 1]])
    assert len(support_polygon(square[:2])) == 2


def test_reduction_groups_round_trip(tmp_path: Path) -> None:
    box = load_scenario(BOX_LIFT).problem
    groups = ("lumbar", "thoracic")
    reduced = Problem(box.model, box.spec.replace(reduction=groups))
    path = tmp_path / "reduced.toml"
    path.write_text(dumps_scenario(scenario_to_dict(reduced, {"preset": "male_50"})), encoding="utf-8")
    assert load_scenario(path).problem.reduction_groups == groups
