"""The whole body along a way (issue 36, "Paths"): the hand's way past a bar is clear, but the arm behind the hand
cannot follow it without passing through the bar; the posture-level check finds and names that."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from solver import load_scenario
from solver.planning import find_way
from solver.planning.follow import follow

STAND = """
name = "a hand raised past a bar"
[manikin]
preset = "male_50"
[[targets]]
tcp = "hand_r"
position = [-0.25, -0.5, 0.85]
lock = ["x", "y", "z"]
[[targets]]
tcp = "foot_r"
position = [-0.083, 0.0, 0.0]
lock = ["x", "y", "z", "rx", "ry"]
support = true
[[targets]]
tcp = "foot_l"
position = [0.083, 0.0, 0.0]
lock = ["x", "y", "z", "rx", "ry"]
support = true
"""
# 2 m long, across the front of the body between the shoulder and the hand's way (17 cm in front of the hand)
BAR = """
[[obstacles]]
name = "bar"
kind = "capsule"
a = [-1.0, -0.33, 1.1]
b = [1.0, -0.33, 1.1]
radius = 0.02
"""


# The standard comfort model keeps the trunk upright here; the behaviour model (the default) bends 90 deg at the hips
# and ducks the shoulders under the bar, a way round it that leaves nothing for this test to catch.
STANDARD = """
[comfort]
trunk = 0.0
"""


def scenario(tmp_path: Path, bar: bool, comfort: str = ""):
    path = tmp_path / f"stand_{bar}.toml"
    path.write_text(STAND + comfort + (BAR if bar else ""), encoding="utf-8")
    return load_scenario(path)


def test_the_arm_through_a_bar_is_caught_though_the_hand_is_clear(tmp_path):
    """The hand rises 50 cm in front of a bar: its way is straight (the hand ball keeps its margin), but the arm
    from the shoulder behind the bar to the hand in front must pass through it; the check halves the piece, solves
    the added way points, and still names the arm and the bar."""
    sc = scenario(tmp_path, bar=True, comfort=STANDARD)
    start, goal = np.array([-0.25, -0.5, 0.85]), np.array([-0.25, -0.5, 1.35])
    way = find_way(start, goal, None, sc.problem.obstacle_constraint.obstacles)
    assert way.found and len(way.points) == 2  # the hand alone sees nothing in the way
    followed = follow(sc.problem, "hand_r", way.points, sc.start, sc.options)
    assert not followed.clear and followed.added > 0
    arm = [line for line in followed.problems if "passes through bar between way points 1 and 2" in line]
    assert arm and all(line.split()[0] in ("upper_arm_r", "forearm_r", "hand_r") for line in arm)


def test_without_the_bar_the_body_follows_the_way(tmp_path):
    sc = scenario(tmp_path, bar=False)
    followed = follow(sc.problem, "hand_r", [[-0.25, -0.5, 0.85], [-0.25, -0.5, 1.35]], sc.start, sc.options)
    assert followed.clear and followed.added == 0 and len(followed.results) == 2
    assert all(r.converged for r in followed.results)


def test_a_hand_without_a_target_is_refused(tmp_path):
    sc = scenario(tmp_path, bar=False)
    with pytest.raises(ValueError, match="no target holds 'hand_l'"):
        follow(sc.problem, "hand_l", [[0.0, -0.5, 1.0]], sc.start, sc.options)


def test_with_the_default_comfort_the_body_goes_round_the_bar(tmp_path):
    """The behaviour model ducks the shoulders under the bar: the first piece crosses it, the added way points go
    round, and every posture along the way is held."""
    sc = scenario(tmp_path, bar=True)
    start, goal = np.array([-0.25, -0.5, 0.85]), np.array([-0.25, -0.5, 1.35])
    way = find_way(start, goal, None, sc.problem.obstacle_constraint.obstacles)
    followed = follow(sc.problem, "hand_r", way.points, sc.start, sc.options)
    assert followed.added > 0 and followed.clear and not followed.problems
    assert all(r.converged for r in followed.results)
