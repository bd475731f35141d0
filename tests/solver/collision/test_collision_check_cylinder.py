"""The independent collision check (tests/collision_check.py) knows cylinders: its own measure (a rectangle turned
about the axis, golden-section search along a capsule; the rims as chords against a carried box) against known
distances and against the solver's cylinder, and a solved box lift with a drum between the hands checked through it
from the result file alone."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from collision_check import (
    axis_distance,
    carried_distance,
    frame_problems,
    result_problems,
    scenario_obstacles,
    surface_distance,
)

REPO = Path(__file__).resolve().parents[3]
BOX_LIFT = REPO / "presets" / "scenarios" / "box_lift.toml"
DRUM = dict(kind="cylinder", a=[0.0, 0.0, 0.0], b=[0.0, 0.0, 1.0], radius=0.2)  # upright, from the floor to 1 m


def test_the_check_measures_known_cylinder_distances() -> None:
    """Points beside, above, diagonally off the rim, inside (nearest the side, nearest an end), and capsule axes that
    pass it, dip into it and cross it."""
    points = np.array([[0.5, 0.0, 0.5], [0.1, 0.0, 1.3], [0.0, 0.6, 1.4], [0.0, 0.05, 0.5], [0.0, 0.0, 0.9]])
    want = [0.3, 0.3, math.hypot(0.6 - 0.2, 1.4 - 1.0), -0.15, -0.1]
    np.testing.assert_allclose(axis_distance(DRUM, points, points), want, atol=1e-12)
    np.testing.assert_allclose([surface_distance(DRUM, p) for p in points], np.abs(want), atol=1e-12)
    p0 = np.array([[0.5, -1.0, 0.3], [0.5, -1.0, 1.2], [-1.0, 0.1, 0.5]])
    p1 = np.array([[0.5, 1.0, 0.3], [0.1, 0.0, 0.8], [1.0, 0.1, 0.5]])
    # beside it, 0.3 from the side; into it through the top (deepest at its lower end, 0.2 under the top and 0.1 from
    # the side); across it 0.1 off the axis (deepest where it passes the axis, 0.1 from the side)
    np.testing.assert_allclose(axis_distance(DRUM, p0, p1), [0.3, -0.1, -0.1], atol=1e-9)


def test_the_check_agrees_with_the_solvers_cylinder_on_random_capsules() -> None:
    """Two independent implementations, capsules apart and overlapping (both the depth of the deepest axis point)."""
    from solver.collision.kinds import Cylinder

    rng = np.random.default_rng(11)
    p0, p1 = rng.uniform(-0.6, 0.6, (300, 3)), rng.uniform(-0.6, 0.6, (300, 3))
    p1[:30] = p0[:30]  # points too
    a, b, radius = [0.1, -0.2, -0.3], [-0.1, 0.3, 0.35], 0.18
    mine = axis_distance(dict(kind="cylinder", a=a, b=b, radius=radius), p0, p1) - 0.05
    theirs = Cylinder(a, b, radius).distance(p0, p1, np.full(300, 0.05)).distance
    assert (theirs >= 0).sum() > 50 and (theirs < 0).sum() > 50
    np.testing.assert_allclose(mine, theirs, atol=1e-9)


def test_a_carried_box_is_measured_against_the_rims() -> None:
    """A 1 m wide box over the drum's top: its edges are far out, its bottom face 0.2 m over the top disc, which only
    the rims see; lowered 0.25 m the rim is 0.05 m inside it; beside the drum its edge is nearest."""
    box = dict(kind="box", center=[0.0, 0.0, 1.3], size=[1.0, 1.0, 0.2], rotation_matrix=np.eye(3))
    assert carried_distance(box, DRUM) == pytest.approx(0.2, abs=1e-9)
    assert carried_distance(dict(box, center=[0.0, 0.0, 1.05]), DRUM) == pytest.approx(-0.05, abs=1e-9)
    beside = dict(box, center=[0.8, 0.0, 0.5], size=[0.2, 0.2, 0.2])  # its near face 0.5 m from the side
    assert carried_distance(beside, DRUM) == pytest.approx(0.5, abs=1e-9)


DRUM_TOML = """
[[obstacles]]
name = "drum"
kind = "cylinder"
a = [-0.22, -0.42, 0.45]
b = [0.22, -0.42, 0.45]
radius = 0.12
clearance = 0.01

[[obstacles]]
name = "post"
kind = "cylinder"
a = [0.40, -0.10, 0.0]
b = [0.25, -0.30, 1.3]
radius = 0.05
"""


def test_a_solved_box_lift_keeps_out_of_a_drum_between_the_hands(tmp_path: Path) -> None:
    """The hands' targets 2 cm inside the ends of a lying drum (1 cm clearance) and a post leaning over the left arm:
    the solve ends short of the targets, and the check finds nothing inside the drum's clearance or the post, the
    closest entries agreeing with its own distances."""
    scenario = tmp_path / "drum.toml"
    scenario.write_text(BOX_LIFT.read_text(encoding="utf-8") + DRUM_TOML, encoding="utf-8")
    out = tmp_path / "r.json"
    proc = subprocess.run([sys.executable, "-m", "solver", "solve", "-q", str(scenario), "-o", str(out)], cwd=REPO,
                          capture_output=True, text=True, timeout=300)  # fmt: skip
    assert proc.returncode in (0, 3) and "Traceback" not in proc.stderr, proc.stdout + proc.stderr
    document = json.loads(out.read_text(encoding="utf-8"))
    frame = document["frames"][0]
    assert {"hand_r", "hand_l"} <= set(frame["unmet"]) and frame["broken"] == []
    assert result_problems(document, scenario) == []
    near = {(e["part"], e["other"]) for e in frame["closest"] if e["distance"] < 0.02}  # the check had these to check
    assert {("hand_r", "drum"), ("forearm_l", "post")} <= near, frame["closest"]
    obstacles, floor = scenario_obstacles(scenario)
    assert [ob["kind"] for ob in obstacles] == ["cylinder", "cylinder"]
    spoiled = json.loads(json.dumps(frame))  # the right hand's capsule moved 2 cm along x: about 1 cm into the drum
    for capsule in spoiled["collision_shapes"]:
        if capsule["link"] == "hand_r":
            capsule["start"][0] += 0.02
            capsule["end"][0] += 0.02
    problems = frame_problems(spoiled, obstacles, floor)
    assert len(problems) == 1 and problems[0].startswith("frame 1: hand_r vs drum: -0.0"), problems
