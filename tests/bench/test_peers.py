"""Benchmark peers: SLSQP on one easy randomized trial, the force recovery used for placo, placo if installed."""

from __future__ import annotations

import numpy as np
import pytest

from bench.peers import balancing_forces, judge, placo_peer, slsqp_peer
from bench.random_targets import LEVELS, draw_targets, trial_problem, workspace_box
from solver.io.scenario.bodies import load_body

EASY_SEED = 2013  # level pi/8, seed of the benchmark's second trial: SLSQP needs ~70 iterations, < 2 s


@pytest.fixture(scope="module")
def easy_problem():
    model = load_body(preset="male_50")
    targets = draw_targets(model, workspace_box(model), LEVELS[0], EASY_SEED)
    return trial_problem(model, targets, True, ())


def test_slsqp_peer_returns_a_finite_judged_result(easy_problem):
    result = slsqp_peer(easy_problem, max_iterations=200)
    converged, time_s, iterations = result[:3]
    assert isinstance(converged, bool) and np.isfinite(time_s) and time_s > 0 and iterations > 0
    assert np.isfinite(result.worst) and np.isfinite(result.comfort)
    assert converged == (result.worst <= 1.0) and converged  # an easy trial: SLSQP meets it


def test_balancing_forces_balance_a_pose_over_the_soles(easy_problem):
    model = easy_problem.model
    theta = model.zero_pose()
    w = balancing_forces(easy_problem, theta)
    assert w.shape == (easy_problem.contacts.n_vars,) and np.all(w >= 0)
    converged, worst, unmet, _ = judge(easy_problem, np.concatenate([theta, w]))
    assert "balance" not in unmet  # standing upright: the CoM is over the soles, so forces exist
    assert not converged  # the hands are not at their targets in the zero pose


def test_placo_peer_on_an_easy_trial(easy_problem):
    pytest.importorskip("placo")
    result = placo_peer(easy_problem)
    assert np.isfinite(result.time_s) and result.iterations > 0
    assert result.converged, result


def test_peer_report_tables_from_outcomes():
    from bench.peer_report import OURS_FOR_PEERS, peer_report
    from bench.random_targets import LEVEL_NAMES

    outcomes = []
    for level in range(len(LEVEL_NAMES)):
        for i in range(2):
            seed = 2012 + 100_000 * level + i
            for config, t in zip([*OURS_FOR_PEERS, "SLSQP"], (0.1, 0.2, 0.05, 1.0), strict=True):
                outcomes.append(dict(config=config, level=level, seed=seed, converged=i == 0, time_s=t, comfort=-1.0))
    text = peer_report(outcomes, 2, ["SLSQP"], LEVEL_NAMES)
    assert "### Peers, same trials" in text and "placo**: not installed" in text
    assert "| pi/8 | 2 | 1/2 | 1/2 | 1/2 | 1/2 |" in text and "| all | 12 | 6/12 | 6/12 | 6/12 | 6/12 |" in text
    assert "10.0 (10.0)" in text and "5.0 (5.0)" in text  # SLSQP time over ours: p+r, then p
