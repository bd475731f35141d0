"""Stepping feet in a pose solve (solver.stance): the step cost's derivatives, a reach 0.4 m beyond the planted reach
met with a reported step (within the stance limits, in balance, recomputed from the forces), the same reach unmet
with planted feet and saying so, an obstacle where a foot would step, find_stance, the scenario key and CLI flag,
and a stepping motion's per-frame foot moves."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from solver import load_preset, solve
from solver.collision.kinds.box import Box
from solver.envelope import search_ray
from solver.envelope.reach import reach_setup
from solver.problem.problem import Problem
from solver.problem.specs import ProblemSpec, Target
from solver.stance import PLANTED_NOTE, annotate, find_stance, frame_moves, stance_limits, stepping, steps_of
from solver.stance.cost import StepCost

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "envelope"))
from test_envelope_stepping import assert_in_balance, assert_within_bounds  # noqa: E402

FEET = ("foot_l", "foot_r")
AHEAD_LOW = np.array([0.0, -1.0, -0.3]) / np.linalg.norm([0.0, -1.0, -0.3])


@pytest.fixture(scope="module")
def model():
    return load_preset("male_50")


@pytest.fixture(scope="module")
def far(model):
    """(problem with planted feet, hand point) for a point 0.4 m beyond the balanced planted reach, ahead and low."""
    setup = reach_setup(model, "right")
    reach = search_ray(setup, AHEAD_LOW, 0.6)
    assert reach.reached
    point = setup.shoulder + (reach.radius + 0.4) * AHEAD_LOW
    zero = model.forward(model.zero_pose())
    feet = [Target(f, zero.tcp_frame(model.tcp(f))[1], support=True) for f in FEET]
    return Problem(model, ProblemSpec([Target("hand_r", point, lock=("x", "y", "z")), *feet])), point


def test_the_step_cost_derivatives_match_finite_differences(model, far):
    problem = stepping(far[0])
    term = next(t for _, t in problem.comfort.terms if isinstance(t, StepCost))
    x = problem.to_x(problem.start(None)).copy()
    x[: model.n] += np.random.default_rng(5).normal(0.0, 0.2, model.n)  # feet off their start: nonzero gradient
    state = problem.state_of_x(x)
    grad = term.derivatives(state, 1.0)[0]
    numeric = np.zeros(model.n)
    for i in range(model.n):
        up, down = x.copy(), x.copy()
        up[i] += 1e-6
        down[i] -= 1e-6
        numeric[i] = (term.cost(problem.state_of_x(up)) - term.cost(problem.state_of_x(down))) / 2e-6
    assert np.abs(grad).max() > 0.1
    assert np.allclose(grad[: model.n], numeric, atol=1e-5)
    rows = term.curvature_rows(state, 1.0)  # Gauss-Newton rows, 4 per foot (x, y, z offset and the turn)
    assert rows.shape == (8, problem.n_x) and np.isfinite(rows).all()


def test_planted_feet_leave_a_far_reach_unmet_and_say_so(far):
    result = annotate(solve(far[0]))
    assert not result.converged and result.shortfall["hand_r"]["position_m"] > 0.3
    assert not result.broken  # the feet held where they stood
    assert PLANTED_NOTE in result.notes and "--feet step" in PLANTED_NOTE


def test_stepping_meets_a_reach_04_m_beyond_planted_reach(model, far):
    problem, point = far
    found = find_stance(problem)
    result = found.result
    assert found.converged and result.converged, found.message
    assert np.linalg.norm(result.state.kin.tcp_frame(model.tcp("hand_r"))[1] - point) < 2e-3
    limits = stance_limits(model)
    assert found.steps and all(0.05 < s.length <= limits.step + 1e-3 for s in found.steps)
    for s in found.steps:  # ahead: the steps go forward, turned within the limit, and each is in the notes
        assert abs(s.direction_deg) < 30.0 and abs(s.turn_deg) <= 45.2
        assert s.text() in result.notes and s.text() in found.message
    assert_within_bounds(model, result.state.theta)
    assert_in_balance(model, result, point, 0.0)
    planted = solve(found.problem, result.x)  # the returned problem: the feet planted at the new stance
    assert planted.converged and {t.tcp: t.lock for t in found.problem.all_targets}["foot_r"] == problem.targets[2].lock


def test_a_foot_does_not_step_into_an_obstacle(model, far):
    problem, point = far
    block = Box(name="crate", center=np.array([0.0, -0.55, 0.15]), size=np.array([0.8, 0.3, 0.3]))
    blocked = Problem(model, problem.spec.replace(obstacles=(block,)))
    result, free = solve(stepping(blocked)), solve(stepping(problem))
    inside = lambda p: abs(p[0]) < 0.4 and -0.7 < p[1] < -0.4  # noqa: E731 (the crate's footprint)
    assert any(inside(free.state.kin.tcp_frame(model.tcp(f))[1]) for f in FEET)  # without it a foot steps there
    for f in FEET:  # with it the feet step around or short of it (they stay on the floor: no step over it)
        assert not inside(result.state.kin.tcp_frame(model.tcp(f))[1]), f
    assert not result.broken and all(c.distance >= c.clearance - 1e-3 for c in result.closest if c.other == "crate")


def test_a_stepping_motion_reports_each_foot_move(model, far):
    problem = stepping(far[0])
    zero = problem.state_of_x(problem.to_x(problem.start(None)))
    end = solve(problem)
    moves = frame_moves(problem, zero, end.state)
    assert len(moves) == len(steps_of(problem, end.state)) >= 1 and all("slid" in m for m in moves)
    assert frame_moves(far[0], zero, end.state) == []  # planted feet: nothing to report


SCENARIO = """
[manikin]
preset = "male_50"

[[targets]]
tcp = "hand_r"
position = [-0.19, -1.61, 0.92]
lock = ["x", "y", "z"]

[[targets]]
tcp = "foot_l"
position = [0.083, 0.0, 0.0]
support = true

[[targets]]
tcp = "foot_r"
position = [-0.083, 0.0, 0.0]
support = true
"""


def run(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "solver", *args], capture_output=True, text=True, timeout=120,
                          cwd=Path(__file__).resolve().parents[3])  # fmt: skip


def test_the_cli_flag_and_the_scenario_key(tmp_path):
    path = tmp_path / "far.toml"
    path.write_text(SCENARIO)
    planted = run("solve", str(path))
    assert planted.returncode == 3 and "the feet stayed planted" in planted.stdout and "--feet step" in planted.stdout
    out = tmp_path / "r.json"
    stepped = run("solve", str(path), "--feet", "step", "-o", str(out))
    assert stepped.returncode == 0, stepped.stdout + stepped.stderr
    assert "stepped" in stepped.stdout
    frame = json.loads(out.read_text())["frames"][0]
    assert frame["feet"] == "step" and frame["steps"]
    assert set(frame["steps"][0]) >= {"foot", "length", "direction_deg", "turn_deg"}
    path.write_text(SCENARIO + '\n[stance]\nfeet = "step"\n')
    keyed = run("solve", str(path), "-q")
    assert keyed.returncode == 0, keyed.stderr


@pytest.mark.parametrize("args,text", [(("--feet", "hop"), "--feet"), ((), "stance.feet")])
def test_bad_feet_values_are_one_line(tmp_path, args, text):
    path = tmp_path / "bad.toml"
    path.write_text(SCENARIO + ('\n[stance]\nfeet = "jump"\n' if not args else ""))
    done = run("solve", str(path), *args)
    assert done.returncode == 2 and len(done.stderr.strip().splitlines()) == 1 and text in done.stderr
