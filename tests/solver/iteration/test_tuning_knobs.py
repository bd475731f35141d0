"""The line-search knobs of issue 37's fourth step (docs/TUNING.md, "Fewer wasted trial points"): each off by
default (the measured method unchanged), and each doing what its comment says when switched on."""

from __future__ import annotations

import importlib
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from solver import load_scenario
from solver.iteration import TUNING, solve
from solver.iteration.trial import Trial

HIGH_LIFT = Path(__file__).resolve().parents[3] / "presets" / "scenarios" / "box_lift_high.toml"
line_search = importlib.import_module("solver.iteration.line_search")


def test_the_new_knobs_are_off_by_default():
    """Measured and not adopted (docs/BENCHMARKS.md, "Issue 37, fourth step"): the defaults keep the method."""
    assert TUNING.comfort_shrink == 1.0 and TUNING.comfort_retry == 0.0 and TUNING.penalty_margin == 2.0
    assert not TUNING.task_first and not TUNING.task_first_far and TUNING.far_comfort_check


def _searches(monkeypatch, tuning) -> list[tuple[object, object]]:
    """(line search, its outcome) of every iteration of a cold solve of the high box lift with ``tuning``."""
    seen = []
    original = line_search.LineSearch.run

    def run(self):
        outcome = original(self)
        seen.append((self, outcome))
        return outcome

    monkeypatch.setattr(line_search.LineSearch, "run", run)
    scenario = load_scenario(HIGH_LIFT)
    assert solve(scenario.problem, scenario.start, scenario.options, tuning).converged
    return seen


def _dropped(search, outcome) -> bool:
    """The search tried comfort first and gave it up."""
    return search.attempts()[0][0] and (outcome.trial is None or not outcome.with_comfort)


@pytest.mark.parametrize("retry", [0.0, 0.5])
def test_comfort_retry_keeps_the_task_part_whole(monkeypatch, retry):
    """Near the constraints a rejected comfort try is retried with the task part whole and the comfort part
    scaled by ``comfort_retry`` (0: the whole step halved, as before)."""
    tuning = replace(TUNING, comfort_retry=retry)
    search = next(s for s, _ in _searches(monkeypatch, tuning) if s.near and s.step.predicted_gain > 0)
    at, step, problem = search.at, search.step, search.problem
    points = []
    evaluate = search.evaluate

    class Rejecting:  # every trial too far off for a correction: the search only shortens
        problem, unweight = evaluate.problem, evaluate.unweight

        def __call__(self, x):
            points.append(x)
            return Trial(x, at.state, np.zeros_like(at.err), np.inf, np.inf)

    search.evaluate = Rejecting()
    assert search._try(True, 2) == (None, retry**2 if retry else 0.25)
    second = at.x + ((step.task + retry * step.comfort) if retry else 0.5 * (step.task + step.comfort)) * problem.scale
    np.testing.assert_allclose(points[1], problem.bounds.clip(second), atol=1e-12)


@pytest.mark.parametrize("field", ["task_first", "task_first_far"])
def test_task_first_follows_a_dropped_comfort_part(monkeypatch, field):
    """With ``task_first`` the iteration after one that gave comfort up tries the task part alone (with
    ``task_first_far`` only far from the constraints); no other iteration does."""
    seen = _searches(monkeypatch, replace(TUNING, **{field: True}))
    pairs = list(zip(seen[:-1], seen[1:], strict=True))
    assert any(_dropped(*before) for before, _ in pairs), "the high box lift gives comfort up at least once"
    for before, (search, _) in pairs:
        wanted = _dropped(*before) and (field == "task_first" or not search.near)
        assert search.task_first == wanted
        if wanted:
            assert search.attempts() == [(False, TUNING.task_tries)]


def test_comfort_shrink_caps_the_next_comfort_part(monkeypatch):
    """With ``comfort_shrink`` the comfort part after a dropped one is at most that share of the dropped one."""
    shrink = 0.5
    seen = _searches(monkeypatch, replace(TUNING, comfort_shrink=shrink))
    pairs = list(zip(seen[:-1], seen[1:], strict=True))
    checked = 0
    for (before, outcome), (after, _) in pairs:
        if _dropped(before, outcome):
            largest = float(np.abs(before.step.comfort).max())
            assert float(np.abs(after.step.comfort).max()) <= shrink * largest + 1e-12
            checked += 1
    assert checked
