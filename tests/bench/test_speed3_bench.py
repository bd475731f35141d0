"""Issue 37's third-step benchmarks: the cold scenarios' counts, the live stages, placo side by side."""

from __future__ import annotations

from collections import Counter

import pytest

import solver
from bench import cold_scenarios, live_parts, placo_side
from bench.peers import placo_available
from solver.iteration import line_search, phases, trial


def test_the_single_pose_scenarios_are_the_shipped_ones_without_a_motion():
    names = cold_scenarios.single_pose_scenarios()
    assert {"box_lift", "box_lift_high", "cabinet_reach", "snake_pose_a"} <= set(names)
    assert not any("motion" in name for name in names)


def test_counting_tallies_a_solve_and_gives_the_solver_its_functions_back():
    own = trial.Evaluator.__call__, line_search.LineSearch.run, phases.attempt
    sc = solver.load_scenario(cold_scenarios.PRESETS / "snake_pose_a.toml")
    with cold_scenarios.counting(Counter()) as count:
        result = solver.solve(sc.problem, sc.start, sc.options)
    assert count["attempts"] >= 1 and count["line searches"] >= result.iterations - 1 > 0
    assert count["evaluations"] >= count["line searches"]
    assert count["cut back"] + count["found nothing"] <= count["line searches"]
    assert (trial.Evaluator.__call__, line_search.LineSearch.run, phases.attempt) == own


def test_live_parts_times_every_stage_of_a_trial_and_a_linearisation():
    table = live_parts.run(drags=1, repeats=1)
    for stage in ("trial: forward kinematics", "trial: comfort cost, load", "linearisation: comfort derivatives, load",
                  "a trial point, all stages"):  # fmt: skip
        assert f"| {stage} |" in table


@pytest.mark.skipif(placo_available(), reason="placo installed: the comparison itself runs (slow)")
def test_placo_side_says_placo_is_missing():
    assert "not installed" in placo_side.run(seeds=1)
