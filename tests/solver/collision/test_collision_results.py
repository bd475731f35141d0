"""No result goes through the floor or an obstacle (issue 20), checked from the result JSON alone by the independent
recomputation of ``collision_check``: every shipped scenario and the obstacle scenarios solved by the command line,
and random reaches around random boxes (hypothesis). The check itself is tested first: against analytic cases,
against ``solver.collision`` on random capsules, and on frames spoiled on purpose."""

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
    capsule_pair,
    carried_obstacle,
    frame_problems,
    is_closed,
    non_finite,
    quaternion_matrix,
    result_problems,
    scenario_obstacles,
    winding,
)
from hypothesis import HealthCheck, assume, event, given, settings
from hypothesis import strategies as st

REPO = Path(__file__).resolve().parents[3]
SCENARIOS = sorted((REPO / "presets" / "scenarios").glob("*.toml"))
BOX_LIFT = REPO / "presets" / "scenarios" / "box_lift.toml"


def solve_cli(scenario: Path, out: Path) -> tuple[int, dict]:
    """Exit code and parsed result of ``python -m solver solve -q scenario -o out``."""
    proc = subprocess.run([sys.executable, "-m", "solver", "solve", "-q", str(scenario), "-o", str(out)], cwd=REPO,
                          capture_output=True, text=True, timeout=300)  # fmt: skip
    assert proc.returncode in (0, 3) and "Traceback" not in proc.stderr, proc.stdout + proc.stderr
    return proc.returncode, json.loads(out.read_text(encoding="utf-8"))


# --------------------------------------------------------------------------------------------- the check itself


def test_the_check_measures_known_distances():
    """Analytic cases: a capsule axis 0.3 m over a box, through it, along a sphere, across a capsule and a plane."""
    box = dict(kind="box", center=[0, 0, 0], size=[1.0, 2.0, 0.4], rotation=[1, 0, 0, 0])
    p0, p1 = np.array([[-2.0, 0.0, 0.5], [-2.0, 0.0, 0.1]]), np.array([[2.0, 0.5, 0.5], [2.0, 0.0, 0.1]])
    np.testing.assert_allclose(axis_distance(box, p0, p1), [0.3, -0.1], atol=1e-12)
    turned = dict(box, size=[1.0, 1.0, 0.4], rotation=[math.cos(math.pi / 8), 0, 0, math.sin(math.pi / 8)])
    point = np.array([[2.0, 0.0, 0.0]])  # a unit square turned 45 degrees about z has a corner at x = sqrt(1/2)
    assert axis_distance(turned, point, point)[0] == pytest.approx(2.0 - math.sqrt(0.5), abs=1e-12)
    sphere = dict(kind="sphere", center=[0.0, 1.0, 0.0], radius=0.25)
    assert axis_distance(sphere, p0[:1] * [1, 0, 0], p1[:1] * [1, 0, 0])[0] == pytest.approx(0.75)
    rail = dict(kind="capsule", a=[0.0, -1.0, 1.0], b=[0.0, 1.0, 1.0], radius=0.1)
    assert axis_distance(rail, p0[:1], p1[:1])[0] == pytest.approx(0.4)
    assert capsule_pair([0, 0, 0], [1, 0, 0], [2, 1, 0], [2, 1, 5]) == pytest.approx(math.sqrt(2))
    wall = dict(kind="plane", point=[0, 0, 0.2], normal=[0, 0, 2.0])
    np.testing.assert_allclose(axis_distance(wall, p0, p1), [0.3, -0.1])


def test_the_check_agrees_with_solver_collision_on_random_capsules():
    """Two independent implementations: every kind, capsules apart and overlapping; a box as a mesh too (which must
    agree with the box where apart, and be negative where an axis enters it)."""
    from solver.collision import Box, Capsule, HalfSpace, Mesh, Sphere, obstacle_distance
    from solver.collision.generate import box_mesh

    rng = np.random.default_rng(5)
    p0, p1 = rng.uniform(-0.8, 0.8, (200, 3)), rng.uniform(-0.8, 0.8, (200, 3))
    q = rng.normal(size=4)
    rotation = quaternion_matrix(q)
    vertices, faces = box_mesh([0.1, 0.0, -0.1], [0.6, 0.3, 0.4], 3, rotation)
    tables = [
        (dict(kind="box", center=[0.1, 0.0, -0.1], size=[0.6, 0.3, 0.4], rotation=q.tolist()),
         Box([0.1, 0.0, -0.1], [0.6, 0.3, 0.4], rotation)),
        (dict(kind="sphere", center=[0.2, 0.1, 0.0], radius=0.3), Sphere([0.2, 0.1, 0.0], 0.3)),
        (dict(kind="capsule", a=[0, 0, 0], b=[0.3, 0.4, 0.5], radius=0.1), Capsule([0, 0, 0], [0.3, 0.4, 0.5], 0.1)),
        (dict(kind="plane", point=[0, 0, 0.1], normal=[0.2, -1.0, 1.0]), HalfSpace([0, 0, 0.1], [0.2, -1.0, 1.0])),
        (dict(kind="mesh", triangles=vertices[faces], closed=is_closed(faces)), Mesh(vertices, faces)),
    ]  # fmt: skip
    assert is_closed(faces) and not is_closed(faces[:-1])
    for table, shape in tables:
        mine = axis_distance(table, p0, p1) - 0.08
        theirs = obstacle_distance(p0, p1, 0.08, shape).distance  # capsules of radius 8 cm
        apart = theirs >= 0.0
        assert apart.sum() > 20 and (~apart).sum() > 20, table["kind"]
        np.testing.assert_allclose(mine[apart], theirs[apart], atol=1e-9, err_msg=table["kind"])
        assert (mine[~apart] <= 1e-12).all(), table["kind"]  # overlapping: negative (or touching) here too
        if table["kind"] in ("sphere", "capsule", "plane"):  # the same measure when overlapping
            np.testing.assert_allclose(mine, theirs, atol=1e-9, err_msg=table["kind"])
    np.testing.assert_allclose(axis_distance(tables[4][0], p0, p1), axis_distance(tables[0][0], p0, p1), atol=0.02)
    centre = np.array([[0.1, 0.0, -0.1], [2.0, 0.0, 0.0]])
    np.testing.assert_allclose(np.abs(winding(centre, vertices[faces])), [1.0, 0.0], atol=1e-9)


def test_the_check_finds_spoiled_frames(tmp_path):
    """A solved frame passes; moved 5 mm into the floor, with a closest distance misreported by 1 mm, with a
    body-part pair overlapping beyond its clearance, or with an obstacle contact left out, it does not."""
    scenario = tmp_path / "s.toml"
    scenario.write_text(BOX_LIFT.read_text(encoding="utf-8") + TABLE, encoding="utf-8")
    _, document = solve_cli(scenario, tmp_path / "r.json")
    obstacles, floor = scenario_obstacles(scenario)
    frame = document["frames"][0]
    assert frame_problems(frame, obstacles, floor) == [] and floor
    lowest = min(min(s["start"][2], s["end"][2]) - s["radius"] for s in frame["collision_shapes"])
    sunk = json.loads(json.dumps(frame))
    for s in sunk["collision_shapes"]:
        s["start"][2] -= lowest + 0.005
        s["end"][2] -= lowest + 0.005
    assert any("vs floor" in p for p in frame_problems(sunk, obstacles, floor))
    misreported = json.loads(json.dumps(frame))
    apart = next(e for e in misreported["closest"] if e["distance"] > 0.0)  # overlaps' distances are not compared
    apart["distance"] += 0.001
    assert any(" distance +0.001" in p for p in frame_problems(misreported, obstacles, floor))
    pair = json.loads(json.dumps(frame))
    pair["closest"].append(dict(pair="hand_r vs thigh_r", part="hand_r", other="thigh_r", distance=0.0, clearance=1.0,
                                point=[0, 0, 0], other_point=[0, 0, 0]))  # fmt: skip
    assert any(p.startswith("frame 1: hand_r vs thigh_r:") and "clearance 1.0" in p
               for p in frame_problems(pair, obstacles, floor))  # fmt: skip
    left_out = json.loads(json.dumps(frame))
    left_out["closest"] = [e for e in frame["closest"] if e["other"] != "table"]
    assert any(p.endswith("not in closest") for p in frame_problems(left_out, obstacles, floor))


CARRIED = """
[carried]
name = "box"
size = [0.35, 0.26, 0.24]
tcps = ["hand_r", "hand_l"]
"""


def _depth(problems: list[str], pair: str) -> float | None:
    """The distance (m) the check reports for ``pair`` ("frame 1: box vs bench: -0.0100 m ..."), None if not reported;
    compared with a tolerance, as the solved box may sit tilted by a rounding's worth on another CPU."""
    for p in problems:
        if p.startswith(f"frame 1: {pair}: "):
            return float(p[len(f"frame 1: {pair}: "):].split()[0])
    return None


def test_the_check_places_the_carried_box_from_the_tcps(tmp_path):
    """The box lift with its box carried: the solved frame passes and lists the box; a forearm moved into the box, the
    box's centre misreported by 2 mm, or the forearms' box entries left out of closest, do not; a holding hand in it
    is allowed."""
    scenario = tmp_path / "s.toml"
    scenario.write_text(BOX_LIFT.read_text(encoding="utf-8") + CARRIED, encoding="utf-8")
    code, document = solve_cli(scenario, tmp_path / "r.json")
    obstacles, floor = scenario_obstacles(scenario)
    frame = document["frames"][0]
    assert code == 0 and frame_problems(frame, obstacles, floor) == []
    assert frame["carried"]["tcps"] == ["hand_r", "hand_l"] and frame["carried"]["clearance"] == 0.0
    assert {e["part"] for e in frame["closest"] if e["other"] == "box"} >= {"forearm_r", "forearm_l"}

    def spoiled(part: str | None = None, shift: float = 0.0, drop: bool = False) -> list[str]:
        bad = json.loads(json.dumps(frame))
        for s in bad["collision_shapes"]:
            if s["link"] == part:  # the capsule's axis through the box's centre
                s["start"], s["end"] = bad["carried"]["center"], np.add(bad["carried"]["center"], 0.01).tolist()
        bad["carried"]["center"][0] += shift
        if drop:
            bad["closest"] = [e for e in bad["closest"] if e["other"] != "box"]
        return frame_problems(bad, obstacles, floor)

    assert any(p.startswith("frame 1: forearm_r vs box:") for p in spoiled("forearm_r"))
    assert any("carried 'box': center off by 0.002" in p for p in spoiled(shift=0.002))
    assert any(p.endswith("not in closest") and "vs box" in p for p in spoiled(drop=True))
    assert spoiled("hand_l") == []

    # the box itself against obstacles it is not in the scenario with: a bench under it, 1 cm into its bottom or 5 mm
    # below it (near, but the file's closest pairs do not list it), the floor raised to its bottom
    entry = frame["carried"]
    bottom = entry["center"][2] - entry["size"][2] / 2.0
    bench = dict(kind="box", name="bench", center=[entry["center"][0], entry["center"][1], bottom - 0.09],
                 size=[0.2, 0.2, 0.2], clearance=0.0)  # fmt: skip
    assert _depth(frame_problems(frame, [bench], floor), "box vs bench") == pytest.approx(-0.0100, abs=5e-4)
    bench["center"][2] -= 0.015
    assert any(p.endswith("not in closest") and "box vs bench" in p for p in frame_problems(frame, [bench], floor))
    raised = dict(kind="plane", name="step", point=[0, 0, bottom + 0.02], normal=[0, 0, 1], clearance=0.0)
    assert any(p.startswith("frame 1: box vs step: -0.02") for p in frame_problems(frame, [raised], False))
    # a triangle in the box's middle plane across its depth: its bottom edge passes through the box's front and back
    # faces 9 cm below the top, both its ends 3 cm outside, its tip 7 cm above the top; none of the box's edges
    # comes within 4 cm of it, no corner of it is inside
    box = carried_obstacle(frame)[0]
    corners = np.array([[0.0, -0.16, 0.03], [0.0, 0.16, 0.03], [0.0, 0.0, 0.19]])  # box coordinates, m
    blade = dict(kind="mesh", name="blade", triangles=(box["center"] + corners @ box["rotation_matrix"].T)[None],
                 closed=False, clearance=0.0)  # fmt: skip
    assert _depth(frame_problems(frame, [blade], floor), "box vs blade") == pytest.approx(-0.0900, abs=5e-4)


# --------------------------------------------------------------------------------------------- solved scenarios

TABLE = """
[[obstacles]]
name = "table"
kind = "box"
center = [0.0, -0.55, 0.3]
size = [0.8, 0.4, 0.6]
clearance = 0.01
"""

SHELF = """
[[obstacles]]
name = "shelf"
kind = "mesh"
file = "shelf.obj"
clearance = 0.005

[[obstacles]]
name = "side"
kind = "box"
center = [-0.5, -0.5, 0.9]
size = [0.03, 0.5, 0.9]
rotation = [0.9848078, 0.0, 0.0, 0.1736482]  # 20 degrees about z

[[obstacles]]
name = "lamp"
kind = "sphere"
center = [0.0, -0.3, 1.72]
radius = 0.1

[[obstacles]]
name = "rail"
kind = "capsule"
a = [-0.6, -0.33, 0.65]
b = [0.6, -0.33, 0.65]
radius = 0.02

[[obstacles]]
name = "wall"
kind = "plane"
point = [0.0, -0.8, 0.0]
normal = [0.0, 1.0, 0.0]
"""


def shelf_scenario(folder: Path) -> Path:
    """Box lift with the right hand's target inside a 2 cm shelf (a 192-triangle mesh file) and the left hand's just
    under it, a tilted side board, a lamp at head height, a rail at the thighs and a wall behind the shelf."""
    from solver.collision import write_obj
    from solver.collision.generate import box_mesh

    write_obj(folder / "shelf.obj", *box_mesh((0.0, -0.55, 1.0), (0.9, 0.4, 0.02), 4))
    text = BOX_LIFT.read_text(encoding="utf-8")
    text = text.replace("position = [-0.20, -0.42, 0.45]", "position = [-0.20, -0.55, 1.0]")
    text = text.replace("position = [0.20, -0.42, 0.45]", "position = [0.20, -0.50, 0.93]")
    (folder / "shelf.toml").write_text(text + SHELF, encoding="utf-8")
    return folder / "shelf.toml"


def clearance_test_scenario(folder: Path) -> Path:
    """The scenario of tests/test_clearance.py: every kind of obstacle, the right hand's target inside the table."""
    from helpers import OBSTACLES_TOML

    from solver.collision import write_obj
    from solver.collision.generate import box_mesh

    write_obj(folder / "cube.obj", *box_mesh((3.0, 3.0, 0.1), (0.2, 0.2, 0.2), 1))
    text = BOX_LIFT.read_text(encoding="utf-8").replace(
        "position = [-0.20, -0.42, 0.45]", "position = [-0.20, -0.55, 0.6]"
    )
    (folder / "s.toml").write_text(text + OBSTACLES_TOML, encoding="utf-8")
    return folder / "s.toml"


@pytest.mark.parametrize(
    "scenario",
    [pytest.param(p, marks=pytest.mark.slow) if p.stem == "box_lift_motion" else p for p in SCENARIOS],  # 60 frames
    ids=[p.stem for p in SCENARIOS],
)
def test_shipped_scenarios_stay_out_of_the_floor_and_the_obstacles(scenario: Path, tmp_path):
    """Every frame of every preset scenario, recomputed from its result JSON (motions whole: 1 s each)."""
    _, document = solve_cli(scenario, tmp_path / "r.json")
    assert document["frames"] and all(f["collision_shapes"] for f in document["frames"])
    assert result_problems(document, scenario) == []


@pytest.mark.parametrize("make", [shelf_scenario, clearance_test_scenario], ids=["shelf", "every_kind"])
def test_obstacle_scenarios_stay_out_of_the_obstacles(make, tmp_path):
    """Hand targets inside obstacles end outside them, at their clearances, with the feet and balance held; every
    obstacle near a body part is among the frame's closest pairs with the recomputed distance and points."""
    scenario = make(tmp_path)
    code, document = solve_cli(scenario, tmp_path / "r.json")
    frame = document["frames"][0]
    assert code == 3 and "hand_r" in frame["unmet"] and frame["broken"] == []
    assert result_problems(document, scenario) == []
    obstacles, _ = scenario_obstacles(scenario)
    near = {e["other"] for e in frame["closest"] if e["part"].startswith(("hand_r", "forearm_r"))}
    assert near & {ob["name"] for ob in obstacles}, frame["closest"]  # the check had something to check


# --------------------------------------------------------------------------------------------- random boxes


@pytest.fixture(scope="module")
def male50():
    from solver.io.scenario.bodies import load_body

    return load_body(preset="male_50")


def coordinates(lo: float, hi: float):
    return st.floats(lo, hi, allow_nan=False, allow_infinity=False)


@pytest.mark.slow
@settings(max_examples=25, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])  # fmt: skip
@given(
    center=st.tuples(coordinates(-0.5, 0.5), coordinates(-0.9, -0.3), coordinates(0.1, 1.5)),
    size=st.tuples(coordinates(0.05, 0.5), coordinates(0.05, 0.5), coordinates(0.05, 0.5)),
    yaw=coordinates(-1.5, 1.5),
    offset=st.tuples(coordinates(-0.4, 0.4), coordinates(-0.4, 0.4), coordinates(-0.4, 0.4)),
    hand=st.sampled_from(["hand_r", "hand_l"]),
)
def test_random_reaches_around_random_boxes(male50, center, size, yaw, offset, hand):
    """A box near the manikin (clear of it at rest), a hand target around or inside it, the feet sliding on the
    floor: no NaN in the result JSON, priority 1 held, nothing in the box or the floor by more than 1 mm."""
    from solver import solve
    from solver.collision import Box
    from solver.collision.body import capsules_of
    from solver.io.result.document import result_document
    from solver.problem.problem import Problem, ProblemSpec, Target

    table = dict(kind="box", name="box", center=list(center), size=list(size), clearance=0.0,
                 rotation=[math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2)])  # fmt: skip
    rest = male50.forward(male50.zero_pose())
    capsules = capsules_of(male50)
    assume((axis_distance(table, *capsules.world(rest)) - capsules.radius).min() > 0.02)
    targets = [Target(f, rest.tcp_frame(male50.tcp(f))[1], lock=("z", "rx", "ry"), support=True)
               for f in ("foot_r", "foot_l")]  # fmt: skip
    targets.append(Target(hand, np.add(center, offset), lock=("x", "y", "z")))
    box = Box(center, size, quaternion_matrix(table["rotation"]), name="box")
    result = solve(Problem(male50, ProblemSpec(targets, obstacles=[box])))
    document = json.loads(json.dumps(result_document([(1, result)])))
    assert non_finite(document) == [] and np.isfinite(result.theta).all()
    frame = document["frames"][0]
    assert result.broken == [] and frame["broken"] == [], (result.broken, result.notes)
    assert frame_problems(frame, [table], floor=True) == []
    touching = any(e["other"] == "box" and e["distance"] < 0.005 for e in frame["closest"])
    event(f"converged: {result.converged}, touching the box: {touching}")  # --hypothesis-show-statistics
