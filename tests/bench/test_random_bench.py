"""The randomized-target benchmark: the workspace box, the trial draw, one end-to-end tiny run."""

from __future__ import annotations

import json

import numpy as np
import pytest

from bench.random_targets import LEVELS, draw_targets, neutral_hand_rotation, run_random_benchmark, workspace_box
from solver.body.spatial import log_so3
from solver.io.scenario.bodies import load_body


def test_workspace_box_follows_the_anthropometry():
    model = load_body(preset="male_50")
    kin = model.forward(model.zero_pose())
    box = workspace_box(model)
    shoulder = kin.tcp_frame(model.tcp("shoulder_r"))[1]
    knuckles = kin.tcp_frame(model.tcp("knuckles_r"))[1]
    assert np.isclose(box.upper[2], shoulder[2]) and np.isclose(box.lower[2], knuckles[2])
    assert box.lower[1] < shoulder[1] - 0.5  # an arm's length in front of the shoulder
    assert np.isclose(box.lower[0], -box.upper[0]) and box.upper[0] > abs(shoulder[0])
    bigger = workspace_box(load_body(preset="male_95"))
    assert np.all(bigger.upper - bigger.lower > box.upper - box.lower)


def test_draw_respects_box_crossing_and_max_deviation():
    model = load_body(preset="male_50")
    box = workspace_box(model)
    for seed in range(30):
        for level in LEVELS[:2]:
            targets = draw_targets(model, box, level, seed)
            (pr, rr), (pl, rl) = targets["r"], targets["l"]
            assert pr[0] <= pl[0]
            assert np.all(pr >= box.lower) and np.all(pr <= box.upper)
            for side, r in (("r", rr), ("l", rl)):
                deviation = np.linalg.norm(log_so3(r @ neutral_hand_rotation(model, side).T))
                assert deviation <= level + 1e-9
    assert np.allclose(draw_targets(model, box, 1.0, 5)["r"][0], draw_targets(model, box, 1.0, 5)["r"][0])


@pytest.mark.slow
def test_tiny_run_writes_tables_plot_and_failures(tmp_path):
    out = tmp_path / "BENCH.md"
    text = run_random_benchmark(out, trials=1, processes=1)
    assert "physics + reduction" in text and "919/1000" in text
    assert out.exists() and (tmp_path / "random_benchmark.png").exists()
    assert isinstance(json.loads((tmp_path / "random_failures.json").read_text()), list)
